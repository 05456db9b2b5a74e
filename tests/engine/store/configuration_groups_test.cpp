// A study's configuration groups in a results file (engine/store/configuration_groups.hpp):
// created with their values, found by their values whatever their names, a
// stranger's group refused, and renumbered for a grown study in two steps.

#include "engine/store/configuration_groups.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/job/job_error.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/files.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// A maze study over maze.slip with these values.
Study slip_study(const std::string& values) {
  const char* source = std::getenv("GGK_SOURCE_DIR");
  const fs::path jobs = fs::path(source != nullptr ? source : ".") / "jobs";
  JobLoadOptions options;
  options.check_output = false;
  return parse_study(
      "name = \"groups\"\ntask = \"maze\"\nruns = 2\nseed = 7\n[sweep]\nbasis = [\"ggk\"]\n"
      "kernels = [4]\nsigma = [10.0]\n\"maze.slip\" = [" +
          values + "]\n[maze]\nmap_file = \"maps/four-rooms.txt\"\nseries = 4\n",
      jobs / "groups.toml", task_tables(), options);
}

// The group name -> configuration index pairs found, sorted by name.
std::vector<std::pair<std::string, std::size_t>> found(const Hdf5File& file, const Study& study) {
  std::vector<std::pair<std::string, std::size_t>> pairs;
  for (const ConfigurationGroup& group : configuration_groups(file, study, file.path())) {
    pairs.emplace_back(group.name, group.configuration);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

TEST(ConfigurationGroups, AlignCreatesTheGroupsAndFindsThemByTheirValues) {
  const test_support::ScratchDir dir("ggk_configuration_groups");
  const Study study = slip_study("0.0, 0.2");
  Hdf5File file = Hdf5File::create(dir.path() / "r.h5");
  file.create_group("/maze");
  EXPECT_TRUE(configuration_groups(file, study, file.path()).empty());
  align_configurations(file, study, file.path());
  using Found = std::vector<std::pair<std::string, std::size_t>>;
  EXPECT_EQ(found(file, study), (Found{{"config_000", 0}, {"config_001", 1}}));
  EXPECT_TRUE(records_configuration(file, "maze/config_001", 1));
}

// A grown study (a value added before the others) renumbers the groups: each
// keeps its values and takes its configuration's new name and index.
TEST(ConfigurationGroups, AGrownStudyRenumbersTheGroupsByTheirValues) {
  const test_support::ScratchDir dir("ggk_configuration_groups");
  Hdf5File file = Hdf5File::create(dir.path() / "r.h5");
  file.create_group("/maze");
  align_configurations(file, slip_study("0.1, 0.2"), file.path());
  file.create_group("/maze/config_001/run_000");  // a run of slip = 0.2 moves with its group
  const Study grown = slip_study("0.0, 0.1, 0.2");
  align_configurations(file, grown, file.path());
  using Found = std::vector<std::pair<std::string, std::size_t>>;
  EXPECT_EQ(found(file, grown), (Found{{"config_000", 0}, {"config_001", 1}, {"config_002", 2}}));
  EXPECT_TRUE(file.exists("/maze/config_002/run_000"));
  EXPECT_FALSE(file.exists("/maze/config_001/run_000"));
  EXPECT_EQ(study_values_of(file, "maze/config_002"),
            study_values_text(grown.configurations[2].assignments));
  EXPECT_TRUE(records_configuration(file, "maze/config_002", 2));
}

// A group caught on its way to a new name (a kill between the two steps) is
// found by its values; a group of a configuration the study lacks is refused.
TEST(ConfigurationGroups, AMovingGroupIsFoundAndAStrangersIsRefused) {
  const test_support::ScratchDir dir("ggk_configuration_groups");
  Hdf5File file = Hdf5File::create(dir.path() / "r.h5");
  file.create_group("/maze");
  const Study study = slip_study("0.1, 0.2");
  align_configurations(file, study, file.path());
  file.move("/maze/config_001", "/maze/moving_config_001");
  using Found = std::vector<std::pair<std::string, std::size_t>>;
  EXPECT_EQ(found(file, study), (Found{{"config_000", 0}, {"moving_config_001", 1}}));
  align_configurations(file, study, file.path());
  EXPECT_EQ(found(file, study), (Found{{"config_000", 0}, {"config_001", 1}}));
  try {
    configuration_groups(file, slip_study("0.1, 0.3"), file.path());
    FAIL() << "the group of slip = 0.2 was matched to a study without it";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("config_001"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("which this job does not have"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ggk::engine
