#include "occlusion_env/common/option_table.hpp"

#include <algorithm>
#include <sstream>

namespace occlusion_env {
namespace {

std::string number(double value) {
  std::ostringstream text;
  text.precision(12);
  text << value;
  return text.str();
}

bool isInteger(const nlohmann::json& value) {
  if (value.is_number_integer()) return true;
  // 2.0 written for an integer is accepted (YAML and XML-RPC turn large integers into doubles).
  if (!value.is_number_float()) return false;
  const double x = value.get<double>();
  return std::isfinite(x) && std::trunc(x) == x && std::abs(x) < 9.0e15;
}

bool hasKind(OptionKind kind, const nlohmann::json& value) {
  switch (kind) {
    case OptionKind::kBool:
      return value.is_boolean();
    case OptionKind::kInteger:
      return isInteger(value);
    case OptionKind::kNumber:
      return value.is_number() && std::isfinite(value.get<double>());
    case OptionKind::kString:
      return value.is_string();
    case OptionKind::kStringList:
    case OptionKind::kIntegerList:
    case OptionKind::kNumberList:
      return value.is_array();
  }
  return false;
}

OptionKind itemKind(OptionKind kind) {
  switch (kind) {
    case OptionKind::kStringList:
      return OptionKind::kString;
    case OptionKind::kIntegerList:
      return OptionKind::kInteger;
    case OptionKind::kNumberList:
      return OptionKind::kNumber;
    default:
      return kind;
  }
}

bool isList(OptionKind kind) {
  return itemKind(kind) != kind;
}

/// Checks one scalar against the range or choices; `what` names it in the message.
void checkScalar(const std::string& what, OptionKind kind, const OptionSpec& spec,
                 const nlohmann::json& value) {
  if (!hasKind(kind, value)) {
    throw InvalidArgumentError(what + " must be " + describe(kind) + ", got " + value.dump());
  }
  if (kind == OptionKind::kInteger || kind == OptionKind::kNumber) {
    const double x = value.get<double>();
    const bool too_small =
        spec.minimum() && (spec.openMinimum() ? !(x > *spec.minimum()) : !(x >= *spec.minimum()));
    const bool too_large =
        spec.maximum() && (spec.openMaximum() ? !(x < *spec.maximum()) : !(x <= *spec.maximum()));
    if (too_small || too_large) {
      const std::string unit = spec.unit().empty() ? "" : " [" + spec.unit() + "]";
      throw InvalidArgumentError(what + " must be in " + spec.allowedText() + unit + ", got " +
                                 displayValue(value));
    }
  }
  if (kind == OptionKind::kString && !spec.choices().empty()) {
    const std::string text = value.get<std::string>();
    if (std::find(spec.choices().begin(), spec.choices().end(), text) == spec.choices().end()) {
      throw InvalidArgumentError(what + " must be " + spec.allowedText() + ", got " + quoted(text));
    }
  }
}

}  // namespace

const char* describe(OptionKind kind) {
  switch (kind) {
    case OptionKind::kBool:
      return "true or false";
    case OptionKind::kInteger:
      return "an integer";
    case OptionKind::kNumber:
      return "a finite number";
    case OptionKind::kString:
      return "a string";
    case OptionKind::kStringList:
      return "a list of strings";
    case OptionKind::kIntegerList:
      return "a list of integers";
    case OptionKind::kNumberList:
      return "a list of numbers";
  }
  return "a value";
}

std::string OptionSpec::allowedText() const {
  if (!choices_.empty()) {
    std::string text;
    for (const std::string& choice : choices_) text += (text.empty() ? "" : " | ") + choice;
    return text;
  }
  if (minimum_ && maximum_) {
    return std::string(open_minimum_ ? "(" : "[") + number(*minimum_) + ", " + number(*maximum_) +
           (open_maximum_ ? ")" : "]");
  }
  if (minimum_) return (open_minimum_ ? "> " : ">= ") + number(*minimum_);
  if (maximum_) return (open_maximum_ ? "< " : "<= ") + number(*maximum_);
  return "";
}

namespace option_detail {

void checkValue(const std::string& key, OptionKind kind, const OptionSpec& spec,
                const nlohmann::json& value) {
  if (value.is_null()) return;  // an unset std::optional
  if (!isList(kind)) {
    checkScalar(key, kind, spec, value);
    return;
  }
  if (!value.is_array()) {
    throw InvalidArgumentError(key + " must be " + describe(kind) + ", got " + value.dump());
  }
  for (const nlohmann::json& item : value) {
    checkScalar(key + " (each item)", itemKind(kind), spec, item);
  }
}

}  // namespace option_detail

std::string displayValue(const nlohmann::json& value) {
  if (value.is_null()) return "unset";
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) return number(value.get<double>());
  if (value.is_array()) {
    std::string text = "[";
    for (const nlohmann::json& item : value) {
      text += (text.size() > 1 ? ", " : "") + displayValue(item);
    }
    return text + "]";
  }
  return value.dump();
}

std::string markdownTable(const std::vector<std::string>& keys,
                          const std::vector<nlohmann::json>& defaults,
                          const std::vector<const OptionSpec*>& specs) {
  std::ostringstream table;
  table << "| name | default | allowed | unit | meaning |\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < keys.size(); ++i) {
    std::string allowed = specs[i]->allowedText();
    std::replace(allowed.begin(), allowed.end(), '|', '/');  // a '|' would end the cell
    table << "| `" << keys[i] << "` | " << displayValue(defaults[i]) << " | " << allowed << " | "
          << specs[i]->unit() << " | " << specs[i]->help() << " |\n";
  }
  return table.str();
}

}  // namespace occlusion_env
