#include "engine/store/results_diff.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
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
  Comparison(const Hdf5File& a, const Hdf5File& b, const DiffOptions& options, std::ostream& out)
      : a_(a),
        b_(b),
        tolerance_(options.tolerance),
        exclude_(options.exclude),
        out_(out),
        meaning_recorded_(a.has_attribute("/", "job_resolved") &&
                          b.has_attribute("/", "job_resolved")) {}

  void compare_object(const std::string& path) {
    if (excluded(path)) return;
    compare_attributes(path);
    const Hdf5File::ObjectKind kind_a = a_.object_kind(path), kind_b = b_.object_kind(path);
    if (kind_a != kind_b) {
      differ(path, "a group in one file, a dataset in the other");
      return;
    }
    if (kind_a == Hdf5File::ObjectKind::kDataset) {
      ++datasets_;
      const Hdf5File::Values va = a_.read_values(path, kWallClockColumns);
      const Hdf5File::Values vb = b_.read_values(path, kWallClockColumns);
      if (va.type != vb.type || va.shape != vb.shape) {
        differ(path, "type or shape differs");
      } else if (!(va == vb)) {
        compare_values_of(path, va, vb, "values differ");
      }
      return;
    }
    if (kind_a != Hdf5File::ObjectKind::kGroup) return;
    std::vector<std::string> names_a = a_.member_names(path), names_b = b_.member_names(path);
    if (path == "/") {
      std::erase_if(names_a, is_scratch);
      std::erase_if(names_b, is_scratch);
    }
    for_each_union(names_a, names_b, [&](const std::string& name, bool in_a, bool in_b) {
      const std::string member = child(path, name);
      if (in_a && in_b) {
        compare_object(member);
      } else {
        differ(member, in_a ? "only in the first file" : "only in the second file");
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

 private:
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

  void compare_attributes(const std::string& path) {
    for_each_union(
        a_.attribute_names(path), b_.attribute_names(path),
        [&](const std::string& name, bool in_a, bool in_b) {
          if (ignored_attribute(path, name)) return;
          const std::string where = path + " @" + name;
          if (excluded(where)) return;
          // Where both files record the job's meaning (job_resolved,
          // compared as a result), its spelling is provenance: the job
          // text and the options as typed (sigma = [10] or [10.0]).
          const bool spelling = meaning_recorded_ && path == "/" &&
                                (name == "job" || name == "job_overrides" || name == "job_sweeps");
          if (provenance(path, name) || spelling) {
            const auto value = [&](const Hdf5File& f, bool present) {
              return present ? shown(f.read_attribute_values(path, name)) : std::string("(none)");
            };
            std::string va = value(a_, in_a), vb = value(b_, in_b);
            if (va == vb) return;
            if (in_a && in_b) {
              const Hdf5File::Values a_values = a_.read_attribute_values(path, name);
              const Hdf5File::Values b_values = b_.read_attribute_values(path, name);
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
            const Hdf5File::Values va = a_.read_attribute_values(path, name);
            const Hdf5File::Values vb = b_.read_attribute_values(path, name);
            if (va.type != vb.type || va.shape != vb.shape) {
              differ(where, "attribute differs: type or shape");
            } else if (!(va == vb)) {
              compare_values_of(where, va, vb, "attribute differs");
            }
          }
        });
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

  const Hdf5File& a_;
  const Hdf5File& b_;
  const Tolerance tolerance_;
  const std::vector<std::string> exclude_;
  std::ostream& out_;
  const bool meaning_recorded_;  // both files hold job_resolved
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
  Comparison comparison(file_a, file_b, options, out);
  try {
    comparison.compare_object("/");
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {  // an object that does not read: damage
    throw UsageError("cannot compare " + a.string() + " and " + b.string() + ": " +
                     one_line(e.what()) +
                     " (a damaged file: `ggk verify FILE` lists every damaged object)");
  }
  for (const std::string& note : comparison.notes()) out << "note: " << note << "\n";
  if (comparison.excluded_count() > 0) {
    out << "note: " << comparison.excluded_count() << " objects excluded (--exclude)\n";
  }
  const std::string largest = comparison.largest_absolute().found
                                  ? "largest absolute difference " +
                                        comparison.largest_absolute().text() +
                                        "; largest relative " + comparison.largest_relative().text()
                                  : "";
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
  }
  return comparison.same();
}

}  // namespace ggk::engine
