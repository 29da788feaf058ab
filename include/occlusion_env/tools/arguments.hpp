// The strict parsing of command-line values behind the tools' flags (tools/cli_options.hpp):
// every tool rejects "--seed 1.5" or "--size 64px" the same way, naming the flag.
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

}  // namespace occlusion_env::tools
