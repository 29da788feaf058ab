// The command line of the tools, made from option tables (common/option_table.hpp) with CLI11:
// every declared option becomes a flag whose --help line shows its meaning, unit, allowed values
// and default, and whose value is checked as the table says. A tool's main:
//
//   CLI::App app("Renders the start view of one seeded scene.", "occlusion_render");
//   addOptionFlags(app, environmentOptionTable(), args.environment, {"seed", "preset", ...});
//   app.add_option("--out", args.out_dir, "output folder");   // a tool's own flags
//   if (const int exit_code = parseCommandLine(app, argc, argv); exit_code >= 0) return exit_code;
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <string>
#include <vector>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace occlusion_env::tools {

/// Command-line text for an option of `kind` as JSON: strict integers and finite numbers,
/// true/false (an empty text, the flag alone, is true), comma-separated lists. Throws
/// ArgumentError naming `flag`.
nlohmann::json parseOptionText(const std::string& flag, OptionKind kind, const std::string& text);

/// The --help line of an option: meaning, allowed values, unit and default.
std::string helpText(const OptionSpec& spec, const nlohmann::json& default_value);

/// Parses argv into the flags `app` holds. Returns -1 to go on, 0 after printing --help, and 2
/// after printing "<tool>: <what is wrong>" for a malformed command line (exit codes of every
/// tool: 0 done, 1 failed, 2 bad command line).
int parseCommandLine(CLI::App& app, int argc, const char* const* argv);

/// Adds a flag for every field of `table` that has one (or for those named in `keys`, in that
/// order). Each flag stores into `options` as it is parsed; help texts show the defaults that
/// `options` holds when this is called.
template <class Options>
void addOptionFlags(CLI::App& app, const OptionTable<Options>& table, Options& options,
                    const std::vector<std::string>& keys = {}) {
  std::vector<const OptionField<Options>*> fields;
  if (keys.empty()) {
    for (const OptionField<Options>& field : table.fields()) fields.push_back(&field);
  } else {
    for (const std::string& key : keys) {
      const OptionField<Options>* field = table.find(key);
      if (field == nullptr) throw std::logic_error("no option " + key + " in the table");
      fields.push_back(field);
    }
  }
  for (const OptionField<Options>* field : fields) {
    const std::string flag = field->flagName();
    if (flag.empty()) continue;
    const std::string help = helpText(field->spec, field->get(options));
    const bool list = field->kind == OptionKind::kStringList ||
                      field->kind == OptionKind::kIntegerList ||
                      field->kind == OptionKind::kNumberList;
    const std::string& key = field->key;
    if (list && field->spec.isRepeatable()) {
      // One item per occurrence, appended to what the list held before the command line.
      auto store = [&table, &options, key, flag](const std::vector<std::string>& items) {
        nlohmann::json list = table.find(key)->get(options);
        for (const std::string& item : items) {
          for (const nlohmann::json& value : parseOptionText(flag, table.find(key)->kind, item)) {
            list.push_back(value);
          }
        }
        try {
          table.set(options, key, list);
        } catch (const InvalidArgumentError& error) {
          throw CLI::ValidationError(flag, error.what());
        }
      };
      app.add_option_function<std::vector<std::string>>(flag, store, help)
          ->allow_extra_args(false)
          ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
          ->type_name("TEXT");
      continue;
    }
    auto store = [&table, &options, key, flag](const std::string& text) {
      try {
        table.set(options, key, parseOptionText(flag, table.find(key)->kind, text));
      } catch (const ArgumentError& error) {
        throw CLI::ValidationError(flag, error.what());
      } catch (const InvalidArgumentError& error) {
        throw CLI::ValidationError(flag, error.what());
      }
    };
    CLI::Option* option = app.add_option_function<std::string>(flag, store, help);
    if (field->kind == OptionKind::kBool) option->expected(0, 1)->type_name("[BOOL]");
    if (field->kind == OptionKind::kInteger) option->type_name("INT");
    if (field->kind == OptionKind::kNumber) option->type_name("NUM");
    if (list) option->type_name("A,B,...");
  }
}

}  // namespace occlusion_env::tools
