#pragma once
// Reads one table of a job file with validation. Every problem becomes a JobError
// that names the file, the line and column toml++ recorded, and the key.
//
// A reader is built with the table's list of known keys and rejects any other key
// at once (the first one in file order, with a "did you mean" suggestion), so a
// misspelt key can never silently fall back to its default. The typed getters
// return the value, the default when the key is absent (a getter without a default
// makes the key required), or throw. Used by job_file.cpp and by each task's table
// parser (maze_table.cpp, ...).
//
// Thread-safety: none needed; a reader is used by one parse call.

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "engine/job/job_error.hpp"
#include "engine/job/resolved_config.hpp"

namespace ggk::engine {

// Closed integer range [min, max].
struct IntegerRange {
  std::int64_t min = std::numeric_limits<std::int64_t>::min();
  std::int64_t max = std::numeric_limits<std::int64_t>::max();
};

// Range of a finite float; each end open or closed. Integers in the file are
// accepted and converted.
struct NumberRange {
  double min = -std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  double max = std::numeric_limits<double>::infinity();
  bool max_inclusive = true;

  static NumberRange at_least(double lo) { return {lo, true}; }
  static NumberRange above(double lo) { return {lo, false}; }
  static NumberRange half_open(double lo, double hi) { return {lo, true, hi, false}; }
  static NumberRange open(double lo, double hi) { return {lo, false, hi, false}; }
  bool contains(double value) const;
};

// Location of a toml++ node (line 0 when it has none).
JobFileLocation location_of(const toml::source_region& region);

// The error at `region` of `file`: FILE:LINE:COLUMN, or, for a value that came
// from elsewhere (a `ggk run --set KEY=VALUE` override, whose region names the
// option), that source without a line.
JobError error_at(const std::string& file, const toml::source_region& region, std::string key_path,
                  std::string detail);

// How a value reads in a message: 12, 2.5, "text", true, an array, a table.
std::string describe_value(const toml::node& node);

class TomlTableReader {
 public:
  // table_path: the table's dotted key path, empty for the root table. `table`
  // and `known_keys` (a static array in practice) must outlive the reader.
  // Throws JobError for the first unknown key.
  TomlTableReader(const toml::table& table, std::string table_path, std::string file,
                  std::span<const std::string_view> known_keys);

  // A reader for a sub-table of this one, or nullopt when the key is absent.
  // Throws JobError when the key holds something other than a table.
  std::optional<TomlTableReader> subtable(std::string_view key,
                                          std::span<const std::string_view> known_keys) const;
  // As subtable(), but an absent table reads as an empty one (every key defaulted).
  TomlTableReader subtable_or_empty(std::string_view key,
                                    std::span<const std::string_view> known_keys) const;

  bool has(std::string_view key) const;
  // The key's value node, or nullptr.
  const toml::node* find(std::string_view key) const;

  std::string string(std::string_view key, std::optional<std::string> fallback = {}) const;
  // A string that must be one of `choices` (with a suggestion when it is not).
  std::string choice(std::string_view key, std::span<const std::string_view> choices,
                     std::optional<std::string> fallback = {}) const;
  std::int64_t integer(std::string_view key, IntegerRange range,
                       std::optional<std::int64_t> fallback = {}) const;
  double number(std::string_view key, NumberRange range, std::optional<double> fallback = {}) const;
  bool boolean(std::string_view key, std::optional<bool> fallback = {}) const;

  // Non-empty arrays with distinct elements (the sweep axes).
  std::vector<std::int64_t> integer_set(
      std::string_view key, IntegerRange range,
      std::optional<std::vector<std::int64_t>> fallback = {}) const;
  std::vector<double> number_set(std::string_view key, NumberRange range,
                                 std::optional<std::vector<double>> fallback = {}) const;
  std::vector<std::string> choice_set(std::string_view key,
                                      std::span<const std::string_view> choices,
                                      std::optional<std::vector<std::string>> fallback = {}) const;

  // Throws JobError at the key's value (at the table when the key is absent).
  [[noreturn]] void fail(std::string_view key, std::string detail) const;
  // Throws JobError at `node` (e.g. one element of an array), naming `key`.
  [[noreturn]] void fail_at(const toml::node& node, std::string_view key, std::string detail) const;
  // Throws JobError at the table itself, naming the table.
  [[noreturn]] void fail_table(std::string detail) const;

  // From now on, every typed getter of this reader and of the sub-table readers
  // it makes records the key and the value it returns (defaults included) in
  // `resolved` (resolved_config.hpp).
  void record_into(std::shared_ptr<ResolvedConfig> resolved) { resolved_ = std::move(resolved); }

  // A key read (and recorded) that the job's other choices leave unused, and
  // why: ResolvedConfig::mark_unused.
  void mark_unused(std::string_view key, std::string why) const {
    if (resolved_) resolved_->mark_unused(key_path(key), std::move(why));
  }

  const std::string& file() const { return file_; }
  const std::string& table_path() const { return table_path_; }
  // Dotted path of a key of this table ("lspi.gamma").
  std::string key_path(std::string_view key) const;

 private:
  TomlTableReader(const toml::table& table, std::string table_path, std::string file,
                  std::span<const std::string_view> known_keys, bool present);
  void reject_unknown_keys() const;
  const toml::node& required(std::string_view key) const;
  const toml::array& set_array(std::string_view key, const toml::node& node,
                               std::string_view expected) const;
  // Records key = value (canonical text) when recording; given = the key is present.
  void note(std::string_view key, std::string value) const;

  const toml::table* table_;
  std::string table_path_;
  std::string file_;
  std::span<const std::string_view> known_keys_;
  bool present_;  // false for an absent table read as empty: it has no location
  std::shared_ptr<ResolvedConfig> resolved_;  // where getters record, or null
};

}  // namespace ggk::engine
