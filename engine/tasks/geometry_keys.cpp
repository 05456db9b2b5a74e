#include "engine/tasks/geometry_keys.hpp"

#include <algorithm>

namespace ggk::engine {

const toml::array& sized_array(const TomlTableReader& table, std::string_view key, std::size_t size,
                               const std::string& what) {
  const toml::node* node = table.find(key);
  if (node == nullptr) table.fail(key, "required key is missing (expected " + what + ")");
  const toml::array* array = node->as_array();
  if (array == nullptr || array->size() != size) {
    const std::string got = array == nullptr ? describe_value(*node)
                            : array->size() == 1
                                ? "an array of 1 element"
                                : "an array of " + std::to_string(array->size()) + " elements";
    table.fail(key, "expected an array of " + std::to_string(size) + " " + what + ", got " + got);
  }
  return *array;
}

std::optional<double> number_value(const toml::node& node) {
  if (const auto* integer = node.as_integer()) return static_cast<double>(integer->get());
  if (const auto* floating = node.as_floating_point()) return floating->get();
  return std::nullopt;
}

sims::Point2 point(const TomlTableReader& table, std::string_view key,
                   std::optional<sims::Point2> fallback) {
  if (!table.has(key) && fallback) return *fallback;
  const toml::array& array = sized_array(table, key, 2, "numbers [x, y]");
  const auto xy = numbers_of<2>(table, key, array, {"x", "y"}, NumberRange{}, "a finite number");
  return {xy[0], xy[1]};
}

const ObstacleKind& obstacle_kind(const TomlTableReader& table, std::span<const ObstacleKind> kinds,
                                  std::span<const std::string_view> all_keys) {
  std::vector<std::string_view> names;
  for (const ObstacleKind& kind : kinds) names.push_back(kind.name);
  const std::string name = table.choice("kind", names);
  const ObstacleKind& own = *std::find_if(kinds.begin(), kinds.end(),
                                          [&](const ObstacleKind& k) { return k.name == name; });
  for (const std::string_view key : all_keys) {
    if (table.has(key) && std::find(own.keys.begin(), own.keys.end(), key) == own.keys.end()) {
      table.fail(key, "a " + name + " has no key '" + std::string(key) +
                          "' (its keys: " + std::string(own.listed) + ")");
    }
  }
  return own;
}

std::vector<TomlTableReader> obstacle_tables(const TomlTableReader& table,
                                             std::span<const ObstacleKind> kinds,
                                             std::span<const std::string_view> all_keys) {
  std::vector<TomlTableReader> readers;
  const toml::node* node = table.find("obstacles");
  if (node == nullptr) return readers;
  const toml::array* array = node->as_array();
  if (array == nullptr) {
    table.fail("obstacles", "expected an array of tables ([[" + table.key_path("obstacles") +
                                "]]), got " + describe_value(*node));
  }
  // "segment", "rectangle" or "disc"
  std::string listed;
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    listed += (k == 0 ? "" : k + 1 == kinds.size() ? " or " : ", ");
    listed += "\"" + std::string(kinds[k].name) + "\"";
  }
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::table* element = (*array)[i].as_table();
    if (element == nullptr) {
      table.fail_at(
          (*array)[i], "obstacles",
          "expected a table with kind = " + listed + ", got " + describe_value((*array)[i]));
    }
    readers.emplace_back(*element, table.key_path("obstacles") + "[" + std::to_string(i) + "]",
                         table.file(), all_keys);
  }
  return readers;
}

}  // namespace ggk::engine
