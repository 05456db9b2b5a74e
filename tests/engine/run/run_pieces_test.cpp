#include "engine/run/run_pieces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

// A maze study of `runs` runs whose fits are 2 bases x 3 kernel counts x 2
// solvers: 6 groups sharing a basis table, 12 points.
Study pieces_study(int runs) {
  const char* source = std::getenv("GGK_SOURCE_DIR");
  const std::filesystem::path jobs =
      std::filesystem::path(source != nullptr ? source : ".") / "jobs";
  JobLoadOptions options;
  options.check_output = false;
  const std::string text = "name = \"pieces\"\ntask = \"maze\"\nruns = " + std::to_string(runs) +
                           "\nseed = 7\n[sweep]\nbasis = [\"ggk\", \"ogk\"]\n"
                           "kernels = [4, 8, 12]\nsigma = [10.0]\nsolver = [\"brm\", \"lstdq\"]\n"
                           "[maze]\nmap_file = \"maps/four-rooms.txt\"\nseries = 4\n";
  return parse_study(text, jobs / "pieces.toml", task_tables(), options);
}

std::vector<WorkUnit> whole_runs(int runs) {
  std::vector<WorkUnit> units;
  for (int run = 0; run < runs; ++run) units.push_back({0, run});
  return units;
}

// The pieces of (configuration 0, run) in queue order.
std::vector<WorkUnit> pieces_of_run(const PiecedUnits& pieced, int run) {
  std::vector<WorkUnit> pieces;
  for (const WorkUnit& unit : pieced.units) {
    if (unit.run == run) pieces.push_back(unit);
  }
  return pieces;
}

TEST(RunPieces, UnitsThatFillTheirRoundsStayWhole) {
  const Study study = pieces_study(6);
  for (const int ranks : {1, 2, 3, 6}) {
    const PiecedUnits pieced = split_tail_runs(study, whole_runs(6), ranks);
    EXPECT_EQ(pieced.units, whole_runs(6)) << ranks << " ranks";
    EXPECT_TRUE(pieced.pieces.empty()) << ranks << " ranks";
  }
}

TEST(RunPieces, TheLastRoundsUnitsShareTheRanks) {
  // 6 runs on 4 ranks: runs 0-3 whole, then runs 4 and 5 in 2 pieces each.
  const Study study = pieces_study(6);
  const PiecedUnits pieced = split_tail_runs(study, whole_runs(6), 4);
  const std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> expected{{{0, 4}, 2},
                                                                               {{0, 5}, 2}};
  EXPECT_EQ(pieced.pieces, expected);
  ASSERT_EQ(pieced.units.size(), 8u);
  for (int run = 0; run < 4; ++run) EXPECT_EQ(pieced.units[run], (WorkUnit{0, run}));
  // 2 runs on 5 ranks: the first gets 3 pieces, the second 2.
  const PiecedUnits two = split_tail_runs(study, whole_runs(2), 5);
  EXPECT_EQ(pieces_of_run(two, 0).size(), 3u);
  EXPECT_EQ(pieces_of_run(two, 1).size(), 2u);
  // One run on 16 ranks: no more pieces than its 6 groups.
  EXPECT_EQ(pieces_of_run(split_tail_runs(study, whole_runs(1), 16), 0).size(), 6u);
}

TEST(RunPieces, APiecesPointsAreWholeTableGroupsAndThePiecesCoverTheRunOnce) {
  const Study study = pieces_study(1);
  const std::vector<SweepPoint> points = expand_points(study.configurations.front());
  ASSERT_EQ(points.size(), 12u);
  for (const int ranks : {2, 3, 4, 6}) {
    const std::vector<WorkUnit> pieces = split_tail_runs(study, whole_runs(1), ranks).units;
    ASSERT_EQ(pieces.size(), static_cast<std::size_t>(ranks));
    std::vector<std::int32_t> covered;
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      // The first piece is the run, the others extend it.
      EXPECT_EQ(pieces[p].extends, p > 0);
      EXPECT_TRUE(std::is_sorted(pieces[p].points.begin(), pieces[p].points.end()));
      ASSERT_FALSE(pieces[p].points.empty());
      // Both solvers of a (basis, kernels, sigma) are in the same piece.
      for (const std::int32_t index : pieces[p].points) {
        for (const SweepPoint& other : points) {
          if (other.basis == points[index].basis && other.kernels == points[index].kernels) {
            EXPECT_NE(std::find(pieces[p].points.begin(), pieces[p].points.end(), other.index),
                      pieces[p].points.end())
                << ranks << " ranks: point " << index << " without " << other.index;
          }
        }
      }
      covered.insert(covered.end(), pieces[p].points.begin(), pieces[p].points.end());
    }
    std::sort(covered.begin(), covered.end());
    std::vector<std::int32_t> every(points.size());
    std::iota(every.begin(), every.end(), 0);
    EXPECT_EQ(covered, every) << ranks << " ranks";
  }
  // Snake order over 4 pieces: groups 0..5 (ggk 4, 8, 12, ogk 4, 8, 12) go to
  // pieces 0 1 2 3 3 2.
  const std::vector<WorkUnit> four = split_tail_runs(study, whole_runs(1), 4).units;
  EXPECT_EQ(four[0].points, (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(four[2].points, (std::vector<std::int32_t>{4, 5, 10, 11}));
  EXPECT_EQ(four[3].points, (std::vector<std::int32_t>{6, 7, 8, 9}));
}

TEST(RunPieces, AUnitOfSomePointsSplitsThemAndAnExtensionStaysWhole) {
  const Study study = pieces_study(2);
  const std::vector<WorkUnit> units{{0, 0, {0, 1, 6, 7}}, {0, 1, {2, 3}, true}};
  const PiecedUnits pieced = split_tail_runs(study, units, 4);
  const std::vector<WorkUnit> expected{{0, 0, {0, 1}}, {0, 0, {6, 7}, true}, {0, 1, {2, 3}, true}};
  EXPECT_EQ(pieced.units, expected);
  EXPECT_EQ(pieced.pieces.size(), 1u);
}

}  // namespace
}  // namespace ggk::engine
