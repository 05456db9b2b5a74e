#pragma once
// A job's resolved configuration: every key the job reader looked at, with the
// value it used (the file's, an override's, or the default), as canonical TOML
// text. Two jobs with equal resolved configurations compute the same results,
// whatever their spelling: `30` and `30.0` for a number, a key at its default
// and the key left out, key order, comments and quoting all read alike.
//
// The job reader (toml_table_reader.hpp) records each typed getter's result;
// parse_job then adds the keys no getter reads (arrays of tables such as
// obstacle lists) as toml++ formats them. Stored with the results (the root
// attribute `job_resolved`), so readers never re-derive a default.
//
// Thread-safety: plain data; a const object may be shared.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace ggk::engine {

class ResolvedConfig {
 public:
  // Records `key` (dotted path, "khepera.motion.turn_deg") = `value` (canonical
  // TOML text). `given`: the job file or an override set it (false: a default).
  // A key read twice keeps its first record.
  void record(const std::string& key, std::string value, bool given);
  // Records `key` = `value` whether or not it was recorded before.
  void replace(const std::string& key, std::string value, bool given);

  // Marks a recorded key as one the job does not use, and why (a default the
  // job's other choices make inapplicable, e.g. noise_sd under a noise model
  // without it): `ggk validate --print` shows it as a comment, since giving it
  // would be refused. No part of text() or of the comparisons.
  void mark_unused(const std::string& key, std::string why);
  // Why `key` is unused, or nullopt when it is used.
  std::optional<std::string> unused_reason(const std::string& key) const;

  bool contains(const std::string& key) const { return values_.count(key) > 0; }
  // The canonical value text of `key`, or nullopt.
  std::optional<std::string> value(const std::string& key) const;
  // Every key, sorted.
  std::vector<std::string> keys() const;
  // The keys the job file or an override set, sorted.
  std::set<std::string> given_keys() const;
  std::size_t size() const { return values_.size(); }

  // One `"dotted.key" = value` line per key, sorted by key: the stored form,
  // parsed back by from_text(). Deterministic.
  std::string text() const;
  // The resolved configuration in text() form; nullopt when it is not one.
  static std::optional<ResolvedConfig> from_text(std::string_view text);

  // The first key whose value differs, in words ("khepera.motion.turn_deg: 30.0 in
  // the results file, 45.0 in the job"), ignoring the keys in `ignored`; nullopt
  // when equal.
  std::optional<std::string> difference(const ResolvedConfig& other, std::string_view this_label,
                                        std::string_view other_label,
                                        const std::set<std::string>& ignored = {}) const;

  // Every key that differs, in the same words, in key order; at most `limit`.
  std::vector<std::string> differences(const ResolvedConfig& other, std::string_view this_label,
                                       std::string_view other_label,
                                       const std::set<std::string>& ignored = {},
                                       std::size_t limit = SIZE_MAX) const;

  bool operator==(const ResolvedConfig& other) const;

 private:
  struct Entry {
    std::string value;
    bool given = false;
  };
  std::map<std::string, Entry> values_;
  std::map<std::string, std::string> unused_;  // key -> why
};

// Canonical TOML texts of typed values, as ResolvedConfig records them: integers
// in decimal, floats as the shortest text that reads back as the same double
// (always with a '.', 'e', "inf" or "nan", so 30 read as a number is "30.0"),
// strings in basic-string quotes with escapes, booleans as true / false.
std::string canonical_integer(std::int64_t value);
std::string canonical_number(double value);
std::string canonical_string(std::string_view value);
std::string canonical_boolean(bool value);
// Whether `given` (as a job, a command line or a user writes a value) names
// `stored` (as a job or a results table holds it, strings unquoted): the same
// text, or the same number ("0.0" and "0", "1e-6" and "0.000001").
bool same_value_text(const std::string& stored, const std::string& given);

// The canonical texts of the elements of an array's canonical text
// ("[15.0, 30.0]" -> {"15.0", "30.0"}); nullopt when `text` is not an array of
// scalars.
std::optional<std::vector<std::string>> canonical_elements(std::string_view text);

}  // namespace ggk::engine
