#include "occlusion_env/common/errors.hpp"

#include <cstdio>

namespace occlusion_env {

std::string quoted(const std::string& text, std::size_t max_chars) {
  const bool cut = text.size() > max_chars;
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < max_chars; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\0') {
      out += "\\0";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c < 0x20 || c == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
      out += escaped;
    } else {
      out += static_cast<char>(c);
    }
  }
  out += cut ? "...'" : "'";
  if (cut) out += " (" + std::to_string(text.size()) + " chars)";
  return out;
}

}  // namespace occlusion_env
