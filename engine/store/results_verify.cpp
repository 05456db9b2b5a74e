#include "engine/store/results_verify.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <new>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include "engine/hdf5/allocation_failures.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/one_line.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_digest.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kShownProblems = 20;

std::string child_path(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

// A results file is a tree of groups no deeper than this; a deeper one is
// damage (or made to never end), not results.
constexpr int kMaxDepth = 32;

struct Walk {
  explicit Walk(const Hdf5File& walked) : file(walked) {}
  const Hdf5File& file;
  std::int64_t datasets = 0;
  std::int64_t attributes = 0;
  std::vector<std::string> problems;
  std::function<bool(const std::string&)> skip = [](const std::string&) { return false; };
  std::set<std::uint64_t> seen;  // object addresses: each object is read once

  // Reads `path` and everything below it; records what fails and goes on. A
  // results file holds hard links only, each object once, in a shallow tree:
  // a soft or external link, an object reached twice (a link to an ancestor)
  // or a tree deeper than kMaxDepth is a problem, never followed.
  void visit(const std::string& path, int depth = 0) {
    if (skip(path)) return;
    try {
      const std::optional<std::uint64_t> address = file.hard_link_address(path);
      if (!address) {
        problems.push_back(path + ": a soft or external link (a results file holds none)");
        return;
      }
      if (!seen.insert(*address).second) {
        problems.push_back(path +
                           ": an object linked a second time (a results file names "
                           "each object once)");
        return;
      }
      if (depth > kMaxDepth) {
        problems.push_back(path + ": groups nested deeper than " + std::to_string(kMaxDepth) +
                           " (a results file's are not)");
        return;
      }
      for (const std::string& name : file.attribute_names(path)) {
        (void)file.read_attribute_values(path, name);
        ++attributes;
      }
      switch (file.object_kind(path)) {
        case Hdf5File::ObjectKind::kDataset:
          (void)file.read_values(path);
          ++datasets;
          return;
        case Hdf5File::ObjectKind::kGroup:
          for (const std::string& name : file.member_names(path)) {
            visit(child_path(path, name), depth + 1);
          }
          return;
        case Hdf5File::ObjectKind::kOther:
          return;
      }
    } catch (const std::runtime_error& e) {
      problems.push_back(path + ": " + one_line(e.what()));
    } catch (const std::bad_alloc&) {
      // Within the room a reader allows itself, a size no file of this size
      // holds; beyond it, the memory ran out (hdf5/allocation_failures.hpp).
      if (allocation_failures() != AllocationFailure::kDamage) throw;
      problems.push_back(
          path +
          ": claims more memory than a file of this size can hold (a size in it is damaged)");
    }
  }
};

bool is_dataset(const Hdf5File& file, const std::string& path) {
  return file.exists(path) && file.object_kind(path) == Hdf5File::ObjectKind::kDataset;
}

bool is_group(const Hdf5File& file, const std::string& path) {
  return file.exists(path) && file.object_kind(path) == Hdf5File::ObjectKind::kGroup;
}

std::optional<std::string> shape_problem(const Hdf5File& file, const std::string& group) {
  for (const char* name : {"samples/observations", "samples/actions", "samples/rewards",
                           "samples/next_observations", "samples/terminals"}) {
    if (!is_dataset(file, group + "/" + name)) return group + "/" + name + ": missing";
  }
  // One transition per row: three vectors and two matrices of one length.
  const std::vector<std::int64_t> actions = file.dataset_shape(group + "/samples/actions");
  if (actions.size() != 1) return group + "/samples/actions: not a vector";
  for (const char* name : {"samples/rewards", "samples/terminals"}) {
    if (file.dataset_shape(group + "/" + name) != actions) {
      return group + "/" + name + ": not one value per transition";
    }
  }
  for (const char* name : {"samples/observations", "samples/next_observations"}) {
    const std::vector<std::int64_t> shape = file.dataset_shape(group + "/" + name);
    if (shape.size() != 2 || shape[0] != actions[0]) {
      return group + "/" + name + ": not one row per transition";
    }
  }
  if (!is_group(file, group + "/graph")) return group + "/graph: missing";
  const std::string table = group + "/fit_metrics";
  if (!is_dataset(file, table)) return table + ": missing";
  const std::vector<TableColumn> columns = file.read_table_columns(table);
  static const std::vector<std::pair<std::string, ColumnType>> kFixed = {
      {"run", ColumnType::kInt32},      {"sweep_point", ColumnType::kInt32},
      {"basis", ColumnType::kString},   {"kernels", ColumnType::kInt32},
      {"sigma", ColumnType::kFloat64},  {"solver", ColumnType::kString},
      {"lambda", ColumnType::kFloat64}, {"status", ColumnType::kString}};
  for (const auto& fixed : kFixed) {
    const auto column = std::find_if(columns.begin(), columns.end(),
                                     [&](const TableColumn& c) { return c.name == fixed.first; });
    if (column == columns.end() || column->type != fixed.second) {
      return table + ": no column '" + fixed.first + "' of the type every results file has";
    }
  }
  std::size_t fits = 0;
  if (is_group(file, group + "/fits")) {
    for (const std::string& basis : file.member_names(group + "/fits")) {
      if (!is_group(file, group + "/fits/" + basis)) return group + "/fits/" + basis + ": no group";
      fits += file.member_names(group + "/fits/" + basis).size();
    }
  }
  const std::size_t rows = file.read_table(table).size();
  if (fits != rows) {
    return group + "/fits: " + std::to_string(fits) + " fit groups for the " +
           std::to_string(rows) + " rows of fit_metrics (a run holds one per row)";
  }
  return std::nullopt;
}

// Empty when the run group has no digest (written before there was one) or
// its digest matches what the group holds now (run_digest.hpp): the content
// digest, or in a run written before it, the metadata digest.
std::optional<std::string> digest_problem(const Hdf5File& file, const std::string& group) {
  try {
    for (const auto& [name, scope] :
         {std::pair{kRunDigestAttribute, DigestScope::kContent},
          std::pair{kMetadataDigestAttribute, DigestScope::kMetadata}}) {
      if (!file.has_attribute(group, name)) continue;
      if (static_cast<std::uint64_t>(file.read_int64_attribute(group, name)) !=
          run_digest(file, group, scope)) {
        return group + ": its " +
               (scope == DigestScope::kContent ? "names, attributes, shapes or values"
                                               : "names, attributes or shapes") +
               " differ from its digest (damage that no HDF5 checksum covers)";
      }
      break;  // the newer digest covers what the older would
    }
  } catch (const std::runtime_error& e) {
    return group + ": " + one_line(e.what());
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> run_shape_problem(const Hdf5File& file, const std::string& task,
                                             std::int32_t run) {
  try {
    return shape_problem(file, run_group(task, run));
  } catch (const std::runtime_error& e) {
    return run_group(task, run) + ": " + one_line(e.what());
  }
}

std::optional<std::string> verify_run(const Hdf5File& file, const std::string& task,
                                      std::int32_t run) {
  Walk walk(file);
  const std::string group = run_group(task, run);
  walk.visit(group);
  if (!walk.problems.empty()) return walk.problems.front();
  if (auto problem = run_shape_problem(file, task, run)) return problem;
  return digest_problem(file, group);
}

std::optional<std::string> verify_beyond_runs(const Hdf5File& file) {
  Walk walk(file);
  walk.skip = [](const std::string& object) {
    const std::size_t last = object.rfind('/');
    if (last == 0) return object.size() > 1 && is_scratch(std::string_view(object).substr(1));
    return std::string_view(object).substr(last + 1).starts_with("run_");
  };
  walk.visit("/");
  if (walk.problems.empty()) return std::nullopt;
  return walk.problems.front();
}

bool verify_results(const std::filesystem::path& path, std::ostream& out) {
  std::optional<Hdf5File> opened;
  try {
    opened.emplace(Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10)));
  } catch (const std::exception& e) {
    std::error_code error;
    throw UsageError(std::string(e.what()) +
                     (fs::is_regular_file(path, error)
                          ? " (if it is a results file, its first bytes are damaged)"
                          : ""));
  }
  const Hdf5File& file = *opened;
  Walk walk(file);
  walk.skip = [](const std::string& object) {
    return object.size() > 1 && object.find('/', 1) == std::string::npos &&
           is_scratch(std::string_view(object).substr(1));
  };
  walk.visit("/");
  std::int64_t runs = -1, complete = 0;
  try {
    const ResultsHeader header = read_results_header(file);
    const std::vector<std::string> locations = runs_locations(file, header.task);
    for (const std::string& location : locations) {
      for (const std::int32_t run :
           complete_runs(file, location, static_cast<std::int32_t>(header.runs))) {
        ++complete;
        if (walk.problems.empty() || walk.problems.size() < kShownProblems) {
          // A run whose objects do not all read is named by them already: its
          // digest, which reads them too, would only repeat it.
          const std::string group = run_group(location, run);
          const bool named = std::any_of(
              walk.problems.begin(), walk.problems.end(),
              [&](const std::string& problem) { return problem.starts_with(group + "/"); });
          if (auto problem = run_shape_problem(file, location, run)) {
            walk.problems.push_back(*problem);
          } else if (!named) {
            if (auto changed = digest_problem(file, group)) walk.problems.push_back(*changed);
          }
        }
      }
    }
    runs = header.runs *
           static_cast<std::int64_t>(locations.size());  // a study's: every configuration's
  } catch (const ResultsHeaderError& e) {
    if (walk.problems.empty()) throw UsageError(one_line(e.what()));
  } catch (const std::runtime_error& e) {
    if (walk.problems.empty()) {
      throw UsageError(path.string() + " is not a ggk results file (" + one_line(e.what()) + ")");
    }
  }
  out << path.string() << ": read " << walk.datasets << " datasets and " << walk.attributes
      << " attributes";
  if (runs >= 0) out << "; runs: " << complete << " of " << runs << " complete";
  out << "\n";
  if (walk.problems.empty()) {
    out << "ok: every checksum matches, every object reads\n";
    return true;
  }
  out << "DAMAGED: " << walk.problems.size() << " objects do not read:\n";
  for (std::size_t i = 0; i < walk.problems.size() && i < kShownProblems; ++i) {
    out << "  " << walk.problems[i] << "\n";
  }
  if (walk.problems.size() > kShownProblems) {
    out << "  ... and " << walk.problems.size() - kShownProblems << " more\n";
  }
  const auto outside = std::find_if(
      walk.problems.begin(), walk.problems.end(),
      [](const std::string& problem) { return problem.find("/run_") == std::string::npos; });
  if (outside == walk.problems.end()) {
    out << "a damaged run is computed again by `ggk run JOB --resume -o " << path.string() << "`\n";
  } else {
    const fs::path kept =
        path.parent_path() / (path.stem().string() + ".damaged" + path.extension().string());
    out << "the damage is not only in runs (" << outside->substr(0, outside->find(':'))
        << "): `ggk run JOB --resume -o " << path.string()
        << "` copies the runs that read back whole into a new file that takes its name, "
           "computes the rest, and keeps this file as "
        << kept.string() << " if a run of it could not be copied\n";
  }
  return false;
}

}  // namespace ggk::engine
