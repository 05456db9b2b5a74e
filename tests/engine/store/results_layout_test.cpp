// The root of a results file: the header written and read back, what a file
// that is not a results file reads as, the roles diff gives root attributes,
// fit statuses.

#include "engine/store/results_layout.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "kernels/lspi.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

class ResultsLayoutTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("ggk_results_layout_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A header with every attribute set, two inputs out of key order.
  static ResultsHeader full_header() {
    ResultsHeader header;
    header.job = "name = \"t\"\ntask = \"maze\"\n";
    header.job_file = "jobs/t.toml";
    header.inputs = {{"maze.map_file", "#####\n#G..#\n#####\n"},
                     {"khepera.arena_file", "[arena]\nwidth = 1.0\n"}};
    header.ggk_version = "0.1.0";
    header.git = "v0.1-3-gabcdef";
    header.blas = "OpenBLAS 0.3.21";
    header.created = "2024-06-01T12:00:00Z";
    header.task = "maze";
    header.runs = 30;
    header.job_overrides = "runs=30\nseed=7";
    header.runs_selected = RunsSelected{4, 9};
    header.configurations_selected = ConfigurationsSelected{{1, 3}, 6};
    return header;
  }

  // A file whose root holds the attributes write_results_header writes for
  // `header`, except `left_out`.
  fs::path file_without(const std::string& left_out) {
    const fs::path path = dir_ / ("without_" + left_out + ".h5");
    Hdf5File file = Hdf5File::create(path);
    write_results_header(file, full_header());
    if (file.has_attribute("/", left_out)) file.remove_attribute("/", left_out);
    file.flush();
    return path;
  }

  fs::path dir_;
};

TEST_F(ResultsLayoutTest, HeaderReadsBackAsWritten) {
  const fs::path path = dir_ / "full.h5";
  {
    Hdf5File file = Hdf5File::create(path);
    write_results_header(file, full_header());
    file.flush();
  }
  const Hdf5File file = Hdf5File::open_read_only(path);
  const ResultsHeader read = read_results_header(file);
  ResultsHeader expected = full_header();
  std::swap(expected.inputs[0], expected.inputs[1]);  // read back ascending by key
  EXPECT_EQ(read, expected);
  // The attributes have the names and types results/README.md gives readers.
  EXPECT_EQ(file.read_string_attribute("/", "input:maze.map_file"), "#####\n#G..#\n#####\n");
  EXPECT_EQ(file.read_int64_attribute("/", "runs"), 30);
  EXPECT_EQ(file.read_int64_attribute("/", "layout"), kLayoutVersion);
  EXPECT_EQ(file.read_int64_array_attribute("/", "runs_selected"),
            (std::vector<std::int64_t>{4, 9}));
  EXPECT_EQ(file.read_int64_array_attribute("/", "configurations_selected"),
            (std::vector<std::int64_t>{1, 3}));
  EXPECT_EQ(file.read_int64_attribute("/", "adaptive_cells"), 6);
}

TEST_F(ResultsLayoutTest, OptionalAttributesAreLeftOutAndReadAsAbsent) {
  ResultsHeader header = full_header();
  header.inputs.clear();
  header.blas.clear();
  header.job_overrides.clear();
  header.runs_selected.reset();
  header.configurations_selected.reset();
  const fs::path path = dir_ / "plain.h5";
  {
    Hdf5File file = Hdf5File::create(path);
    write_results_header(file, header);
    file.flush();
  }
  const Hdf5File file = Hdf5File::open_read_only(path);
  EXPECT_FALSE(file.has_attribute("/", "blas"));
  EXPECT_FALSE(file.has_attribute("/", "job_overrides"));
  EXPECT_FALSE(file.has_attribute("/", "runs_selected"));
  EXPECT_EQ(file.attribute_names("/"),
            (std::vector<std::string>{"created", "ggk_version", "git", "job", "job_file", "layout",
                                      "rules", "runs", "task"}));
  EXPECT_EQ(read_results_header(file), header);
}

TEST_F(ResultsLayoutTest, AFileWithoutALayoutIsLayoutOne) {
  const Hdf5File file = Hdf5File::open_read_only(file_without("layout"));
  const ResultsHeader header = read_results_header(file);
  EXPECT_EQ(header.layout, 1);
  EXPECT_NE(layout_mismatch(header.layout).find("written by an older ggk"), std::string::npos);
  EXPECT_NE(layout_mismatch(kLayoutVersion + 1).find("written by a newer ggk"), std::string::npos);
  EXPECT_EQ(layout_mismatch(kLayoutVersion), "");
}

// Results rules (results_rules.hpp): written by every new file; a file without
// the attribute is rules 1, unless its `git` names a commit that computed under
// rules 2 before files said so (stop 41's campaign, F4: a file of the rules
// before common random numbers resumed to a mix of both).
TEST_F(ResultsLayoutTest, AFileRecordsItsResultsRulesAndOlderOnesAreToldByTheirCommit) {
  {
    const Hdf5File file = Hdf5File::open_read_only(file_without("nothing"));
    EXPECT_EQ(file.read_int64_attribute("/", "rules"), kResultsRules);
  }
  const fs::path path = file_without("rules");
  for (const auto& [git, rules] : std::vector<std::pair<std::string, std::int64_t>>{
           {"90152b7", 1},        // the commit before common random numbers
           {"10a1054", 2},        // common random numbers
           {"0643028-dirty", 2},  // a later commit's build with changes of its own
           {"064302868a", 2},     // a longer abbreviation
           {"v0.1-3-gabcdef", 1},
           {"unknown", 1},
           {"", 1}}) {
    {
      Hdf5File file = Hdf5File::open_read_write(path);
      file.remove_attribute("/", "git");
      file.write_string_attribute("/", "git", git);
      file.flush();
    }
    const Hdf5File file = Hdf5File::open_read_only(path);
    EXPECT_EQ(read_results_header(file).rules, rules) << git;
  }
  EXPECT_EQ(rules_mismatch(kResultsRules), "");
  const std::string mismatch = rules_mismatch(1);
  EXPECT_NE(mismatch.find("rules 1 (before common random numbers"), std::string::npos) << mismatch;
  EXPECT_NE(mismatch.find("this ggk computes under rules 2"), std::string::npos) << mismatch;
}

TEST_F(ResultsLayoutTest, AMissingRequiredAttributeIsNamed) {
  for (const std::string name :
       {"job", "job_file", "ggk_version", "git", "created", "task", "runs"}) {
    const fs::path path = file_without(name);
    const Hdf5File file = Hdf5File::open_read_only(path);
    try {
      (void)read_results_header(file);
      ADD_FAILURE() << "a file without '" << name << "' read as a results file";
    } catch (const ResultsHeaderError& e) {
      const std::string what = e.what();
      EXPECT_NE(
          what.find(path.string() + " is not a ggk results file (no '" + name + "' attribute)"),
          std::string::npos)
          << what;
    }
  }
}

TEST_F(ResultsLayoutTest, AnAttributeOfTheWrongTypeIsNamedWithBothTypes) {
  struct Case {
    std::string name;
    bool as_string;  // written as a string (else as an int64)
    std::string expected;
  };
  for (const Case& c : {Case{"runs", true, "not int64"}, Case{"layout", true, "not int64"},
                        Case{"job", false, "not a string"}, Case{"task", false, "not a string"},
                        Case{"input:maze.map_file", false, "not a string"},
                        Case{"runs_selected", true, "not int64"},
                        Case{"configurations_selected", true, "not int64"},
                        Case{"adaptive_cells", true, "not int64"}}) {
    const fs::path path = file_without(c.name);
    {
      Hdf5File file = Hdf5File::open_read_write(path);
      if (c.as_string) {
        file.write_string_attribute("/", c.name, "30");
      } else {
        file.write_int64_attribute("/", c.name, 30);
      }
      file.flush();
    }
    const Hdf5File file = Hdf5File::open_read_only(path);
    try {
      (void)read_results_header(file);
      ADD_FAILURE() << "'" << c.name << "' of the wrong type was read";
    } catch (const ResultsHeaderError& e) {
      const std::string what = e.what();
      EXPECT_NE(
          what.find(path.string() + " is not a ggk results file: its '" + c.name + "' attribute"),
          std::string::npos)
          << what;
      EXPECT_NE(what.find(c.expected), std::string::npos) << what;
    }
  }
}

TEST_F(ResultsLayoutTest, ARangeOfOtherThanTwoValuesIsRefused) {
  const fs::path path = file_without("runs_selected");
  {
    Hdf5File file = Hdf5File::open_read_write(path);
    const std::int64_t three[3] = {0, 1, 2};
    file.write_int64_array_attribute("/", "runs_selected", three);
    file.flush();
  }
  const Hdf5File file = Hdf5File::open_read_only(path);
  try {
    (void)read_results_header(file);
    ADD_FAILURE() << "a three-value runs_selected was read";
  } catch (const ResultsHeaderError& e) {
    EXPECT_NE(std::string(e.what()).find("'runs_selected' attribute: holds 3 values"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ResultsLayoutTest, RunsSelectedIsRewrittenOrRemoved) {
  const fs::path path = dir_ / "shard.h5";
  Hdf5File file = Hdf5File::create(path);
  write_results_header(file, full_header());
  write_runs_selected(file, RunsSelected{0, 2});
  EXPECT_EQ(read_results_header(file).runs_selected, (RunsSelected{0, 2}));
  write_runs_selected(file, std::nullopt);
  EXPECT_FALSE(file.has_attribute("/", "runs_selected"));
  EXPECT_FALSE(read_results_header(file).runs_selected);
}

TEST(RootAttributeRole, ProvenanceAndWallClockAreNamedAndTheRestAreResults) {
  for (const char* name : {"job_file", "git", "ggk_version", "blas", "runs_selected"}) {
    EXPECT_EQ(root_attribute_role(name), RootAttributeRole::kProvenance) << name;
  }
  EXPECT_EQ(root_attribute_role("created"), RootAttributeRole::kWallClock);
  for (const char* name :
       {"job", "task", "runs", "layout", "job_overrides", "input:maze.map_file"}) {
    EXPECT_EQ(root_attribute_role(name), RootAttributeRole::kResult) << name;
  }
}

TEST(InputAttributeName, IsTheKeyAfterThePrefix) {
  EXPECT_EQ(input_attribute_name("maze.map_file"), "input:maze.map_file");
}

TEST(FitStatus, TextsAreLspisAndInvalid) {
  using kernels::LspiStatus;
  EXPECT_EQ(to_string(FitStatus::kConverged), kernels::to_string(LspiStatus::converged));
  EXPECT_EQ(to_string(FitStatus::kMaxIterations), kernels::to_string(LspiStatus::max_iterations));
  EXPECT_EQ(to_string(FitStatus::kSolverFailed), kernels::to_string(LspiStatus::solver_failed));
  EXPECT_EQ(to_string(FitStatus::kInvalid), "invalid");
  for (const FitStatus status : {FitStatus::kConverged, FitStatus::kMaxIterations,
                                 FitStatus::kSolverFailed, FitStatus::kInvalid}) {
    EXPECT_EQ(fit_status_from_text(to_string(status)), status);
  }
  EXPECT_FALSE(fit_status_from_text("converged "));
  EXPECT_FALSE(fit_status_from_text(""));
}

TEST(FitStatus, FailedMeansNoUsablePolicy) {
  EXPECT_TRUE(is_failed(FitStatus::kSolverFailed));
  EXPECT_TRUE(is_failed(FitStatus::kInvalid));
  EXPECT_FALSE(is_failed(FitStatus::kConverged));
  EXPECT_FALSE(is_failed(FitStatus::kMaxIterations));
  EXPECT_TRUE(is_failed_status("solver_failed"));
  EXPECT_TRUE(is_failed_status("invalid"));
  EXPECT_FALSE(is_failed_status("max_iterations"));
  EXPECT_FALSE(is_failed_status("unknown"));
}

}  // namespace
}  // namespace ggk::engine
