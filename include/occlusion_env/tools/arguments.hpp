// Command-line flags of the tools (occlusion_render, occlusion_eval, ...): one strict reader, so
// that every tool rejects "--seed 1.5" or "--size 64px" the same way, naming the flag.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace occlusion_env::tools {

/// A malformed command line; the message names the flag and what it expected.
class ArgumentError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// `text` as an integer in [minimum, maximum]: digits only (a leading sign allowed), no fraction,
/// no trailing characters. Throws ArgumentError naming `flag`.
long long parseInteger(const std::string& flag, const std::string& text, long long minimum,
                       long long maximum);

/// `text` as an unsigned 64-bit integer (seeds). Throws ArgumentError naming `flag`.
std::uint64_t parseUnsigned(const std::string& flag, const std::string& text);

/// `text` as a finite number in [minimum, maximum]. Throws ArgumentError naming `flag`.
double parseNumber(const std::string& flag, const std::string& text, double minimum,
                   double maximum);

/// Comma-separated items; empty items are refused. Throws ArgumentError naming `flag`.
std::vector<std::string> splitList(const std::string& flag, const std::string& text);

/// Walks argv flag by flag:
///   ArgumentReader args(argc, argv);
///   while (args.next()) {
///     if (args.flag() == "--size") size = args.integer(64, 1024);
///     else if (args.flag() == "--check") check = true;
///     else args.unknown();
///   }
class ArgumentReader {
 public:
  ArgumentReader(int argc, const char* const* argv);

  /// Moves to the next argument; false when none is left.
  bool next();
  /// The current argument (a flag such as "--seed").
  const std::string& flag() const { return flag_; }

  /// The current flag's value: the argument after it, which is consumed.
  std::string text();
  long long integer(long long minimum, long long maximum);
  std::uint64_t unsignedInteger();
  double number(double minimum, double maximum);
  std::vector<std::string> list();
  std::vector<double> numbers(double minimum, double maximum);

  /// Throws ArgumentError("unknown option ...").
  [[noreturn]] void unknown() const;

 private:
  std::vector<std::string> arguments_;
  std::size_t index_ = 0;  // of the next argument to read
  std::string flag_;
};

}  // namespace occlusion_env::tools
