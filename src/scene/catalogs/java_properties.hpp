// Parser of Java .properties text (private to the core library; used by the Sweet Home 3D
// catalogue).
#pragma once

#include <map>
#include <string>
#include <string_view>

namespace occlusion_env {
namespace detail {

/// Parses `text` as java.util.Properties does: '#'/'!' comment lines, "key=value", "key:value" or
/// "key value", backslash line continuations and the escapes \t \n \r \f \uXXXX (others drop the
/// backslash). Bytes that are not valid UTF-8 are read as ISO-8859-1 (like Java 9's resource
/// bundles); keys and values come back as UTF-8. A later key replaces an earlier one. Throws
/// CatalogError for a malformed \uXXXX escape (the message gives the line number).
std::map<std::string, std::string> parseJavaProperties(std::string_view text);

}  // namespace detail
}  // namespace occlusion_env
