#include "engine/run/adaptive_shards.hpp"

#include <string>
#include <vector>

#include "engine/job/usage_error.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

ResultsContents planned_contents(const Study& study) {
  ResultsContents planned;
  planned.configurations = study.configurations.size();
  for (std::size_t c = 0; c < study.configurations.size(); ++c) {
    for (const SweepPoint& point : expand_points(study.configurations[c])) {
      if (planned.axis_names.empty()) planned.axis_names = point_axis_names(point);
      FitRow fit;
      fit.configuration = static_cast<std::int32_t>(c);
      fit.point = (static_cast<std::int64_t>(c) << 32) + point.index;
      for (const TableValue& value : point_axis_cells(point)) fit.key.push_back(as_text(value));
      planned.fits.push_back(std::move(fit));
    }
  }
  return planned;
}

AdaptivePlan adaptive_plan_of(const Study& study) {
  return adaptive_plan(planned_contents(study), *study.job().adaptive,
                       static_cast<std::int32_t>(study.configurations.size()));
}

void select_adaptive_shard(const Shard& shard, const Study& study, RunOptions& options) {
  const AdaptivePlan plan = adaptive_plan_of(study);
  const std::string named =
      "--shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count);
  if (shard.count > plan.groups) {
    throw UsageError(named + ": the adaptive study's " +
                     std::to_string(study.configurations.size()) + " run configurations form " +
                     std::to_string(plan.groups) +
                     " groups its rule never links (configurations a cell compares stay in one "
                     "shard), fewer than " +
                     std::to_string(shard.count) + " shards: use at most " +
                     std::to_string(plan.groups) + " shards");
  }
  const RunRange groups = shard_range(shard, plan.groups);
  ConfigurationShard selected{shard.index, shard.count, {}};
  for (std::size_t c = 0; c < plan.group_of.size(); ++c) {
    if (plan.group_of[c] >= groups.first && plan.group_of[c] < groups.last) {
      selected.scope.configurations.push_back(static_cast<std::int32_t>(c));
    }
  }
  selected.scope.cells = plan.cells;
  options.configuration_shard = std::move(selected);
  options.output =
      shard_output(options.output.empty() ? study.job().output.file : options.output, shard);
}

}  // namespace ggk::engine
