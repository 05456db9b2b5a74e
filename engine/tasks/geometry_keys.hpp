#pragma once
// Readers of the plane geometry (sims/geometry.hpp) in task tables, shared by the
// [arm] and [khepera] tables: fixed-size number arrays, points, and the
// [[...obstacles]] arrays of tables with a `kind` each. Errors name the file,
// line and key (JobError), with one wording for every task.

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/toml_table_reader.hpp"
#include "sims/geometry.hpp"

namespace ggk::engine {

// The array of exactly `size` elements at `key`; `what` names the elements in
// messages ("numbers [x, y]"). Required.
const toml::array& sized_array(const TomlTableReader& table, std::string_view key, std::size_t size,
                               const std::string& what);

// The value of a number node (integer or float), if it is one.
std::optional<double> number_value(const toml::node& node);

// The numbers of `array` (of `key`), each in `range`; names[i] names element i
// in messages ("expected <expectation> for <name>, got ...").
template <std::size_t N>
std::array<double, N> numbers_of(const TomlTableReader& table, std::string_view key,
                                 const toml::array& array, std::array<std::string_view, N> names,
                                 NumberRange range, std::string_view expectation) {
  std::array<double, N> values{};
  for (std::size_t i = 0; i < N; ++i) {
    const toml::node& element = array[i];
    const std::optional<double> value = number_value(element);
    if (!value || !range.contains(*value)) {
      table.fail_at(element, key,
                    "expected " + std::string(expectation) + " for " + std::string(names[i]) +
                        ", got " + describe_value(element));
    }
    values[i] = *value;
  }
  return values;
}

// [x, y] of finite numbers; required unless a fallback is given.
sims::Point2 point(const TomlTableReader& table, std::string_view key,
                   std::optional<sims::Point2> fallback = {});

// An obstacle kind: its name (the value of `kind`), its keys, and how a message
// lists them ("kind, min, max").
struct ObstacleKind {
  std::string_view name;
  std::span<const std::string_view> keys;
  std::string_view listed;
};

// The kind of the obstacle table `table` (its key `kind`, one of `kinds`); a key
// of `all_keys` that its kind does not have is an error, not ignored.
const ObstacleKind& obstacle_kind(const TomlTableReader& table, std::span<const ObstacleKind> kinds,
                                  std::span<const std::string_view> all_keys);

// The readers of the obstacle tables of `table`'s key `obstacles`
// ([[<table>.obstacles]]), in file order, each knowing `all_keys`.
std::vector<TomlTableReader> obstacle_tables(const TomlTableReader& table,
                                             std::span<const ObstacleKind> kinds,
                                             std::span<const std::string_view> all_keys);

}  // namespace ggk::engine
