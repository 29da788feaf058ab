#include "occlusion_env/tools/cli_options.hpp"

#include <iostream>

namespace occlusion_env::tools {
namespace {

nlohmann::json parseScalar(const std::string& flag, OptionKind kind, const std::string& text) {
  constexpr double kHuge = 1.7e308;
  switch (kind) {
    case OptionKind::kBool:
      if (text.empty() || text == "true" || text == "1") return true;
      if (text == "false" || text == "0") return false;
      throw ArgumentError(flag + " expects true or false, got " + quoted(text));
    case OptionKind::kInteger:
      if (!text.empty() && text[0] == '-') {
        return parseInteger(flag, text, std::numeric_limits<long long>::min(),
                            std::numeric_limits<long long>::max());
      }
      return parseUnsigned(flag, text);
    case OptionKind::kNumber:
      return parseNumber(flag, text, -kHuge, kHuge);
    default:
      return text;
  }
}

}  // namespace

nlohmann::json parseOptionText(const std::string& flag, OptionKind kind, const std::string& text) {
  OptionKind item = kind;
  if (kind == OptionKind::kStringList) item = OptionKind::kString;
  if (kind == OptionKind::kIntegerList) item = OptionKind::kInteger;
  if (kind == OptionKind::kNumberList) item = OptionKind::kNumber;
  if (item == kind) return parseScalar(flag, kind, text);
  nlohmann::json list = nlohmann::json::array();
  for (const std::string& part : splitList(flag, text))
    list.push_back(parseScalar(flag, item, part));
  return list;
}

std::string helpText(const OptionSpec& spec, const nlohmann::json& default_value) {
  std::string help = spec.help();
  const std::string allowed = spec.allowedText();
  if (!allowed.empty()) help += "; " + allowed;
  if (!spec.unit().empty()) help += " [" + spec.unit() + "]";
  // An unset optional, an empty text or list: the help says what happens then.
  if (default_value.is_null() ||
      (default_value.is_string() && default_value.get_ref<const std::string&>().empty()) ||
      (default_value.is_array() && default_value.empty())) {
    return help;
  }
  return help + " (default " + displayValue(default_value) + ")";
}

int parseCommandLine(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& error) {
    std::cerr << app.get_name() << ": " << error.what() << "\n(--help lists the options)\n";
    return 2;
  }
  return -1;
}

int parseAndRun(CLI::App& app, int argc, const char* const* argv, const std::function<int()>& run) {
  if (const int exit_code = parseCommandLine(app, argc, argv); exit_code >= 0) return exit_code;
  try {
    return run();
  } catch (const std::exception& error) {
    std::cerr << "\n" << app.get_name() << ": " << error.what() << "\n";
    return 1;
  }
}

}  // namespace occlusion_env::tools
