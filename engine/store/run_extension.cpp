#include "engine/store/run_extension.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/store/metric_specs_table.hpp"
#include "engine/store/run_digest.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

// The fit groups below a run's `fits` group: "<basis>/<name>" (fit_group_name).
std::vector<std::string> fit_groups_of(const Hdf5File& file, const std::string& run) {
  std::vector<std::string> names;
  const std::string fits = run + "/fits";
  if (!file.exists(fits)) return names;
  for (const std::string& basis : file.member_names(fits)) {
    for (const std::string& name : file.member_names(fits + "/" + basis)) {
      names.push_back(basis + "/" + name);
    }
  }
  return names;
}

std::size_t column_index(const std::vector<TableColumn>& columns, const std::string& name,
                         const std::string& table) {
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].name == name) return c;
  }
  throw std::runtime_error(table + " has no column " + name);
}

// Adds the old run's fits to the staged extension: each old fit group copied
// with its new index, fit_metrics holding every fit's row in point order, the
// digest set again.
void add_old_fits(Hdf5File& file, const std::string& old_run, const std::string& staging,
                  std::span<const SweepPoint> points) {
  const std::string what = "cannot grow " + old_run.substr(1) + ": ";
  std::map<std::string, std::int32_t> index_of;  // fit group name -> its point's index
  for (const SweepPoint& point : points) index_of.emplace(fit_group_name(point), point.index);

  std::map<std::int64_t, std::int32_t> renumbered;  // old index -> new
  for (const std::string& name : fit_groups_of(file, old_run)) {
    const auto found = index_of.find(name);
    if (found == index_of.end()) {
      throw std::runtime_error(what + "its fit " + name + " is no sweep point of the job");
    }
    const std::string source = old_run + "/fits/" + name;
    const std::string target = staging + "/fits/" + name;
    if (file.exists(target)) {
      throw std::runtime_error(what + "its fit " + name + " was computed again");
    }
    renumbered[file.read_int64_attribute(source, "sweep_point")] = found->second;
    file.copy_from(file, source, target);
    file.remove_attribute(target, "sweep_point");
    file.write_int64_attribute(target, "sweep_point", found->second);
  }

  const std::string old_table = old_run + "/fit_metrics";
  const std::string new_table = staging + "/fit_metrics";
  // An extension by no fit (it renumbers the old ones) has a table with no
  // metric columns: the old table's are the run's.
  const bool new_fits = !file.read_table(new_table).empty();
  const std::string described = new_fits ? new_table : old_table;
  const std::vector<TableColumn> columns = file.read_table_columns(described);
  if (file.read_table_columns(old_table) != columns) {
    throw std::runtime_error(what + "its fit_metrics columns differ from the job's");
  }
  const std::size_t point_column = column_index(columns, "sweep_point", new_table);
  std::vector<TableRow> rows = new_fits ? file.read_table(new_table) : std::vector<TableRow>{};
  for (TableRow row : file.read_table(old_table)) {
    const auto found = renumbered.find(std::get<std::int32_t>(row[point_column]));
    if (found == renumbered.end()) {
      throw std::runtime_error(what + "a row of its fit_metrics belongs to no fit group");
    }
    row[point_column] = found->second;
    rows.push_back(std::move(row));
  }
  std::sort(rows.begin(), rows.end(), [&](const TableRow& a, const TableRow& b) {
    return std::get<std::int32_t>(a[point_column]) < std::get<std::int32_t>(b[point_column]);
  });
  // The table again, with every row, and its attributes (strings: dims, units,
  // description, study_axes).
  std::vector<std::pair<std::string, std::string>> attributes;
  for (const std::string& name : file.attribute_names(described)) {
    attributes.emplace_back(name, file.read_string_attribute(described, name));
  }
  file.remove(new_table);
  file.create_table(new_table, columns);
  file.append_rows(new_table, rows);
  for (const auto& [name, text] : attributes) file.write_string_attribute(new_table, name, text);
  if (!new_fits) {  // the metrics' declarations, which the staged run derived from no fit
    const std::string specs = "/" + std::string(kMetricSpecsTable);
    if (file.exists(staging + specs)) file.remove(staging + specs);
    if (file.exists(old_run + specs)) file.copy_from(file, old_run + specs, staging + specs);
  }

  file.remove_attribute(staging, kRunDigestAttribute);  // the extension's alone
  file.write_int64_attribute(staging, kRunDigestAttribute,
                             static_cast<std::int64_t>(run_digest(file, staging)));
  file.flush();
}

}  // namespace

std::vector<std::int32_t> lacking_points(const Hdf5File& file, const std::string& location,
                                         std::int32_t run, std::span<const SweepPoint> points) {
  const std::string group = run_group(location, run);
  std::map<std::string, std::int32_t> index_of;
  for (const SweepPoint& point : points) index_of.emplace(fit_group_name(point), point.index);
  for (const std::string& name : fit_groups_of(file, group)) {
    if (index_of.erase(name) == 0) {
      throw std::runtime_error(group.substr(1) + " holds the fit " + name +
                               ", which is no sweep point of the job");
    }
  }
  std::vector<std::int32_t> lacking;
  for (const auto& [name, index] : index_of) lacking.push_back(index);
  std::sort(lacking.begin(), lacking.end());
  return lacking;
}

void extend_run(Hdf5File& file, const JobSpec& job, const RunRecord& extension,
                std::span<const SweepPoint> points) {
  const std::string location = runs_location(job);
  const std::string staging = stage_run(file, job, extension);
  add_old_fits(file, run_group(location, extension.run), staging, points);
  commit_staged_run(file, location, extension.run);
}

void extend_run_from_image(Hdf5File& file, const JobSpec& job, std::int32_t run,
                           std::span<const unsigned char> image,
                           std::span<const SweepPoint> points) {
  const Hdf5File source = Hdf5File::open_image(image, "run_" + std::to_string(run));
  const std::string location = runs_location(job);
  if (!run_is_complete(source, location, run)) {
    throw std::runtime_error("the image sent for run " + std::to_string(run) +
                             " does not hold that run complete");
  }
  const std::string staging = staging_group(location, run);
  if (file.exists(staging)) file.detach(staging);  // a killed writer's: never read
  file.copy_from(source, run_group(location, run), staging);
  file.remove_attribute(staging, "complete");  // marked when it is in place
  add_old_fits(file, run_group(location, run), staging, points);
  commit_staged_run(file, location, run);
}

void write_run_pieces(Hdf5File& file, const JobSpec& job, std::int32_t run,
                      std::span<const RunPiece> pieces, std::span<const SweepPoint> points) {
  const std::string what = "run " + std::to_string(run) + ", computed in pieces: ";
  const auto first = std::find_if(pieces.begin(), pieces.end(),
                                  [](const RunPiece& piece) { return !piece.extension; });
  if (first == pieces.end() ||
      std::count_if(pieces.begin(), pieces.end(),
                    [](const RunPiece& piece) { return !piece.extension; }) != 1) {
    throw std::runtime_error(what + "not one first piece and its extensions");
  }
  Hdf5File assembled = Hdf5File::create_in_memory("run_" + std::to_string(run) + "_pieces");
  assembled.set_gzip_level(job.output.compression);
  auto add = [&](const RunPiece& piece) {
    if (piece.record != nullptr && piece.record->run != run) {
      throw std::runtime_error(what + "a piece of run " + std::to_string(piece.record->run));
    }
    if (piece.record != nullptr) {
      piece.extension ? extend_run(assembled, job, *piece.record, points)
                      : write_run(assembled, job, *piece.record);
    } else if (piece.bytes != nullptr && piece.offset <= piece.bytes->size()) {
      const std::span<const unsigned char> image(piece.bytes->data() + piece.offset,
                                                 piece.bytes->size() - piece.offset);
      piece.extension ? extend_run_from_image(assembled, job, run, image, points)
                      : write_run_image(assembled, job, run, image);
    } else {
      throw std::runtime_error(what + "a piece holds neither a run nor its image");
    }
  };
  add(*first);
  for (const RunPiece& piece : pieces) {
    if (piece.extension) add(piece);
  }
  write_run_image(file, job, run, assembled.file_image());
}

}  // namespace ggk::engine
