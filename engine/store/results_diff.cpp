#include "engine/store/results_diff.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <variant>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/resolved_config.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/one_line.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_digest.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

const std::array<std::string, 1> kWallClockColumns = {"fit_seconds"};

bool ignored_attribute(const std::string& object, const std::string& name) {
  if (name == "fit_seconds") return true;
  // A run's digest is derived from what diff compares itself (run_digest.hpp);
  // files from before it have none.
  if ((name == kRunDigestAttribute || name == kMetadataDigestAttribute) &&
      object.find("/run_") != std::string::npos) {
    return true;
  }
  return object == "/" && root_attribute_role(name) == RootAttributeRole::kWallClock;
}
bool provenance(const std::string& object, const std::string& name) {
  return object == "/" && root_attribute_role(name) == RootAttributeRole::kProvenance;
}

std::string child(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

// A short, readable form of an attribute for notes (strings and numbers).
// Two provenance strings that differ, each cut to the window around their first
// difference (a BLAS's name differs in its kernel set, past the first 40 characters).
std::pair<std::string, std::string> shown_difference(const std::string& a, const std::string& b) {
  constexpr std::size_t kBefore = 12, kWidth = 60;
  std::size_t first = 0;
  while (first < a.size() && first < b.size() && a[first] == b[first]) ++first;
  const std::size_t from = first > kBefore ? first - kBefore : 0;
  const auto cut = [&](const std::string& text) {
    std::string window = text.substr(std::min(from, text.size()), kWidth);
    return "\"" + std::string(from > 0 ? "..." : "") + window +
           (from + kWidth < text.size() ? "..." : "") + "\"";
  };
  return {cut(a), cut(b)};
}

std::string shown(const Hdf5File::Values& v) {
  if (!v.strings.empty()) {
    std::string text = v.strings.front();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return "\"" + text + "\"";
  }
  return v.type + " value";
}

// The largest difference over every object, with the object's path.
struct LargestDifference {
  double value = 0.0;
  std::string path;
  ElementPlace place;
  std::vector<std::int64_t> shape;
  bool found = false;
  void consider(double candidate, const std::string& object, const std::optional<ElementPlace>& at,
                const std::vector<std::int64_t>& object_shape) {
    if (!at || (found && !(candidate > value))) return;
    value = candidate;
    path = object;
    place = *at;
    shape = object_shape;
    found = true;
  }
  std::string text() const {
    std::ostringstream out;
    out.precision(2);
    out << value << " at " << path << " " << element_place(place, shape);
    return out.str();
  }
};

class Comparison {
 public:
  // jobs_differ: both files record the job's meaning and the two differ.
  Comparison(const Hdf5File& a, const Hdf5File& b, const std::string& task,
             const DiffOptions& options, bool jobs_differ, std::ostream& out)
      : a_(a),
        b_(b),
        task_group_("/" + task),
        tolerance_(options.tolerance),
        exclude_(options.exclude),
        common_(options.common),
        out_(out),
        meaning_recorded_(a.has_attribute("/", "job_resolved") &&
                          b.has_attribute("/", "job_resolved")),
        by_value_(jobs_differ) {}

  // Compares the object at `path_a` in the first file with the one at `path_b`
  // in the second: the same path, but for a study's configuration groups, which
  // two different jobs number differently (matched by their values).
  void compare_object(const std::string& path_a, const std::string& path_b) {
    const std::string path = shown_path(path_a, path_b);
    if (excluded(path)) return;
    compare_attributes(path_a, path_b);
    const Hdf5File::ObjectKind kind_a = a_.object_kind(path_a), kind_b = b_.object_kind(path_b);
    if (kind_a != kind_b) {
      differ(path, "a group in one file, a dataset in the other");
      return;
    }
    if (kind_a == Hdf5File::ObjectKind::kDataset) {
      ++datasets_;
      if (by_value_ && is_fit_table(path_a)) {
        compare_tables_by_key(path_a, path_b, path);
        return;
      }
      const Hdf5File::Values va = a_.read_values(path_a, kWallClockColumns);
      const Hdf5File::Values vb = b_.read_values(path_b, kWallClockColumns);
      if (va.type != vb.type || va.shape != vb.shape) {
        differ(path, "type or shape differs");
      } else if (!(va == vb)) {
        compare_values_of(path, va, vb, "values differ");
      }
      return;
    }
    if (kind_a != Hdf5File::ObjectKind::kGroup) return;
    std::vector<std::string> names_a = a_.member_names(path_a), names_b = b_.member_names(path_b);
    if (path_a == "/") {
      std::erase_if(names_a, is_scratch);
      std::erase_if(names_b, is_scratch);
    }
    if (path_a == task_group_) compare_configurations(names_a, names_b);
    for_each_union(names_a, names_b, [&](const std::string& name, bool in_a, bool in_b) {
      if (in_a && in_b) {
        compare_object(child(path_a, name), child(path_b, name));
      } else {
        only_in(child(in_a ? path_a : path_b, name), in_a);
      }
    });
  }

  bool same() const { return differences_ == 0; }
  std::size_t differences() const { return differences_; }
  std::size_t within_tolerance() const { return within_tolerance_; }
  std::size_t excluded_count() const { return excluded_; }
  const LargestDifference& largest_absolute() const { return largest_absolute_; }
  const LargestDifference& largest_relative() const { return largest_relative_; }
  std::size_t datasets() const { return datasets_; }
  std::size_t attributes() const { return attributes_; }
  const std::vector<std::string>& notes() const { return notes_; }
  bool by_value() const { return by_value_; }
  std::size_t only_in_one() const { return only_in_one_; }
  std::size_t matched_rows() const { return matched_rows_; }

 private:
  static std::string shown_path(const std::string& path_a, const std::string& path_b) {
    return path_a == path_b ? path_a : path_a + " (" + path_b + " in the second file)";
  }

  // Something only one file holds: a difference, or with --common a note.
  void only_in(const std::string& what, bool in_first) {
    const std::string where = in_first ? "only in the first file" : "only in the second file";
    ++only_in_one_;
    if (common_) {
      if (notes_.size() < kMostNotes) notes_.push_back(what + ": " + where + " (--common)");
      return;
    }
    differ(what, where);
  }

  // A study's configuration groups, paired by their values (attribute
  // study_values), not their names: two studies with other values of a
  // run-level axis number their shared configurations differently. Removes the
  // groups it compares (or reports) from both lists.
  void compare_configurations(std::vector<std::string>& names_a,
                              std::vector<std::string>& names_b) {
    const auto by_values = [&](const Hdf5File& file, std::vector<std::string>& names) {
      std::map<std::string, std::string> found;  // study_values -> group name
      std::erase_if(names, [&](const std::string& name) {
        if (!is_configuration_group_name(name)) return false;
        const std::optional<std::string> values =
            study_values_of(file, child(task_group_, name).substr(1));
        return values && found.emplace(*values, name).second;
      });
      return found;
    };
    const std::map<std::string, std::string> a = by_values(a_, names_a);
    const std::map<std::string, std::string> b = by_values(b_, names_b);
    for (const auto& [values, name] : a) {
      const auto other = b.find(values);
      if (other != b.end()) {
        compare_object(child(task_group_, name), child(task_group_, other->second));
      } else {
        only_in(child(task_group_, name) + " {" + one_line(values_words(values)) + "}", true);
      }
    }
    for (const auto& [values, name] : b) {
      if (a.count(values) == 0) {
        only_in(child(task_group_, name) + " {" + one_line(values_words(values)) + "}", false);
      }
    }
  }

  static std::string values_words(const std::string& values) {
    std::string text;
    for (char c : values) text += c == '\n' ? std::string(", ") : std::string(1, c);
    while (text.ends_with(", ")) text.resize(text.size() - 2);
    return text;
  }

  // The tables of fits (a run's fit_metrics, the task's summary): compared row by
  // row when the jobs differ, the rows matched by their point (the columns before
  // `status` but the numbering ones).
  static bool is_fit_table(const std::string& path) {
    return path.ends_with("/fit_metrics") || path.ends_with("/summary");
  }

  void compare_tables_by_key(const std::string& path_a, const std::string& path_b,
                             const std::string& path) {
    const std::vector<TableColumn> columns = a_.read_table_columns(path_a);
    if (columns != b_.read_table_columns(path_b)) {
      differ(path, "its columns differ");
      return;
    }
    const auto status = std::find_if(columns.begin(), columns.end(),
                                     [](const TableColumn& c) { return c.name == "status"; });
    std::vector<std::size_t> keys, values;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const std::string& name = columns[c].name;
      if (name == "sweep_point" || name == "configuration" || name == "fit_seconds") continue;
      (c < static_cast<std::size_t>(status - columns.begin()) ? keys : values).push_back(c);
    }
    const auto keyed = [&](const std::vector<TableRow>& rows) {
      std::map<std::string, const TableRow*> by_key;
      for (const TableRow& row : rows) {
        std::string key;
        for (const std::size_t c : keys) {
          key += (key.empty() ? "" : ", ") + columns[c].name + " = " + cell_text(row[c]);
        }
        by_key.emplace(key, &row);
      }
      return by_key;
    };
    const std::vector<TableRow> rows_a = a_.read_table(path_a), rows_b = b_.read_table(path_b);
    const auto a = keyed(rows_a), b = keyed(rows_b);
    std::size_t differing = 0;
    std::string first;
    for (const auto& [key, row] : a) {
      const auto other = b.find(key);
      if (other == b.end()) {
        only_in(path + " row {" + key + "}", true);
        continue;
      }
      ++matched_rows_;
      for (const std::size_t c : values) {
        if (!same_cell((*row)[c], (*other->second)[c], path, columns[c].name,
                       row - rows_a.data())) {
          if (differing++ == 0) {
            first = "first at {" + key + "}, column " + columns[c].name + " (" +
                    cell_text((*row)[c]) + " vs " + cell_text((*other->second)[c]) + ")";
          }
        }
      }
    }
    for (const auto& [key, row] : b) {
      if (a.count(key) == 0) only_in(path + " row {" + key + "}", false);
    }
    if (differing > 0) {
      differ(path, "rows matched by their point differ: " + std::to_string(differing) + " cells, " +
                       first);
    }
  }

  // A cell as text, numbers in their shortest exact form ("0.1", not 0.10000000000000001).
  static std::string cell_text(const TableValue& value) {
    if (const auto* text = std::get_if<std::string>(&value)) return *text;
    char buffer[64];
    char* end = buffer;
    if (const auto* real = std::get_if<double>(&value)) {
      end = std::to_chars(buffer, buffer + sizeof buffer, *real).ptr;
    } else if (const auto* wide = std::get_if<std::int64_t>(&value)) {
      end = std::to_chars(buffer, buffer + sizeof buffer, *wide).ptr;
    } else if (const auto* narrow = std::get_if<std::int32_t>(&value)) {
      end = std::to_chars(buffer, buffer + sizeof buffer, *narrow).ptr;
    }
    return std::string(buffer, end);
  }

  // Two cells of one column: equal as diff compares elements (value_difference.hpp).
  bool same_cell(const TableValue& a, const TableValue& b, const std::string& path,
                 const std::string& column, std::ptrdiff_t row) {
    if (a == b) return true;
    const auto* x = std::get_if<double>(&a);
    const auto* y = std::get_if<double>(&b);
    if (x == nullptr || y == nullptr) return false;
    if (std::isnan(*x) && std::isnan(*y)) return true;
    const double absolute = std::fabs(*x - *y);
    ElementPlace place;
    place.index = row;
    place.member = column;
    place.a = *x;
    place.b = *y;
    const std::vector<std::int64_t> shape = {row + 1};
    largest_absolute_.consider(absolute, path, place, shape);
    largest_relative_.consider(absolute / std::fabs(*y), path, place, shape);
    if (absolute <= tolerance_.atol + tolerance_.rtol * std::fabs(*y)) {
      ++within_tolerance_;
      return true;
    }
    return false;
  }

  template <class Visit>
  static void for_each_union(const std::vector<std::string>& a, const std::vector<std::string>& b,
                             Visit&& visit) {
    std::set<std::string> all(a.begin(), a.end());
    all.insert(b.begin(), b.end());
    for (const std::string& name : all) {
      visit(name, std::binary_search(a.begin(), a.end(), name),
            std::binary_search(b.begin(), b.end(), name));
    }
  }

  void compare_attributes(const std::string& path_a, const std::string& path_b) {
    const std::string path = shown_path(path_a, path_b);
    for_each_union(
        a_.attribute_names(path_a), b_.attribute_names(path_b),
        [&](const std::string& name, bool in_a, bool in_b) {
          if (ignored_attribute(path_a, name)) return;
          // Numbering by the job's order of points and configurations: two jobs
          // with other values number the same fit or configuration differently.
          if (by_value_ && (name == "sweep_point" || name == "configuration")) return;
          const std::string where = path + " @" + name;
          if (excluded(where)) return;
          if (meaning_recorded_ && path_a == "/" && (name == "job_resolved" || name == "runs")) {
            if (name == "job_resolved") note_job_difference();
            return;
          }
          // Where both files record the job's meaning (job_resolved,
          // compared as a result), its spelling is provenance: the job
          // text and the options as typed (sigma = [10] or [10.0]).
          const bool spelling = meaning_recorded_ && path_a == "/" &&
                                (name == "job" || name == "job_overrides" || name == "job_sweeps");
          if (provenance(path_a, name) || spelling) {
            const auto value = [&](const Hdf5File& f, bool present) {
              return present ? shown(f.read_attribute_values("/", name)) : std::string("(none)");
            };
            std::string va = value(a_, in_a), vb = value(b_, in_b);
            if (va == vb) return;
            if (in_a && in_b) {
              const Hdf5File::Values a_values = a_.read_attribute_values("/", name);
              const Hdf5File::Values b_values = b_.read_attribute_values("/", name);
              if (!a_values.strings.empty() && !b_values.strings.empty()) {
                std::tie(va, vb) =
                    shown_difference(a_values.strings.front(), b_values.strings.front());
              }
            }
            notes_.push_back(name + ": " + va + " vs " + vb);
            if (name == "blas") {
              notes_.push_back(
                  "the files were computed with different BLAS kernels: results are "
                  "bit-identical for one BLAS kernel set (OpenBLAS picks it by the CPU, or "
                  "OPENBLAS_CORETYPE); another can move weights, most in ill-conditioned fits "
                  "(README, \"Same bits\")");
            }
            return;
          }
          ++attributes_;
          if (!in_a || !in_b) {
            differ(where, in_a ? "only in the first file" : "only in the second file");
          } else {
            const Hdf5File::Values va = a_.read_attribute_values(path_a, name);
            const Hdf5File::Values vb = b_.read_attribute_values(path_b, name);
            if (va.type != vb.type || va.shape != vb.shape) {
              differ(where, "attribute differs: type or shape");
            } else if (!(va == vb)) {
              compare_values_of(where, va, vb, "attribute differs");
            }
          }
        });
  }

  // Where both files record the job's meaning, the jobs' differences are
  // provenance: each key that differs, named (the results are compared below).
  void note_job_difference() {
    const auto a = ResolvedConfig::from_text(a_.read_string_attribute("/", "job_resolved"));
    const auto b = ResolvedConfig::from_text(b_.read_string_attribute("/", "job_resolved"));
    if (!a || !b) {
      differ("/ @job_resolved", "not a resolved configuration in one file (damaged)");
      return;
    }
    const std::set<std::string> ignored = {"output.file"};
    const std::vector<std::string> keys =
        a->differences(*b, "the first file", "the second file", ignored);
    if (keys.empty()) return;
    std::string text = "the jobs differ in " + std::to_string(keys.size()) +
                       (keys.size() == 1 ? " key: " : " keys: ");
    for (std::size_t k = 0; k < keys.size() && k < 8; ++k) text += (k ? "; " : "") + keys[k];
    if (keys.size() > 8) text += "; ...";
    notes_.push_back(text);
  }

  bool excluded(const std::string& printed_path) {
    for (const std::string& pattern : exclude_) {
      if (fnmatch(pattern.c_str(), printed_path.c_str(), 0) == 0) {
        ++excluded_;
        return true;
      }
    }
    return false;
  }

  // Two readings of one type and shape that are not identical: a difference
  // (printed with its largest differences) unless within the tolerance.
  void compare_values_of(const std::string& path, const Hdf5File::Values& va,
                         const Hdf5File::Values& vb, const std::string& what) {
    const ValuesDifference difference = compare_values(va, vb, tolerance_);
    largest_absolute_.consider(difference.largest_absolute, path, difference.absolute_at, va.shape);
    largest_relative_.consider(difference.largest_relative, path, difference.relative_at, va.shape);
    if (difference.equal()) {
      ++within_tolerance_;
    } else {
      differ(path, what + ": " + describe_difference(difference, va.shape));
    }
  }

  void differ(const std::string& path, const std::string& why) {
    out_ << "differs: " << path << ": " << why << "\n";
    ++differences_;
  }

  static constexpr std::size_t kMostNotes = 40;
  const Hdf5File& a_;
  const Hdf5File& b_;
  const std::string task_group_;  // "/maze"
  const Tolerance tolerance_;
  const std::vector<std::string> exclude_;
  const bool common_;  // --common: what only one file holds is a note
  std::ostream& out_;
  const bool meaning_recorded_;  // both files hold job_resolved
  // The jobs differ (job_resolved): fits and configurations are matched by their
  // values, and their numbering is no result.
  const bool by_value_;
  std::size_t only_in_one_ = 0;
  std::size_t matched_rows_ = 0;  // rows of fit tables in both files (by value)
  std::size_t differences_ = 0, datasets_ = 0, attributes_ = 0, within_tolerance_ = 0;
  std::size_t excluded_ = 0;
  LargestDifference largest_absolute_, largest_relative_;
  std::vector<std::string> notes_;
};

// "rtol 1e-06, atol 0"
std::string tolerance_text(const Tolerance& tolerance) {
  std::ostringstream out;
  out << "rtol " << tolerance.rtol << ", atol " << tolerance.atol;
  return out.str();
}

Hdf5File open_results_file(const std::filesystem::path& path, std::string& task) {
  std::optional<Hdf5File> file;
  try {
    file.emplace(Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10)));
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  try {
    task = read_results_header(*file).task;
  } catch (const ResultsHeaderError& e) {
    throw UsageError(e.what());
  } catch (const std::runtime_error& e) {  // the root's attributes do not read: damage
    throw UsageError(path.string() +
                     " does not read as a ggk results file (`ggk verify` says whether it is "
                     "damaged): " +
                     e.what());
  }
  return std::move(*file);
}

}  // namespace

bool diff_results(const std::filesystem::path& a, const std::filesystem::path& b, std::ostream& out,
                  const DiffOptions& options) {
  const Tolerance& tolerance = options.tolerance;
  for (const double value : {tolerance.rtol, tolerance.atol}) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      std::ostringstream text;
      text << value;
      throw UsageError("diff: --rtol and --atol must be finite and >= 0, not " + text.str());
    }
  }
  std::string task_a, task_b;
  const Hdf5File file_a = open_results_file(a, task_a);
  const Hdf5File file_b = open_results_file(b, task_b);
  if (task_a != task_b) {
    throw UsageError(a.string() + " holds " + one_line(task_a, 60) + " results and " + b.string() +
                     " " + one_line(task_b, 60) +
                     " results: ggk diff compares two files of one task");
  }
  const auto damaged = [&](const std::runtime_error& e) {  // an object that does not read
    return UsageError("cannot compare " + a.string() + " and " + b.string() + ": " +
                      one_line(e.what()) +
                      " (a damaged file: `ggk verify FILE` lists every damaged object)");
  };
  bool jobs_differ = false;
  try {
    jobs_differ = file_a.has_attribute("/", "job_resolved") &&
                  file_b.has_attribute("/", "job_resolved") &&
                  file_a.read_string_attribute("/", "job_resolved") !=
                      file_b.read_string_attribute("/", "job_resolved");
  } catch (const std::runtime_error& e) {
    throw damaged(e);
  }
  Comparison comparison(file_a, file_b, task_a, options, jobs_differ, out);
  try {
    comparison.compare_object("/", "/");
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw damaged(e);
  }
  for (const std::string& note : comparison.notes()) out << "note: " << note << "\n";
  if (comparison.by_value()) {
    out << "note: the jobs differ: fits matched by their points and run configurations by "
           "their values, not by their numbers\n";
  }
  if (options.common && comparison.only_in_one() > 0) {
    out << "note: " << comparison.only_in_one()
        << " objects or rows only in one file, not compared (--common)\n";
  }
  if (comparison.excluded_count() > 0) {
    out << "note: " << comparison.excluded_count() << " objects excluded (--exclude)\n";
  }
  const std::string largest = comparison.largest_absolute().found
                                  ? "largest absolute difference " +
                                        comparison.largest_absolute().text() +
                                        "; largest relative " + comparison.largest_relative().text()
                                  : "";
  if (options.common && comparison.by_value() && comparison.matched_rows() == 0) {
    out << "different results: the files share no fit (--common compares the fits both "
           "hold)\n";
    return false;
  }
  if (comparison.same()) {
    out << "same results";
    if (!tolerance.exact()) out << " within " << tolerance_text(tolerance);
    out << ": " << comparison.datasets() << " datasets and " << comparison.attributes()
        << " attributes equal (wall-clock times and provenance not compared)\n";
    if (comparison.within_tolerance() > 0) {
      out << comparison.within_tolerance()
          << " of them differ bit for bit, within the tolerance: " << largest << "\n";
    }
  } else {
    if (!largest.empty()) out << largest << "\n";
    out << "different results";
    if (!tolerance.exact()) out << " beyond " << tolerance_text(tolerance);
    out << ": " << comparison.differences() << " of "
        << comparison.datasets() + comparison.attributes() << " objects differ\n";
    if (!options.common && comparison.only_in_one() > 0) {
      out << comparison.only_in_one()
          << " of them are only in one file: --common compares what both hold\n";
    }
  }
  return comparison.same();
}

}  // namespace ggk::engine
