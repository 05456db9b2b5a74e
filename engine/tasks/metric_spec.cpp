#include "engine/tasks/metric_spec.hpp"

#include <algorithm>
#include <utility>

namespace ggk::engine {

std::string_view kind_name(MetricKind kind) {
  switch (kind) {
    case MetricKind::kIndicator:
      return "indicator";
    case MetricKind::kFraction:
      return "fraction";
    case MetricKind::kMean:
      break;
  }
  return "mean";
}

std::optional<MetricKind> kind_from_name(std::string_view name) {
  for (const MetricKind kind : {MetricKind::kMean, MetricKind::kIndicator, MetricKind::kFraction}) {
    if (kind_name(kind) == name) return kind;
  }
  return std::nullopt;
}

MetricSpec mean_metric(std::string name, std::string unit, std::string meaning, double low,
                       double high) {
  MetricSpec spec;
  spec.name = std::move(name);
  spec.unit = std::move(unit);
  spec.meaning = std::move(meaning);
  spec.low = low;
  spec.high = high;
  return spec;
}

MetricSpec fraction_metric(std::string name, std::string meaning) {
  MetricSpec spec = mean_metric(std::move(name), "1", std::move(meaning), 0.0, 1.0);
  spec.kind = MetricKind::kFraction;
  return spec;
}

MetricSpec indicator_metric(std::string name, std::string meaning) {
  MetricSpec spec = mean_metric(std::move(name), "1", std::move(meaning), 0.0, 1.0);
  spec.kind = MetricKind::kIndicator;
  return spec;
}

MetricSpec tested(MetricSpec spec) {
  spec.tested = true;
  return spec;
}

MetricSpec integer(MetricSpec spec) {
  spec.integer = true;
  return spec;
}

std::vector<std::string> integer_metric_names(std::span<const MetricSpec> specs) {
  std::vector<std::string> names;
  for (const MetricSpec& spec : specs) {
    if (spec.integer) names.push_back(spec.name);
  }
  return names;
}

const MetricSpec* find_metric_spec(std::span<const MetricSpec> specs, std::string_view metric) {
  for (const MetricSpec& spec : specs) {
    if (spec.name == metric) return &spec;
  }
  return nullptr;
}

MetricKind declared_kind(std::span<const MetricSpec> specs, std::string_view metric) {
  const MetricSpec* spec = find_metric_spec(specs, metric);
  return spec != nullptr ? spec->kind : MetricKind::kMean;
}

MetricSpec fit_seconds_spec() {
  return mean_metric("fit_seconds", "s",
                     "wall time of the fit (the only number that differs between machines)", 0.0);
}

std::vector<MetricSpec> united_metric_specs(std::span<const MetricSpec> a,
                                            std::span<const MetricSpec> b) {
  std::vector<MetricSpec> united(a.begin(), a.end());
  for (const MetricSpec& spec : b) {
    const auto at = std::find_if(united.begin(), united.end(),
                                 [&](const MetricSpec& s) { return s.name == spec.name; });
    if (at == united.end()) {
      united.push_back(spec);
      continue;
    }
    at->low = std::min(at->low, spec.low);
    at->high = std::max(at->high, spec.high);
  }
  return united;
}

}  // namespace ggk::engine
