// The shared geometry readers (engine/tasks/geometry_keys.hpp): sized arrays,
// numbers and points with their messages, and obstacle tables with their kinds
// (each table's own messages: arm_table_test.cpp, khepera_table_test.cpp).

#include "engine/tasks/geometry_keys.hpp"

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "engine/job/job_error.hpp"

namespace ggk::engine {
namespace {

constexpr std::array<std::string_view, 4> kKeys = {"p", "size", "obstacles", "kind"};
constexpr std::array<std::string_view, 3> kBoxKeys = {"kind", "min", "max"};
constexpr std::array<std::string_view, 3> kDiscKeys = {"kind", "center", "radius"};
constexpr std::array<std::string_view, 5> kObstacleKeys = {"kind", "min", "max", "center",
                                                           "radius"};
constexpr std::array<ObstacleKind, 2> kKinds = {
    {{"box", kBoxKeys, "kind, min, max"}, {"disc", kDiscKeys, "kind, center, radius"}}};

// The JobError message of `read` on the table `text` ([t] of g.toml), or "ok".
template <class Read>
std::string read_outcome(const std::string& text, Read read) {
  const toml::table table = toml::parse(text);
  try {
    read(TomlTableReader(table, "t", "g.toml", kKeys));
  } catch (const JobError& error) {
    return error.what();
  }
  return "ok";
}

TEST(GeometryKeys, PointsAndSizedArrays) {
  const toml::table table = toml::parse("p = [1, 2.5]\nsize = [3, -1]\n");
  const TomlTableReader reader(table, "t", "g.toml", kKeys);
  const sims::Point2 p = point(reader, "p");
  EXPECT_EQ(p.x, 1.0);
  EXPECT_EQ(p.y, 2.5);
  EXPECT_EQ(point(reader, "absent", sims::Point2{4.0, 5.0}).x, 4.0);
  const auto read_size = [](const TomlTableReader& r) {
    numbers_of<2>(r, "size", sized_array(r, "size", 2, "numbers [w, h]"), {"w", "h"},
                  NumberRange::above(0.0), "a length > 0.0");
  };
  EXPECT_NE(
      read_outcome("size = [3, -1]\n", read_size).find("[t] size: expected a length > 0.0 for h"),
      std::string::npos);
  EXPECT_NE(read_outcome("size = [3]\n", read_size)
                .find("expected an array of 2 numbers [w, h], got an array of 1 element"),
            std::string::npos);
  EXPECT_NE(read_outcome("", read_size).find("size: required key is missing"), std::string::npos);
}

TEST(GeometryKeys, ObstacleTablesAndTheirKinds) {
  const auto read_all = [](const TomlTableReader& r) {
    for (const TomlTableReader& obstacle : obstacle_tables(r, kKinds, kObstacleKeys)) {
      obstacle_kind(obstacle, kKinds, kObstacleKeys);
    }
  };
  EXPECT_EQ(read_outcome("[[obstacles]]\nkind = \"box\"\nmin = [0, 0]\n", read_all), "ok");
  EXPECT_NE(read_outcome("obstacles = 1\n", read_all)
                .find("expected an array of tables ([[t.obstacles]]), got 1"),
            std::string::npos);
  EXPECT_NE(read_outcome("obstacles = [1]\n", read_all)
                .find("expected a table with kind = \"box\" or \"disc\", got 1"),
            std::string::npos);
  EXPECT_NE(read_outcome("[[obstacles]]\nkind = \"disc\"\nmin = [0, 0]\n", read_all)
                .find("a disc has no key 'min' (its keys: kind, center, radius)"),
            std::string::npos);
  EXPECT_NE(read_outcome("[[obstacles]]\nkind = \"dsic\"\n", read_all).find("did you mean 'disc'"),
            std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
