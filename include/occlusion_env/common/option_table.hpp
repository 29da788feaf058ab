// Options declared once. An OptionTable lists the fields of one options struct (name, where the
// value lives, range or choices, unit, help); the command line (tools/cli_options.hpp), the ROS
// parameter reader (ros/parameters.hpp), JSON in and out, range checks and the docs' tables all
// come from it, so a default, a range or a name is written in one place only.
//
//   const OptionTable<EnvironmentOptions>& table = environmentOptionTable();
//   table.applyJson({{"radius", 2.0}}, options);   // refuses unknown names and bad values
//   nlohmann::json json = table.toJson(options);    // every field by its name
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

/// How a value is written: fixes how text, JSON and ROS parameters are read into it.
enum class OptionKind { kBool, kInteger, kNumber, kString, kStringList, kIntegerList, kNumberList };

/// "a boolean", "an integer", ... for messages and docs.
const char* describe(OptionKind kind);

/// What is declared of an option besides its name and place: meaning, unit, allowed values and
/// the command-line flag. Built fluently: OptionSpec("radius of the sphere").unit("m").above(0).
class OptionSpec {
 public:
  explicit OptionSpec(std::string help) : help_(std::move(help)) {}

  OptionSpec& unit(std::string unit) {
    unit_ = std::move(unit);
    return *this;
  }
  /// Numbers, integers and list items: inclusive bounds.
  OptionSpec& range(double minimum, double maximum) { return atLeast(minimum).atMost(maximum); }
  OptionSpec& atLeast(double minimum) {
    minimum_ = minimum;
    open_minimum_ = false;
    return *this;
  }
  OptionSpec& atMost(double maximum) {
    maximum_ = maximum;
    open_maximum_ = false;
    return *this;
  }
  /// Exclusive bounds.
  OptionSpec& above(double minimum) {
    minimum_ = minimum;
    open_minimum_ = true;
    return *this;
  }
  OptionSpec& below(double maximum) {
    maximum_ = maximum;
    open_maximum_ = true;
    return *this;
  }
  /// Strings and string-list items: the allowed values.
  OptionSpec& choices(std::vector<std::string> choices) {
    choices_ = std::move(choices);
    return *this;
  }
  /// The command-line flag when it is not "--" + the name with '-' for '_'; "" for none.
  OptionSpec& flag(std::string flag) {
    flag_ = std::move(flag);
    return *this;
  }
  /// List options: one item per occurrence of the flag (--category chair --category table)
  /// instead of one comma-separated list; given at all, the items replace the default list.
  OptionSpec& repeatable() {
    repeatable_ = true;
    return *this;
  }
  /// Bool options: the command-line flag `flag` (e.g. "--no-augment"), given alone, sets the
  /// option false; it takes no value.
  OptionSpec& negatedFlag(std::string flag) {
    flag_ = std::move(flag);
    negated_ = true;
    return *this;
  }

  const std::string& help() const { return help_; }
  const std::string& unit() const { return unit_; }
  const std::optional<double>& minimum() const { return minimum_; }
  const std::optional<double>& maximum() const { return maximum_; }
  bool openMinimum() const { return open_minimum_; }
  bool openMaximum() const { return open_maximum_; }
  const std::vector<std::string>& choices() const { return choices_; }
  const std::optional<std::string>& flag() const { return flag_; }
  bool isRepeatable() const { return repeatable_; }
  bool isNegated() const { return negated_; }

  /// The allowed values in words: "(0, 3.14159]", ">= 1", "embedded | sweethome3d"; "" if any.
  std::string allowedText() const;

 private:
  std::string help_;
  std::string unit_;
  std::optional<double> minimum_;
  std::optional<double> maximum_;
  bool open_minimum_ = false;
  bool open_maximum_ = false;
  std::vector<std::string> choices_;
  std::optional<std::string> flag_;
  bool repeatable_ = false;
  bool negated_ = false;
};

/// One declared option. Its value is read and written as JSON of its kind.
template <class Options>
struct OptionField {
  std::string key;  // the name: ROS parameter, JSON key, and (dashed) the default flag
  OptionKind kind;
  OptionSpec spec;
  std::function<nlohmann::json(const Options&)> get;
  /// Stores an already checked value (OptionTable::set checks, then calls this).
  std::function<void(Options&, const nlohmann::json&)> put;

  /// "--field-of-view", the declared flag, or "" when the option has no flag.
  std::string flagName() const;
};

namespace option_detail {

/// Throws InvalidArgumentError naming `key` unless `value` is a `kind` allowed by `spec` (or null,
/// the unset value of an optional).
void checkValue(const std::string& key, OptionKind kind, const OptionSpec& spec,
                const nlohmann::json& value);

template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

template <class T>
constexpr OptionKind kindOf() {
  if constexpr (IsOptional<T>::value) {
    return kindOf<typename T::value_type>();
  } else if constexpr (std::is_same_v<T, bool>) {
    return OptionKind::kBool;
  } else if constexpr (std::is_integral_v<T>) {
    return OptionKind::kInteger;
  } else if constexpr (std::is_floating_point_v<T>) {
    return OptionKind::kNumber;
  } else if constexpr (std::is_same_v<T, std::string>) {
    return OptionKind::kString;
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    return OptionKind::kStringList;
  } else if constexpr (IsVector<T>::value && std::is_integral_v<typename T::value_type>) {
    return OptionKind::kIntegerList;
  } else {
    static_assert(IsVector<T>::value && std::is_floating_point_v<typename T::value_type>,
                  "options are bool, integers, numbers, strings or lists of them");
    return OptionKind::kNumberList;
  }
}

/// An integer JSON value as T; throws when it does not fit T.
template <class T>
T integerAs(const std::string& key, const nlohmann::json& value) {
  if (value.is_number_unsigned()) {
    const auto wide = value.get<std::uint64_t>();
    if (wide > static_cast<std::uint64_t>(std::numeric_limits<T>::max())) {
      throw InvalidArgumentError(key + ": " + value.dump() + " is too large");
    }
    return static_cast<T>(wide);
  }
  const auto wide = value.get<std::int64_t>();
  if constexpr (std::is_unsigned_v<T>) {
    if (wide < 0) throw InvalidArgumentError(key + ": must be >= 0, got " + value.dump());
    if (static_cast<std::uint64_t>(wide) > std::numeric_limits<T>::max()) {
      throw InvalidArgumentError(key + ": " + value.dump() + " is too large");
    }
  } else {
    if (wide < std::numeric_limits<T>::min() || wide > std::numeric_limits<T>::max()) {
      throw InvalidArgumentError(key + ": " + value.dump() + " is out of range");
    }
  }
  return static_cast<T>(wide);
}

template <class T>
T valueAs(const std::string& key, const nlohmann::json& value) {
  if constexpr (IsOptional<T>::value) {
    if (value.is_null()) return T();
    return valueAs<typename T::value_type>(key, value);
  } else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string> ||
                       std::is_floating_point_v<T>) {
    return value.get<T>();
  } else if constexpr (std::is_integral_v<T>) {
    return integerAs<T>(key, value);
  } else {
    T list;
    for (const nlohmann::json& item : value) {
      list.push_back(valueAs<typename T::value_type>(key, item));
    }
    return list;
  }
}

}  // namespace option_detail

/// The declared options of one struct, in the order of the docs.
template <class Options>
class OptionTable {
 public:
  using Field = OptionField<Options>;

  /// An option stored in `member` (a data member of Options).
  template <class T>
  OptionTable& add(std::string key, T Options::*member, OptionSpec spec) {
    return add(
        std::move(key), [member](Options& options) -> T& { return options.*member; },
        std::move(spec));
  }

  /// An option stored where `access(options)` refers (nested structs:
  /// [](EnvironmentOptions& o) -> int& { return o.scene.num_objects; }).
  template <class Access, class = std::enable_if_t<!std::is_member_object_pointer_v<Access>>>
  OptionTable& add(std::string key, Access access, OptionSpec spec) {
    using T = std::remove_reference_t<std::invoke_result_t<Access, Options&>>;
    Field field{std::move(key), option_detail::kindOf<T>(), std::move(spec), {}, {}};
    field.get = [access](const Options& options) {
      const T& value = access(const_cast<Options&>(options));  // read only
      if constexpr (option_detail::IsOptional<T>::value) {
        return value ? nlohmann::json(*value) : nlohmann::json();  // null: unset
      } else {
        return nlohmann::json(value);
      }
    };
    const std::string name = field.key;
    field.put = [access, name](Options& options, const nlohmann::json& value) {
      access(options) = option_detail::valueAs<T>(name, value);
    };
    return insert(std::move(field));
  }

  /// A string option whose value is converted (enums): `text` names the current value and
  /// `parse` stores one of spec's choices.
  OptionTable& addChoice(std::string key, std::function<std::string(const Options&)> text,
                         std::function<void(Options&, const std::string&)> parse, OptionSpec spec) {
    Field field{std::move(key), OptionKind::kString, std::move(spec), {}, {}};
    field.get = [text](const Options& options) { return nlohmann::json(text(options)); };
    field.put = [parse](Options& options, const nlohmann::json& value) {
      parse(options, value.get<std::string>());
    };
    return insert(std::move(field));
  }

  /// Every field of `inner`, stored in the part of Options that `access` refers to.
  template <class Inner, class Access>
  OptionTable& include(const OptionTable<Inner>& inner, Access access) {
    for (const OptionField<Inner>& field : inner.fields()) {
      Field lifted{field.key, field.kind, field.spec, {}, {}};
      lifted.get = [access, get = field.get](const Options& options) {
        return get(access(const_cast<Options&>(options)));  // read only
      };
      lifted.put = [access, put = field.put](Options& options, const nlohmann::json& value) {
        put(access(options), value);
      };
      insert(std::move(lifted));
    }
    return *this;
  }

  const std::vector<Field>& fields() const { return fields_; }
  /// The field named `key`, or nullptr.
  const Field* find(const std::string& key) const {
    for (const Field& field : fields_) {
      if (field.key == key) return &field;
    }
    return nullptr;
  }
  /// Every name, in table order.
  std::vector<std::string> keys() const {
    std::vector<std::string> names;
    for (const Field& field : fields_) names.push_back(field.key);
    return names;
  }

  /// Checks `value` against the field named `key` and stores it. Throws InvalidArgumentError
  /// naming the option (unknown name, wrong kind, out of range, not a choice); `options` is then
  /// unchanged.
  void set(Options& options, const std::string& key, const nlohmann::json& value) const {
    const Field* field = find(key);
    if (field == nullptr) throw InvalidArgumentError("unknown option " + quoted(key));
    option_detail::checkValue(key, field->kind, field->spec, value);
    field->put(options, value);
  }

  /// Sets every member of the JSON object `object`; unknown names are refused. All values are
  /// checked before any is stored.
  void applyJson(const nlohmann::json& object, Options& options) const {
    if (!object.is_object()) throw InvalidArgumentError("options must be a JSON object");
    Options updated = options;
    for (const auto& [key, value] : object.items()) set(updated, key, value);
    options = std::move(updated);
  }

  /// Every option by its name.
  nlohmann::json toJson(const Options& options) const {
    nlohmann::json json = nlohmann::json::object();
    for (const Field& field : fields_) json[field.key] = field.get(options);
    return json;
  }

  /// Throws InvalidArgumentError naming the first option whose value is out of its declared
  /// range or choices (the declared part of an options struct's validate()).
  void check(const Options& options) const {
    for (const Field& field : fields_) {
      option_detail::checkValue(field.key, field.kind, field.spec, field.get(options));
    }
  }

  /// A Markdown table of the options: name, default (from `defaults`), allowed values, unit and
  /// meaning; what the docs show and a test compares with them.
  std::string markdown(const Options& defaults = Options()) const;

 private:
  OptionTable& insert(Field field) {
    if (find(field.key) != nullptr) {
      throw std::logic_error("option " + field.key + " declared twice");
    }
    fields_.push_back(std::move(field));
    return *this;
  }

  std::vector<Field> fields_;
};

/// A value as the docs and --help show it: 0.05, true, embedded, [chair, table], [] .
std::string displayValue(const nlohmann::json& value);

/// The Markdown table of `fields` (see OptionTable::markdown).
std::string markdownTable(const std::vector<std::string>& keys,
                          const std::vector<nlohmann::json>& defaults,
                          const std::vector<const OptionSpec*>& specs);

template <class Options>
std::string OptionField<Options>::flagName() const {
  if (spec.flag()) return *spec.flag();
  std::string flag = "--" + key;
  for (char& c : flag) {
    if (c == '_') c = '-';
  }
  return flag;
}

template <class Options>
std::string OptionTable<Options>::markdown(const Options& defaults) const {
  std::vector<std::string> names;
  std::vector<nlohmann::json> values;
  std::vector<const OptionSpec*> specs;
  for (const Field& field : fields_) {
    names.push_back(field.key);
    values.push_back(field.get(defaults));
    specs.push_back(&field.spec);
  }
  return markdownTable(names, values, specs);
}

}  // namespace occlusion_env
