#include "engine/store/results_diff.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

constexpr std::size_t kMaxReported = 10;
const std::array<std::string, 1> kWallClockColumns = {"fit_seconds"};

bool ignored_attribute(const std::string& object, const std::string& name) {
  if (name == "fit_seconds") return true;
  return object == "/" && root_attribute_role(name) == RootAttributeRole::kWallClock;
}
bool provenance(const std::string& object, const std::string& name) {
  return object == "/" && root_attribute_role(name) == RootAttributeRole::kProvenance;
}

std::string child(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

// A short, readable form of an attribute for notes (strings and numbers).
std::string shown(const Hdf5File::Values& v) {
  if (!v.strings.empty()) {
    std::string text = v.strings.front();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return "\"" + text + "\"";
  }
  return v.type + " value";
}

class Comparison {
 public:
  Comparison(const Hdf5File& a, const Hdf5File& b, std::ostream& out) : a_(a), b_(b), out_(out) {}

  void compare_object(const std::string& path) {
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
        differ(path, "values differ");
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
    for_each_union(a_.attribute_names(path), b_.attribute_names(path),
                   [&](const std::string& name, bool in_a, bool in_b) {
                     if (ignored_attribute(path, name)) return;
                     const std::string where = path + " @" + name;
                     if (provenance(path, name)) {
                       const auto value = [&](const Hdf5File& f, bool present) {
                         return present ? shown(f.read_attribute_values(path, name))
                                        : std::string("(none)");
                       };
                       const std::string va = value(a_, in_a), vb = value(b_, in_b);
                       if (va != vb) notes_.push_back(name + ": " + va + " vs " + vb);
                       return;
                     }
                     ++attributes_;
                     if (!in_a || !in_b) {
                       differ(where, in_a ? "only in the first file" : "only in the second file");
                     } else if (!(a_.read_attribute_values(path, name) ==
                                  b_.read_attribute_values(path, name))) {
                       differ(where, "attribute differs");
                     }
                   });
  }

  void differ(const std::string& path, const std::string& why) {
    if (differences_ < kMaxReported) out_ << "differs: " << path << ": " << why << "\n";
    ++differences_;
  }

  const Hdf5File& a_;
  const Hdf5File& b_;
  std::ostream& out_;
  std::size_t differences_ = 0, datasets_ = 0, attributes_ = 0;
  std::vector<std::string> notes_;
};

Hdf5File open_results_file(const std::filesystem::path& path) {
  std::optional<Hdf5File> file;
  try {
    file.emplace(Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10)));
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  try {
    (void)read_results_header(*file);
  } catch (const ResultsHeaderError& e) {
    throw UsageError(e.what());
  }
  return std::move(*file);
}

}  // namespace

bool diff_results(const std::filesystem::path& a, const std::filesystem::path& b,
                  std::ostream& out) {
  const Hdf5File file_a = open_results_file(a);
  const Hdf5File file_b = open_results_file(b);
  Comparison comparison(file_a, file_b, out);
  comparison.compare_object("/");
  for (const std::string& note : comparison.notes()) out << "note: " << note << "\n";
  if (comparison.same()) {
    out << "same results: " << comparison.datasets() << " datasets and " << comparison.attributes()
        << " attributes equal (wall-clock times and provenance not compared)\n";
  } else {
    if (comparison.differences() > kMaxReported) {
      out << "... and " << comparison.differences() - kMaxReported << " more\n";
    }
    out << "different results: " << comparison.differences() << " of "
        << comparison.datasets() + comparison.attributes() << " objects differ\n";
  }
  return comparison.same();
}

}  // namespace ggk::engine
