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
#include <functional>
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

/// A tool's whole main after its flags are declared: parses argv (exit code 0 or 2 as
/// parseCommandLine), then returns `run()`; an exception from it is printed as
/// "<tool>: <what>" and gives exit code 1.
int parseAndRun(CLI::App& app, int argc, const char* const* argv, const std::function<int()>& run);

namespace cli_detail {

inline bool isList(OptionKind kind) {
  return kind == OptionKind::kStringList || kind == OptionKind::kIntegerList ||
         kind == OptionKind::kNumberList;
}

/// The fields named by `keys` in that order, or every field when `keys` is empty.
template <class Options>
std::vector<const OptionField<Options>*> selectFields(const OptionTable<Options>& table,
                                                      const std::vector<std::string>& keys) {
  std::vector<const OptionField<Options>*> fields;
  if (keys.empty()) {
    for (const OptionField<Options>& field : table.fields()) fields.push_back(&field);
  }
  for (const std::string& key : keys) {
    const OptionField<Options>* field = table.find(key);
    if (field == nullptr) throw std::logic_error("no option " + key + " in the table");
    fields.push_back(field);
  }
  return fields;
}

/// Checks and stores `value` as the table says; a bad value becomes CLI11's validation error.
template <class Options>
void store(const OptionTable<Options>& table, Options& options, const std::string& key,
           const std::string& flag, const nlohmann::json& value) {
  try {
    table.set(options, key, value);
  } catch (const InvalidArgumentError& error) {
    throw CLI::ValidationError(flag, error.what());
  }
}

/// A repeatable list flag: one item per occurrence; the items replace the default list.
template <class Options>
void addRepeatableFlag(CLI::App& app, const OptionTable<Options>& table, Options& options,
                       const OptionField<Options>& field, const std::string& help) {
  const std::string key = field.key, flag = field.flagName();
  const OptionKind kind = field.kind;
  auto collect = [&table, &options, key, flag, kind](const std::vector<std::string>& items) {
    nlohmann::json list = nlohmann::json::array();
    try {
      for (const std::string& item : items) {
        for (const nlohmann::json& value : parseOptionText(flag, kind, item)) list.push_back(value);
      }
    } catch (const ArgumentError& error) {
      throw CLI::ValidationError(flag, error.what());
    }
    store(table, options, key, flag, list);
  };
  app.add_option_function<std::vector<std::string>>(flag, collect, help)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->type_name("TEXT");
}

/// A flag taking one value (a bool's value is optional: the flag alone means true).
template <class Options>
void addValueFlag(CLI::App& app, const OptionTable<Options>& table, Options& options,
                  const OptionField<Options>& field, const std::string& help) {
  const std::string key = field.key, flag = field.flagName();
  const OptionKind kind = field.kind;
  auto parse = [&table, &options, key, flag, kind](const std::string& text) {
    nlohmann::json value;
    try {
      value = parseOptionText(flag, kind, text);
    } catch (const ArgumentError& error) {
      throw CLI::ValidationError(flag, error.what());
    }
    store(table, options, key, flag, value);
  };
  CLI::Option* option = app.add_option_function<std::string>(flag, parse, help);
  if (kind == OptionKind::kBool) option->expected(0, 1)->type_name("[BOOL]");
  if (kind == OptionKind::kInteger) option->type_name("INT");
  if (kind == OptionKind::kNumber) option->type_name("NUM");
  if (isList(kind)) option->type_name("A,B,...");
}

}  // namespace cli_detail

/// Adds a flag for every field of `table` that has one (or for those named in `keys`, in that
/// order). Each flag stores into `options` as it is parsed; help texts show the defaults that
/// `options` holds when this is called.
template <class Options>
void addOptionFlags(CLI::App& app, const OptionTable<Options>& table, Options& options,
                    const std::vector<std::string>& keys = {}) {
  for (const OptionField<Options>* field : cli_detail::selectFields(table, keys)) {
    const std::string flag = field->flagName();
    if (flag.empty()) continue;
    const std::string help = helpText(field->spec, field->get(options));
    if (field->spec.isNegated()) {
      const std::string key = field->key;
      app.add_flag_callback(
          flag,
          [&table, &options, key, flag] { cli_detail::store(table, options, key, flag, false); },
          "turns off: " + help);
    } else if (cli_detail::isList(field->kind) && field->spec.isRepeatable()) {
      cli_detail::addRepeatableFlag(app, table, options, *field, help);
    } else {
      cli_detail::addValueFlag(app, table, options, *field, help);
    }
  }
}

}  // namespace occlusion_env::tools
