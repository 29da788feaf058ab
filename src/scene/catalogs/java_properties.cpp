#include "java_properties.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace detail {
namespace {

void appendUtf8(std::string& out, std::uint32_t code_point) {
  if (code_point < 0x80) {
    out += static_cast<char>(code_point);
  } else if (code_point < 0x800) {
    out += static_cast<char>(0xC0 | (code_point >> 6));
    out += static_cast<char>(0x80 | (code_point & 0x3F));
  } else if (code_point < 0x10000) {
    out += static_cast<char>(0xE0 | (code_point >> 12));
    out += static_cast<char>(0x80 | ((code_point >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code_point & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (code_point >> 18));
    out += static_cast<char>(0x80 | ((code_point >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code_point >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code_point & 0x3F));
  }
}

// Strict UTF-8: no overlong forms, no surrogates, nothing above U+10FFFF.
bool isValidUtf8(std::string_view text) {
  constexpr std::uint32_t kSmallest[] = {0, 0x80, 0x800, 0x10000};  // by continuation bytes
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const int extra = byte < 0x80           ? 0
                      : (byte >> 5) == 0x6  ? 1
                      : (byte >> 4) == 0xE  ? 2
                      : (byte >> 3) == 0x1E ? 3
                                            : -1;
    if (extra < 0 || i + extra >= text.size()) return false;
    std::uint32_t code_point = extra == 0 ? byte : byte & (0x3F >> extra);
    for (int k = 1; k <= extra; ++k) {
      const auto continuation = static_cast<unsigned char>(text[i + k]);
      if ((continuation & 0xC0) != 0x80) return false;
      code_point = (code_point << 6) | (continuation & 0x3F);
    }
    if (code_point < kSmallest[extra] || code_point > 0x10FFFF ||
        (code_point >= 0xD800 && code_point < 0xE000)) {
      return false;
    }
    i += 1 + extra;
  }
  return true;
}

std::string latin1ToUtf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) appendUtf8(out, static_cast<unsigned char>(c));
  return out;
}

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\f';
}

// Splits `text` into logical lines: joins continuations (an odd number of trailing backslashes)
// after dropping the leading blanks of the next line; skips blank and comment lines. Each result
// keeps the 1-based number of the line it starts on.
std::vector<std::pair<std::string, int>> logicalLines(std::string_view text) {
  std::vector<std::pair<std::string, int>> lines;
  std::string current;
  int line_number = 0, start_line = 0;
  bool continuing = false;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view natural = text.substr(pos, end - pos);
    pos = end;
    if (pos < text.size() && text[pos] == '\r') ++pos;
    if (pos < text.size() && text[pos] == '\n') ++pos;  // "\n" alone or the end of "\r\n"
    ++line_number;

    std::size_t first = 0;
    while (first < natural.size() && isBlank(natural[first])) ++first;
    natural.remove_prefix(first);
    if (!continuing) {
      if (natural.empty() || natural[0] == '#' || natural[0] == '!') continue;
      start_line = line_number;
    }
    std::size_t backslashes = 0;
    while (backslashes < natural.size() && natural[natural.size() - 1 - backslashes] == '\\')
      ++backslashes;
    continuing = backslashes % 2 == 1;
    if (continuing) natural.remove_suffix(1);
    current.append(natural);
    if (!continuing) lines.emplace_back(std::move(current), start_line), current.clear();
  }
  if (continuing) lines.emplace_back(std::move(current), start_line);
  return lines;
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Resolves the escapes of `raw` (one key or value). \uXXXX escapes are UTF-16 code units: a
// high surrogate followed by a low one makes one code point; an unpaired surrogate becomes
// U+FFFD, the replacement character, so the result is always valid UTF-8.
std::string unescape(std::string_view raw, int line_number) {
  constexpr std::uint32_t kReplacementCharacter = 0xFFFD;
  std::string out;
  out.reserve(raw.size());
  std::uint32_t pending_high_surrogate = 0;
  const auto flushPendingSurrogate = [&] {
    if (pending_high_surrogate != 0) appendUtf8(out, kReplacementCharacter);
    pending_high_surrogate = 0;
  };
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != '\\' || i + 1 == raw.size()) {
      flushPendingSurrogate();
      out += raw[i];
      continue;
    }
    const char c = raw[++i];
    if (c != 'u') {
      flushPendingSurrogate();
      out += c == 't' ? '\t' : c == 'n' ? '\n' : c == 'r' ? '\r' : c == 'f' ? '\f' : c;
      continue;
    }
    std::uint32_t unit = 0;
    for (int k = 1; k <= 4; ++k) {
      const int digit = i + k < raw.size() ? hexValue(raw[i + k]) : -1;
      if (digit < 0)
        throw CatalogError("line " + std::to_string(line_number) + ": malformed \\uXXXX escape");
      unit = unit * 16 + static_cast<std::uint32_t>(digit);
    }
    i += 4;
    if (unit >= 0xD800 && unit < 0xDC00) {  // high surrogate: wait for the low one
      flushPendingSurrogate();
      pending_high_surrogate = unit;
    } else if (unit >= 0xDC00 && unit < 0xE000) {  // low surrogate: completes a pair, or stray
      appendUtf8(out, pending_high_surrogate != 0
                          ? 0x10000 + ((pending_high_surrogate - 0xD800) << 10) + (unit - 0xDC00)
                          : kReplacementCharacter);
      pending_high_surrogate = 0;
    } else {
      flushPendingSurrogate();
      appendUtf8(out, unit);
    }
  }
  flushPendingSurrogate();
  return out;
}

}  // namespace

std::map<std::string, std::string> parseJavaProperties(std::string_view text) {
  std::string utf8;
  if (!isValidUtf8(text)) {
    utf8 = latin1ToUtf8(text);
    text = utf8;
  }
  std::map<std::string, std::string> properties;
  for (const auto& [line, line_number] : logicalLines(text)) {
    // The key ends at the first unescaped '=', ':' or blank.
    std::size_t key_end = 0;
    while (key_end < line.size()) {
      const char c = line[key_end];
      if (c == '\\') {
        key_end += 2;
        continue;
      }
      if (c == '=' || c == ':' || isBlank(c)) break;
      ++key_end;
    }
    key_end = std::min(key_end, line.size());
    std::size_t value_start = key_end;
    while (value_start < line.size() && isBlank(line[value_start])) ++value_start;
    if (value_start < line.size() && (line[value_start] == '=' || line[value_start] == ':'))
      ++value_start;
    while (value_start < line.size() && isBlank(line[value_start])) ++value_start;
    properties[unescape(std::string_view(line).substr(0, key_end), line_number)] =
        unescape(std::string_view(line).substr(value_start), line_number);
  }
  return properties;
}

}  // namespace detail
}  // namespace occlusion_env
