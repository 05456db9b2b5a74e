#include "engine/store/results_verify.hpp"

#include <chrono>
#include <functional>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include "engine/job/usage_error.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

constexpr std::size_t kShownProblems = 20;
constexpr std::size_t kReasonLength = 300;

std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  if (text.size() > kReasonLength) text = text.substr(0, kReasonLength) + "...";
  return text;
}

std::string child(const std::string& group, const std::string& name) {
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
            visit(child(path, name), depth + 1);
          }
          return;
        case Hdf5File::ObjectKind::kOther:
          return;
      }
    } catch (const std::runtime_error& e) {
      problems.push_back(path + ": " + one_line(e.what()));
    }
  }
};

}  // namespace

std::optional<std::string> verify_run(const Hdf5File& file, const std::string& task,
                                      std::int32_t run) {
  Walk walk(file);
  walk.visit(run_group(task, run));
  if (walk.problems.empty()) return std::nullopt;
  return walk.problems.front();
}

bool verify_results(const std::filesystem::path& path, std::ostream& out) {
  std::optional<Hdf5File> opened;
  try {
    opened.emplace(Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10)));
  } catch (const std::exception& e) {
    throw UsageError(std::string(e.what()) +
                     " (if it is a results file, its first bytes are damaged)");
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
      complete += static_cast<std::int64_t>(
          complete_runs(file, location, static_cast<std::int32_t>(header.runs)).size());
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
  out << "a damaged run is computed again by `ggk run JOB --resume -o " << path.string() << "`\n";
  return false;
}

}  // namespace ggk::engine
