#include "engine/store/metric_specs_table.hpp"

#include <cmath>
#include <stdexcept>

namespace ggk::engine {

namespace {

const std::vector<TableColumn>& metric_spec_columns() {
  static const std::vector<TableColumn> columns = {
      {"name", ColumnType::kString}, {"kind", ColumnType::kString},
      {"unit", ColumnType::kString}, {"meaning", ColumnType::kString},
      {"low", ColumnType::kFloat64}, {"high", ColumnType::kFloat64}};
  return columns;
}

}  // namespace

void write_metric_specs(Hdf5File& file, const std::string& path,
                        std::span<const MetricSpec> specs) {
  std::vector<TableRow> rows;
  rows.reserve(specs.size());
  for (const MetricSpec& spec : specs) {
    rows.push_back({spec.name, std::string(kind_name(spec.kind)), spec.unit, spec.meaning, spec.low,
                    spec.high});
  }
  file.create_table(path, metric_spec_columns());
  file.append_rows(path, rows);
}

std::optional<std::vector<MetricSpec>> read_metric_specs(const Hdf5File& file,
                                                         const std::string& path) {
  if (!file.exists(path)) return std::nullopt;
  const std::vector<TableColumn> columns = file.read_table_columns(path);
  const std::vector<TableColumn>& expected = metric_spec_columns();
  bool same = columns.size() == expected.size();
  for (std::size_t c = 0; same && c < columns.size(); ++c) {
    same = columns[c].name == expected[c].name &&
           (columns[c].type == ColumnType::kString) == (expected[c].type == ColumnType::kString);
  }
  const auto damaged = [&](const std::string& why) {
    return std::runtime_error(file.path().string() + ": " + path + ": " + why);
  };
  if (!same) throw damaged("not a metric_specs table (name, kind, unit, meaning, low, high)");
  std::vector<MetricSpec> specs;
  for (const TableRow& row : file.read_table(path)) {
    MetricSpec spec;
    spec.name = std::get<std::string>(row[0]);
    const std::optional<MetricKind> kind = kind_from_name(std::get<std::string>(row[1]));
    if (!kind) {
      throw damaged("metric '" + spec.name + "' has the unknown kind '" +
                    std::get<std::string>(row[1]) + "' (mean, indicator, fraction)");
    }
    spec.kind = *kind;
    spec.unit = std::get<std::string>(row[2]);
    spec.meaning = std::get<std::string>(row[3]);
    spec.low = std::get<double>(row[4]);
    spec.high = std::get<double>(row[5]);
    if (std::isnan(spec.low) || std::isnan(spec.high) || spec.low > spec.high) {
      throw damaged("metric '" + spec.name + "' has no range [low, high]");
    }
    specs.push_back(std::move(spec));
  }
  return specs;
}

void unite_run_metric_specs(const Hdf5File& file, const std::string& run_group,
                            std::optional<std::vector<MetricSpec>>& declared) {
  if (auto specs = read_metric_specs(file, run_group + "/" + kMetricSpecsTable)) {
    declared = declared ? united_metric_specs(*declared, *specs) : std::move(*specs);
  }
}

MetricSpec legacy_metric_spec(std::string_view metric) {
  const std::string name(metric);
  MetricSpec spec = metric.starts_with("success_from_") ? indicator_metric(name, "")
                    : metric == "success_rate" || metric.ends_with("_fraction")
                        ? fraction_metric(name, "")
                        : mean_metric(name, "", "");
  spec.unit = "";
  return spec;
}

}  // namespace ggk::engine
