#include "engine/job/toml_table_reader.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "engine/job/spelling.hpp"

namespace ggk::engine {
namespace {

constexpr std::int64_t kInt32Max = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t kInt64Max = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kInt64Min = std::numeric_limits<std::int64_t>::min();

template <class T, class Format>
std::string canonical_list(const std::vector<T>& values, Format format) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i > 0 ? ", " : "") + format(values[i]);
  return text + "]";
}

std::string quoted_list(std::span<const std::string_view> words) {
  std::string list;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) list += i + 1 == words.size() ? (words.size() > 2 ? ", or " : " or ") : ", ";
    list += '\'';
    list += words[i];
    list += '\'';
  }
  return list;
}

// "an integer >= 1" / "integers in [0, 9]". A maximum that only says "fits the
// storage type" is shown only to a value beyond it.
std::string integer_expectation(IntegerRange range, bool plural, bool value_above_max = false) {
  std::string text = plural ? "integers" : "an integer";
  const bool storage_max = range.max == kInt32Max || range.max == kInt64Max;
  const bool show_max = !storage_max || value_above_max;
  if (range.min == kInt64Min && !show_max) return text;
  if (range.min == kInt64Min) return text + " <= " + std::to_string(range.max);
  if (!show_max) return text + " >= " + std::to_string(range.min);
  return text + " in [" + std::to_string(range.min) + ", " + std::to_string(range.max) + "]";
}

std::string number_expectation(const NumberRange& range, bool plural) {
  std::string text = plural ? "numbers" : "a number";
  const bool has_min = std::isfinite(range.min);
  const bool has_max = std::isfinite(range.max);
  if (has_min && has_max) {
    return text + " in " + (range.min_inclusive ? "[" : "(") + canonical_number(range.min) + ", " +
           canonical_number(range.max) + (range.max_inclusive ? "]" : ")");
  }
  if (has_min) return text + (range.min_inclusive ? " >= " : " > ") + canonical_number(range.min);
  if (has_max) return text + (range.max_inclusive ? " <= " : " < ") + canonical_number(range.max);
  return text;
}

std::string choice_expectation(std::span<const std::string_view> choices, bool plural) {
  return (plural ? "strings out of " : "one of ") + quoted_list(choices);
}

std::string suggestion(std::string_view word, std::span<const std::string_view> candidates) {
  const auto best = closest_spelling(word, candidates);
  return best ? "; did you mean '" + std::string(*best) + "'?" : std::string();
}

// The value of a number node (integer or float), if it is one.
std::optional<double> number_value(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

}  // namespace

bool NumberRange::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above_min = min_inclusive ? value >= min : value > min;
  const bool below_max = max_inclusive ? value <= max : value < max;
  return above_min && below_max;
}

JobError error_at(const std::string& file, const toml::source_region& region, std::string key_path,
                  std::string detail) {
  if (region.path && !region.path->empty() && *region.path != file) {
    return JobError(*region.path, {}, std::move(key_path), std::move(detail));
  }
  return JobError(file, location_of(region), std::move(key_path), std::move(detail));
}

JobFileLocation location_of(const toml::source_region& region) {
  return {static_cast<std::int32_t>(region.begin.line),
          static_cast<std::int32_t>(region.begin.column)};
}

std::string describe_value(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::integer:
      return std::to_string(node.as_integer()->get());
    case toml::node_type::floating_point:
      return canonical_number(node.as_floating_point()->get());
    case toml::node_type::boolean:
      return node.as_boolean()->get() ? "true" : "false";
    case toml::node_type::string: {
      return '"' + shortened(node.as_string()->get(), 40) + '"';
    }
    case toml::node_type::array:
      return node.as_array()->empty() ? "an empty array" : "an array";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

TomlTableReader::TomlTableReader(const toml::table& table, std::string table_path, std::string file,
                                 std::span<const std::string_view> known_keys)
    : TomlTableReader(table, std::move(table_path), std::move(file), known_keys, true) {}

TomlTableReader::TomlTableReader(const toml::table& table, std::string table_path, std::string file,
                                 std::span<const std::string_view> known_keys, bool present)
    : table_(&table),
      table_path_(std::move(table_path)),
      file_(std::move(file)),
      known_keys_(known_keys),
      present_(present) {
  reject_unknown_keys();
}

std::string TomlTableReader::key_path(std::string_view key) const {
  return table_path_.empty() ? std::string(key) : table_path_ + '.' + std::string(key);
}

void TomlTableReader::reject_unknown_keys() const {
  // toml++ keeps keys sorted by name; report the first unknown one in file order.
  const toml::key* first_unknown = nullptr;
  for (const auto& [key, value] : *table_) {
    if (std::find(known_keys_.begin(), known_keys_.end(), key.str()) != known_keys_.end()) {
      continue;
    }
    const auto place = [](const toml::key& k) {
      return std::make_tuple(k.source().begin.line, k.source().begin.column);
    };
    if (first_unknown == nullptr || place(key) < place(*first_unknown)) first_unknown = &key;
  }
  if (first_unknown == nullptr) return;
  const std::string_view name = first_unknown->str();
  std::string detail = "unknown key";
  const std::string hint = suggestion(name, known_keys_);
  if (!hint.empty()) {
    detail += hint;
  } else {
    detail += " (known keys";
    detail += table_path_.empty() ? "" : " of [" + table_path_ + "]";
    detail += ": " + quoted_list(known_keys_) + ")";
  }
  throw error_at(file_, first_unknown->source(), key_path(name), detail);
}

bool TomlTableReader::has(std::string_view key) const {
  return find(key) != nullptr;
}

const toml::node* TomlTableReader::find(std::string_view key) const {
  return table_->get(key);
}

void TomlTableReader::fail(std::string_view key, std::string detail) const {
  const auto it = table_->find(key);
  if (it == table_->end()) {
    if (present_ && !table_path_.empty()) {
      throw error_at(file_, table_->source(), key_path(key), std::move(detail));
    }
    throw JobError(file_, {}, key_path(key), std::move(detail));
  }
  throw error_at(file_, it->first.source(), key_path(key), std::move(detail));
}

void TomlTableReader::fail_at(const toml::node& node, std::string_view key,
                              std::string detail) const {
  throw error_at(file_, node.source(), key_path(key), std::move(detail));
}

void TomlTableReader::fail_table(std::string detail) const {
  if (present_ && !table_path_.empty()) {
    throw error_at(file_, table_->source(), table_path_, std::move(detail));
  }
  throw JobError(file_, {}, table_path_, std::move(detail));
}

std::optional<TomlTableReader> TomlTableReader::subtable(
    std::string_view key, std::span<const std::string_view> known_keys) const {
  const toml::node* node = find(key);
  if (node == nullptr) return std::nullopt;
  const toml::table* table = node->as_table();
  if (table == nullptr) fail(key, "expected a table, got " + describe_value(*node));
  TomlTableReader reader(*table, key_path(key), file_, known_keys, true);
  reader.resolved_ = resolved_;
  return reader;
}

TomlTableReader TomlTableReader::subtable_or_empty(
    std::string_view key, std::span<const std::string_view> known_keys) const {
  if (auto table = subtable(key, known_keys)) return std::move(*table);
  static const toml::table empty;
  TomlTableReader reader(empty, key_path(key), file_, known_keys, false);
  reader.resolved_ = resolved_;
  return reader;
}

void TomlTableReader::note(std::string_view key, std::string value) const {
  if (resolved_) resolved_->record(key_path(key), std::move(value), has(key));
}

const toml::node& TomlTableReader::required(std::string_view key) const {
  const toml::node* node = find(key);
  if (node == nullptr) fail(key, "required key is missing");
  return *node;
}

std::string TomlTableReader::string(std::string_view key,
                                    std::optional<std::string> fallback) const {
  std::string result = [&]() -> std::string {
    if (!has(key) && fallback) return std::move(*fallback);
    const toml::node& node = required(key);
    if (const auto* text = node.as_string()) return text->get();
    fail(key, "expected a string, got " + describe_value(node));
  }();
  note(key, canonical_string(result));
  return result;
}

std::string TomlTableReader::choice(std::string_view key, std::span<const std::string_view> choices,
                                    std::optional<std::string> fallback) const {
  std::string result = [&]() -> std::string {
    if (!has(key) && fallback) return std::move(*fallback);
    const toml::node& node = required(key);
    const auto* text = node.as_string();
    if (text == nullptr) {
      fail(key, "expected " + choice_expectation(choices, false) + ", got " + describe_value(node));
    }
    const std::string& value = text->get();
    if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
      fail(key, "expected " + choice_expectation(choices, false) + ", got " + describe_value(node) +
                    suggestion(value, choices));
    }
    return value;
  }();
  note(key, canonical_string(result));
  return result;
}

std::int64_t TomlTableReader::integer(std::string_view key, IntegerRange range,
                                      std::optional<std::int64_t> fallback) const {
  std::int64_t result = [&]() -> std::int64_t {
    if (!has(key) && fallback) return *fallback;
    const toml::node& node = required(key);
    const auto* value = node.as_integer();
    if (value == nullptr) {
      fail(key, "expected " + integer_expectation(range, false) + ", got " + describe_value(node));
    }
    const std::int64_t v = value->get();
    if (v < range.min || v > range.max) {
      fail(key, "expected " + integer_expectation(range, false, v > range.max) + ", got " +
                    describe_value(node));
    }
    return v;
  }();
  note(key, canonical_integer(result));
  return result;
}

double TomlTableReader::number(std::string_view key, NumberRange range,
                               std::optional<double> fallback) const {
  double result = [&]() -> double {
    if (!has(key) && fallback) return *fallback;
    const toml::node& node = required(key);
    const std::optional<double> value = number_value(node);
    if (!value || !range.contains(*value)) {
      fail(key, "expected " + number_expectation(range, false) + ", got " + describe_value(node));
    }
    return *value;
  }();
  note(key, canonical_number(result));
  return result;
}

bool TomlTableReader::boolean(std::string_view key, std::optional<bool> fallback) const {
  bool result = [&]() -> bool {
    if (!has(key) && fallback) return *fallback;
    const toml::node& node = required(key);
    if (const auto* value = node.as_boolean()) return value->get();
    fail(key, "expected true or false, got " + describe_value(node));
  }();
  note(key, canonical_boolean(result));
  return result;
}

const toml::array& TomlTableReader::set_array(std::string_view key, const toml::node& node,
                                              std::string_view expected) const {
  const toml::array* array = node.as_array();
  const std::string expectation = "expected a non-empty array of " + std::string(expected);
  if (array == nullptr) {
    const bool scalar = node.is_number() || node.is_string() || node.is_boolean();
    fail(key, expectation + ", got " + describe_value(node) +
                  (scalar ? " (write [" + describe_value(node) + "] for a single value)" : ""));
  }
  if (array->empty()) fail(key, expectation + ", got an empty array");
  return *array;
}

namespace {

// Throws at the second of two equal elements.
template <typename T>
void reject_duplicates(const TomlTableReader& reader, std::string_view key,
                       const toml::array& array, const std::vector<T>& values) {
  for (std::size_t i = 1; i < values.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (values[i] != values[j]) continue;
      const JobFileLocation first = location_of(array[j].source());
      reader.fail_at(array[i], key,
                     "duplicate value " + describe_value(array[i]) + " (first given at line " +
                         std::to_string(first.line) + ", column " + std::to_string(first.column) +
                         "); the values of a sweep axis must be distinct");
    }
  }
}

}  // namespace

std::vector<std::int64_t> TomlTableReader::integer_set(
    std::string_view key, IntegerRange range,
    std::optional<std::vector<std::int64_t>> fallback) const {
  std::vector<std::int64_t> result = [&]() -> std::vector<std::int64_t> {
    if (!has(key) && fallback) return std::move(*fallback);
    const toml::array& array = set_array(key, required(key), integer_expectation(range, true));
    std::vector<std::int64_t> values;
    for (const toml::node& element : array) {
      const auto* value = element.as_integer();
      if (value == nullptr || value->get() < range.min || value->get() > range.max) {
        const bool above_max = value != nullptr && value->get() > range.max;
        fail_at(element, key,
                "expected an array of " + integer_expectation(range, true, above_max) + ", got " +
                    describe_value(element));
      }
      values.push_back(value->get());
    }
    reject_duplicates(*this, key, array, values);
    return values;
  }();
  note(key, canonical_list(result, canonical_integer));
  return result;
}

std::vector<double> TomlTableReader::number_set(std::string_view key, NumberRange range,
                                                std::optional<std::vector<double>> fallback) const {
  std::vector<double> result = [&]() -> std::vector<double> {
    if (!has(key) && fallback) return std::move(*fallback);
    const toml::array& array = set_array(key, required(key), number_expectation(range, true));
    std::vector<double> values;
    for (const toml::node& element : array) {
      const std::optional<double> value = number_value(element);
      if (!value || !range.contains(*value)) {
        fail_at(element, key,
                "expected an array of " + number_expectation(range, true) + ", got " +
                    describe_value(element));
      }
      values.push_back(*value);
    }
    reject_duplicates(*this, key, array, values);
    return values;
  }();
  note(key, canonical_list(result, canonical_number));
  return result;
}

std::vector<std::string> TomlTableReader::choice_set(
    std::string_view key, std::span<const std::string_view> choices,
    std::optional<std::vector<std::string>> fallback) const {
  std::vector<std::string> result = [&]() -> std::vector<std::string> {
    if (!has(key) && fallback) return std::move(*fallback);
    const toml::array& array = set_array(key, required(key), choice_expectation(choices, true));
    std::vector<std::string> values;
    for (const toml::node& element : array) {
      const auto* text = element.as_string();
      if (text == nullptr ||
          std::find(choices.begin(), choices.end(), text->get()) == choices.end()) {
        fail_at(element, key,
                "expected an array of " + choice_expectation(choices, true) + ", got " +
                    describe_value(element) + (text ? suggestion(text->get(), choices) : ""));
      }
      values.push_back(text->get());
    }
    reject_duplicates(*this, key, array, values);
    return values;
  }();
  note(key, canonical_list(result, [](const std::string& v) { return canonical_string(v); }));
  return result;
}

}  // namespace ggk::engine
