#include "engine/job/job_compare.hpp"

#include <sstream>

#include <toml++/toml.h>

#include "engine/job/job_error.hpp"
#include "engine/job/resolved_config.hpp"

namespace ggk::engine {

namespace {

constexpr std::size_t kShownValue = 60;  // characters of a value shown in a message

// A value as a person wrote it: numbers in their shortest exact form (0.2, where
// toml++ prints 0.20000000000000001), arrays element by element.
std::string value_text(const toml::node& node) {
  if (node.is_table()) return "a table";
  if (const auto* array = node.as_array()) {
    std::string text = "[";
    for (const toml::node& element : *array) {
      text += (text.size() > 1 ? ", " : "") + value_text(element);
    }
    return text + "]";
  }
  if (const auto* number = node.as_floating_point()) return canonical_number(number->get());
  std::ostringstream out;
  node.visit([&out](const auto& value) { out << value; });
  return out.str();
}

std::string shown(const toml::node& node) {
  std::string text = value_text(node);
  if (text.size() > kShownValue) text = text.substr(0, kShownValue) + "...";
  return text;
}

std::string joined(const std::string& prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

struct Labels {
  std::string_view recorded, current;
};

std::optional<std::string> table_difference(const toml::table& recorded, const toml::table& current,
                                            const std::string& prefix, const Labels& labels) {
  for (const auto& [key, value] : recorded) {
    const std::string path = joined(prefix, key.str());
    const toml::node* other = current.get(key.str());
    if (other == nullptr) return display_key(path) + ": only in " + std::string(labels.recorded);
    const auto* table = value.as_table();
    const auto* other_table = other->as_table();
    if (table != nullptr && other_table != nullptr) {
      if (auto difference = table_difference(*table, *other_table, path, labels)) {
        return difference;
      }
    } else if (toml::node_view<const toml::node>(&value) !=
               toml::node_view<const toml::node>(other)) {
      return display_key(path) + ": " + shown(value) + " in " + std::string(labels.recorded) +
             ", " + shown(*other) + " in " + std::string(labels.current);
    }
  }
  for (const auto& [key, value] : current) {
    if (recorded.get(key.str()) == nullptr) {
      return display_key(joined(prefix, key.str())) + ": only in " + std::string(labels.current);
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> job_difference(std::string_view recorded, std::string_view current,
                                          std::string_view recorded_label,
                                          std::string_view current_label) {
  toml::table recorded_table, current_table;
  try {
    recorded_table = toml::parse(recorded);
    current_table = toml::parse(current);
  } catch (const toml::parse_error&) {
    if (recorded == current) return std::nullopt;
    return std::string("the job texts differ (one does not parse as TOML)");
  }
  return table_difference(recorded_table, current_table, "", {recorded_label, current_label});
}

}  // namespace ggk::engine
