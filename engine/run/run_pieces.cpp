#include "engine/run/run_pieces.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

#include "engine/job/sweep.hpp"

namespace ggk::engine {

namespace {

// The unit's points (its own, or every point of its configuration) in groups that
// share a basis table, each ascending, in order of their first point.
std::vector<std::vector<std::int32_t>> table_groups(const Study& study, const WorkUnit& unit) {
  const std::vector<SweepPoint> points = expand_points(study.configurations.at(unit.configuration));
  std::vector<std::int32_t> chosen = unit.points;
  if (chosen.empty()) {
    chosen.resize(points.size());
    std::iota(chosen.begin(), chosen.end(), 0);
  }
  std::vector<std::vector<std::int32_t>> groups;
  std::vector<std::tuple<KernelType, std::int32_t, double>> keys;
  for (const std::int32_t index : chosen) {
    const SweepPoint& point = points.at(static_cast<std::size_t>(index));
    const auto key = std::make_tuple(point.basis, point.kernels, point.sigma);
    const auto found = std::find(keys.begin(), keys.end(), key);
    if (found == keys.end()) {
      keys.push_back(key);
      groups.push_back({index});
    } else {
      groups[static_cast<std::size_t>(found - keys.begin())].push_back(index);
    }
  }
  return groups;
}

// The unit in `count` pieces (fewer when it has fewer groups).
std::vector<WorkUnit> pieces_of(const Study& study, const WorkUnit& unit, std::int32_t count) {
  const std::vector<std::vector<std::int32_t>> groups = table_groups(study, unit);
  const auto k = static_cast<std::size_t>(
      std::min<std::int64_t>(count, static_cast<std::int64_t>(groups.size())));
  if (k <= 1) return {unit};
  std::vector<WorkUnit> pieces(k, WorkUnit{unit.configuration, unit.run});
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::size_t lap = g / k, step = g % k;
    WorkUnit& piece = pieces[lap % 2 == 0 ? step : k - 1 - step];
    piece.points.insert(piece.points.end(), groups[g].begin(), groups[g].end());
  }
  for (std::size_t p = 0; p < k; ++p) {
    std::sort(pieces[p].points.begin(), pieces[p].points.end());
    pieces[p].extends = p > 0;  // the first piece is the run; the others extend it
  }
  return pieces;
}

}  // namespace

PiecedUnits split_tail_runs(const Study& study, std::span<const WorkUnit> units,
                            std::int32_t ranks) {
  PiecedUnits result;
  const auto total = static_cast<std::int64_t>(units.size());
  const std::int64_t tail = ranks > 1 ? total % ranks : 0;
  const std::int64_t first_split = total - tail;
  for (std::int64_t u = 0; u < total; ++u) {
    const WorkUnit& unit = units[static_cast<std::size_t>(u)];
    if (u < first_split || unit.extends) {
      result.units.push_back(unit);
      continue;
    }
    // The ranks shared out among the tail's units, the first ones one more.
    const std::int64_t j = u - first_split;
    const auto count = static_cast<std::int32_t>(ranks / tail + (j < ranks % tail ? 1 : 0));
    std::vector<WorkUnit> pieces = pieces_of(study, unit, count);
    if (pieces.size() > 1) {
      result.pieces[{unit.configuration, unit.run}] = static_cast<std::int32_t>(pieces.size());
    }
    result.units.insert(result.units.end(), pieces.begin(), pieces.end());
  }
  return result;
}

}  // namespace ggk::engine
