// libFuzzer target: the Java .properties parser of the Sweet Home 3D catalogue on arbitrary
// bytes. It may throw CatalogError (a malformed \uXXXX escape) and nothing else, must not crash
// or trip the sanitizers, and every key and value must come back as valid UTF-8.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "../../src/scene/catalogs/java_properties.hpp"
#include "occlusion_env/common/errors.hpp"

namespace {

// Strict UTF-8: no overlong forms, no surrogates, nothing above U+10FFFF.
bool isValidUtf8(const std::string& text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    int length = 0;
    std::uint32_t code_point = 0;
    if (byte < 0x80) {
      ++i;
      continue;
    } else if ((byte & 0xE0) == 0xC0) {
      length = 2;
      code_point = byte & 0x1F;
    } else if ((byte & 0xF0) == 0xE0) {
      length = 3;
      code_point = byte & 0x0F;
    } else if ((byte & 0xF8) == 0xF0) {
      length = 4;
      code_point = byte & 0x07;
    } else {
      return false;
    }
    if (i + length > text.size()) return false;
    for (int k = 1; k < length; ++k) {
      const auto continuation = static_cast<unsigned char>(text[i + k]);
      if ((continuation & 0xC0) != 0x80) return false;
      code_point = (code_point << 6) | (continuation & 0x3F);
    }
    const std::uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code_point < smallest[length] || code_point > 0x10FFFF ||
        (code_point >= 0xD800 && code_point <= 0xDFFF)) {
      return false;
    }
    i += length;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto properties = occlusion_env::detail::parseJavaProperties(
        std::string_view(reinterpret_cast<const char*>(data), size));
    for (const auto& [key, value] : properties) {
      if (!isValidUtf8(key) || !isValidUtf8(value)) __builtin_trap();
    }
  } catch (const occlusion_env::CatalogError&) {
    // The one documented failure.
  }
  return 0;
}
