#include "occlusion_env/tools/arguments.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "occlusion_env/common/errors.hpp"  // quoted()

namespace occlusion_env::tools {
namespace {

bool isInteger(const std::string& text, bool allow_sign) {
  std::size_t first = 0;
  if (allow_sign && !text.empty() && (text[0] == '-' || text[0] == '+')) first = 1;
  if (first == text.size()) return false;
  for (std::size_t i = first; i < text.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i]))) return false;
  }
  return true;
}

}  // namespace

long long parseInteger(const std::string& flag, const std::string& text, long long minimum,
                       long long maximum) {
  const std::string expected = flag + " expects an integer in [" + std::to_string(minimum) + ", " +
                               std::to_string(maximum) + "], got " + quoted(text);
  if (!isInteger(text, true)) throw ArgumentError(expected);
  errno = 0;
  const long long value = std::strtoll(text.c_str(), nullptr, 10);
  if (errno == ERANGE || value < minimum || value > maximum) throw ArgumentError(expected);
  return value;
}

std::uint64_t parseUnsigned(const std::string& flag, const std::string& text) {
  const std::string expected = flag + " expects an integer in [0, 2^64), got " + quoted(text);
  if (!isInteger(text, false)) throw ArgumentError(expected);
  errno = 0;
  const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) throw ArgumentError(expected);
  return value;
}

double parseNumber(const std::string& flag, const std::string& text, double minimum,
                   double maximum) {
  std::ostringstream expected;
  expected << flag << " expects a number in [" << minimum << ", " << maximum << "], got "
           << quoted(text);
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) {
    throw ArgumentError(expected.str());
  }
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value) || value < minimum ||
      value > maximum) {
    throw ArgumentError(expected.str());
  }
  return value;
}

std::vector<std::string> splitList(const std::string& flag, const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    if (item.empty()) {
      throw ArgumentError(flag + " expects comma-separated items, got " + quoted(text));
    }
    items.push_back(item);
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

}  // namespace occlusion_env::tools
