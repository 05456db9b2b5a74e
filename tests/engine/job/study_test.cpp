#include "engine/job/study.hpp"

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

std::filesystem::path jobs_dir() {
  const char* source = std::getenv("GGK_SOURCE_DIR");
  return std::filesystem::path(source != nullptr ? source : ".") / "jobs";
}

// A maze job file (four-rooms map) with `extra` appended to its [sweep] table.
std::string maze_job(const std::string& sweep_extra, const std::string& tail = "") {
  return "name = \"study\"\ntask = \"maze\"\nruns = 3\nseed = 7\n"
         "[sweep]\nbasis = [\"ggk\"]\nkernels = [4, 8]\nsigma = [10.0]\n" +
         sweep_extra + "\n[maze]\nmap_file = \"maps/four-rooms.txt\"\nseries = 4\n" + tail;
}

JobLoadOptions no_output_check() {
  JobLoadOptions options;
  options.check_output = false;
  return options;
}

Study study_of(const std::string& text, JobLoadOptions options = no_output_check()) {
  return parse_study(text, jobs_dir() / "study.toml", task_tables(), options);
}

std::string error_of(const std::string& text, JobLoadOptions options = no_output_check()) {
  try {
    study_of(text, std::move(options));
  } catch (const JobError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Study, APlainJobIsOneConfigurationWithoutAGroup) {
  const Study study = study_of(maze_job(""));
  EXPECT_FALSE(study.has_axes());
  ASSERT_EQ(study.configurations.size(), 1u);
  EXPECT_EQ(study.configurations[0].job.configuration_group, "");
  ASSERT_EQ(study.configurations[0].variants.size(), 1u);
  EXPECT_TRUE(study.configurations[0].variants[0].assignments.empty());
  EXPECT_EQ(expand_points(study.configurations[0]).size(), 2u);
}

TEST(Study, RunLevelAxesMakeConfigurationsInProductOrder) {
  const Study study = study_of(maze_job("\"maze.slip\" = [0.0, 0.1]\n\"maze.series\" = [4, 6, 8]"));
  ASSERT_EQ(study.axes.size(), 2u);
  EXPECT_EQ(study.axes[0].keys, std::vector<std::string>{"maze.slip"});
  EXPECT_EQ(study.axes[0].level, StageLevel::kRun);
  ASSERT_EQ(study.configurations.size(), 6u);
  // The last axis varies fastest; each configuration's job holds its values.
  const double slips[] = {0.0, 0.0, 0.0, 0.1, 0.1, 0.1};
  const char* series[] = {"4", "6", "8", "4", "6", "8"};
  for (std::size_t c = 0; c < 6; ++c) {
    const RunConfiguration& configuration = study.configurations[c];
    EXPECT_EQ(configuration.index, static_cast<std::int32_t>(c));
    EXPECT_EQ(configuration.job.configuration_group, "config_00" + std::to_string(c));
    ASSERT_EQ(configuration.assignments.size(), 2u);
    EXPECT_EQ(configuration.assignments[0].key, "maze.slip");
    EXPECT_EQ(configuration.assignments[0].value, slips[c] == 0.0 ? "0.0" : "0.1");
    EXPECT_EQ(configuration.assignments[1].value, series[c]);
    EXPECT_EQ(configuration.job.resolved.value("maze.series"), series[c]);
    // Everything but the axes is the job's: same runs, seed, sweep.
    EXPECT_EQ(configuration.job.runs, 3);
    EXPECT_EQ(configuration.job.seed, 7u);
    EXPECT_EQ(configuration.job.sweep.kernels, (std::vector<std::int32_t>{4, 8}));
  }
}

TEST(Study, AConfigurationIsTheSingleJobWithThatValue) {
  // The 0.1-slip configuration of the study resolves exactly as the plain job
  // with slip = 0.1 written in its [maze] table.
  const Study study = study_of(maze_job("\"maze.slip\" = [0.0, 0.1]"));
  const Study single = study_of(maze_job("", "slip = 0.1\n"));
  const RunConfiguration& configuration = study.configurations[1];
  EXPECT_EQ(configuration.job.resolved.difference(single.job().resolved, "study", "single"),
            std::nullopt);
}

TEST(Study, FitLevelAxesAreVariantsOfOneConfiguration) {
  const Study study =
      study_of(maze_job("\"lspi.max_iterations\" = [5, 20]\n\"lspi.stopping\" = [\"policy\", "
                        "\"weights\"]"));
  ASSERT_EQ(study.configurations.size(), 1u);
  EXPECT_EQ(study.axes[0].level, StageLevel::kFit);
  const RunConfiguration& configuration = study.configurations[0];
  EXPECT_EQ(configuration.job.configuration_group,
            "");  // no run-level axis: runs where they always are
  ASSERT_EQ(configuration.variants.size(), 4u);
  EXPECT_EQ(configuration.variants[0].lspi.max_iterations, 5);
  EXPECT_EQ(configuration.variants[1].lspi.stopping, kernels::LspiStopping::weights_converged);
  EXPECT_EQ(configuration.variants[2].lspi.max_iterations, 20);
  EXPECT_EQ(configuration.variants[3].assignments.size(), 2u);
  // Two kernel counts x four variants, the variant fastest.
  const std::vector<SweepPoint> points = expand_points(configuration);
  ASSERT_EQ(points.size(), 8u);
  EXPECT_EQ(points[0].kernels, 4);
  EXPECT_EQ(points[3].variant, 3);
  EXPECT_EQ(points[4].kernels, 8);
  EXPECT_EQ(points[4].variant, 0);
  EXPECT_EQ(lspi_options(points[2]).max_iterations, 20);
  EXPECT_EQ(lspi_options(points[0]).max_iterations, 5);
}

TEST(Study, FoldDuplicatesIsRunLevel) {
  EXPECT_EQ(stage_of("lspi.fold_duplicates"), StageLevel::kRun);
  EXPECT_EQ(stage_of("lspi.gamma"), StageLevel::kFit);
  EXPECT_EQ(stage_of("basis.truncation"), StageLevel::kRun);
  EXPECT_EQ(stage_of("khepera.motion.turn_deg"), StageLevel::kRun);
  EXPECT_EQ(stage_of("kernels"), StageLevel::kFit);
}

TEST(Study, ZipVariesKeysTogether) {
  const Study study =
      study_of(maze_job("\"maze.series\" = [4, 6]\n[[sweep.zip]]\n\"maze.slip\" = [0.0, 0.2, 0.3]\n"
                        "\"maze.steps_per_series\" = [100, 200, 300]"));
  ASSERT_EQ(study.axes.size(), 2u);
  EXPECT_EQ(study.axes[1].keys, (std::vector<std::string>{"maze.slip", "maze.steps_per_series"}));
  ASSERT_EQ(study.configurations.size(), 6u);  // 2 x 3, not 2 x 3 x 3
  const RunConfiguration& last = study.configurations[5];
  EXPECT_EQ(last.job.resolved.value("maze.series"), "6");
  EXPECT_EQ(last.job.resolved.value("maze.slip"), "0.3");
  EXPECT_EQ(last.job.resolved.value("maze.steps_per_series"), "300");
}

TEST(Study, ValuesCompareByMeaning) {
  // 0 and 0.0 of a float key are one value: refused as a repeat.
  EXPECT_NE(error_of(maze_job("\"maze.slip\" = [0, 0.0]")).find("appears twice"),
            std::string::npos);
  // An integer written for a float key reads as the float.
  const Study study = study_of(maze_job("\"maze.slip\" = [0, 0.5]"));
  EXPECT_EQ(study.configurations[0].assignments[0].value, "0.0");
}

TEST(Study, ErrorsNameTheAxisAndTheValue) {
  const std::string bad_value = error_of(maze_job("\"maze.slip\" = [0.0, 1.5]"));
  // study.toml:LINE:COLUMN of the value 1.5 in [sweep] (line 9 of maze_job's text).
  EXPECT_NE(bad_value.find("study.toml:9:21:"), std::string::npos) << bad_value;
  EXPECT_NE(bad_value.find("slip"), std::string::npos) << bad_value;
  EXPECT_NE(bad_value.find("at the study point maze.slip = 1.5"), std::string::npos) << bad_value;

  const std::string misspelt = error_of(maze_job("\"maze.slipp\" = [0.0]"));
  EXPECT_NE(misspelt.find("did you mean 'slip'"), std::string::npos) << misspelt;

  EXPECT_NE(error_of(maze_job("\"runs\" = [1, 2]")).find("runs = N"), std::string::npos);
  EXPECT_NE(error_of(maze_job("\"output.file\" = [\"a.h5\"]")).find("one results file"),
            std::string::npos);
  EXPECT_NE(error_of(maze_job("\"seed\" = [1, 2]")).find("common random numbers"),
            std::string::npos);
  EXPECT_NE(error_of(maze_job("\"sweep.kernels\" = [1]")).find("built-in axes"), std::string::npos);
  EXPECT_NE(error_of(maze_job("\"maze.slip\" = [[0.1]]")).find("scalar values"), std::string::npos);
  EXPECT_NE(error_of(maze_job("\"maze.slip\" = []")).find("non-empty array"), std::string::npos);
  EXPECT_NE(error_of(maze_job("\"maze.slip\" = [0.1]\n[[sweep.zip]]\n\"maze.slip\" = [0.2]"))
                .find("already an axis"),
            std::string::npos);
  EXPECT_NE(error_of(maze_job("[[sweep.zip]]\n\"maze.slip\" = [0.1, 0.2]\n\"maze.series\" = [4]"))
                .find("as many values"),
            std::string::npos);
  EXPECT_NE(error_of(maze_job("\"runs.x\" = [1]")).find("not a table"), std::string::npos);
}

TEST(Study, SweepOptionAddsAnAxis) {
  JobLoadOptions options = no_output_check();
  options.sweeps = {"maze.slip=0.0,0.1,0.2", "kernels=[4, 16]"};
  const Study study = study_of(maze_job(""), options);
  ASSERT_EQ(study.configurations.size(), 3u);
  EXPECT_EQ(study.configurations[2].job.resolved.value("maze.slip"), "0.2");
  EXPECT_EQ(study.job().sweep.kernels, (std::vector<std::int32_t>{4, 16}));
  // Bare words are strings.
  options.sweeps = {"lspi.stopping=policy,weights"};
  EXPECT_EQ(study_of(maze_job(""), options).configurations[0].variants.size(), 2u);
  options.sweeps = {"maze.slip"};
  EXPECT_NE(error_of(maze_job(""), options).find("--sweep maze.slip: expected KEY=V1,V2"),
            std::string::npos);
  options.sweeps = {"maze.slip=0.1,,0.2"};
  EXPECT_NE(error_of(maze_job(""), options).find("empty value"), std::string::npos);
}

// Hydra's habits: a range START:STOP:STEP (the end included when reached), and
// a key swept twice is refused instead of the second replacing the first.
TEST(Study, SweepOptionTakesARangeAndRefusesAKeyTwice) {
  JobLoadOptions options = no_output_check();
  options.sweeps = {"kernels=4:16:4"};
  EXPECT_EQ(study_of(maze_job(""), options).job().sweep.kernels,
            (std::vector<std::int32_t>{4, 8, 12, 16}));
  options.sweeps = {"kernels=4:15:4"};
  EXPECT_EQ(study_of(maze_job(""), options).job().sweep.kernels,
            (std::vector<std::int32_t>{4, 8, 12}));
  options.sweeps = {"maze.slip=0.0:0.3:0.1"};
  const Study slips = study_of(maze_job(""), options);
  ASSERT_EQ(slips.configurations.size(), 4u);
  EXPECT_EQ(slips.configurations[3].job.resolved.value("maze.slip"),
            "0.30000000000000004");  // 0.0 + 3 x 0.1, as a range computes it
  options.sweeps = {"kernels=16:4:4"};
  EXPECT_NE(error_of(maze_job(""), options).find("STEP > 0 and STOP >= START"), std::string::npos);
  options.sweeps = {"kernels=4:16:0"};
  EXPECT_NE(error_of(maze_job(""), options).find("STEP > 0"), std::string::npos);
  options.sweeps = {"kernels=4,8", "kernels=16"};
  const std::string twice = error_of(maze_job(""), options);
  EXPECT_NE(twice.find("--sweep kernels=16: the key 'kernels' is swept twice"), std::string::npos)
      << twice;
}

// An error in a --sweep value names the option and the key as written, not the
// job file and a key split at its inner dot (issue 36: "jobs/ci-arm.toml:
// [sweep."arm] links": ...).
TEST(Study, ASweepOptionsErrorNamesTheOptionAndTheKeyAsWritten) {
  JobLoadOptions options = no_output_check();
  options.sweeps = {"maze.slip=[[0.1,0.2],[0.3]]"};
  const std::string error = error_of(maze_job(""), options);
  EXPECT_EQ(error.rfind("--sweep maze.slip=[[0.1,0.2],[0.3]]: [sweep] \"maze.slip\": a study axis "
                        "takes scalar values",
                        0),
            0u)
      << error;
}

// ggk validate --print: every shipped job (studies, zipped axes, a khepera noise
// model that leaves keys unused, a Python environment's folder) printed resolved
// reads back as the same study, and prints the same again.
TEST(Study, EveryShippedJobPrintedResolvedReadsBackAsTheSameStudy) {
  std::size_t jobs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(jobs_dir())) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().filename().string());
    // A task this build does not register (python_env in a build without Python).
    const std::optional<std::string> task =
        toml::parse_file(entry.path().string())["task"].value<std::string>();
    if (!task || find_task(*task) == nullptr) continue;
    const Study study = load_study(entry.path(), task_tables(), no_output_check());
    const std::string printed = resolved_job_toml(study);
    const Study again = study_of(printed);
    EXPECT_TRUE(resolved_of(again) == resolved_of(study))
        << resolved_of(study)
               .difference(resolved_of(again), "the job", "the printed job")
               .value_or("");
    EXPECT_EQ(resolved_job_toml(again), printed);
    ++jobs;
  }
  EXPECT_GE(jobs, 20u);
}

TEST(Study, APrintedJobShowsTheKeysItsChoicesLeaveUnusedAsComments) {
  const Study study = study_of(
      "name = \"noise\"\ntask = \"khepera\"\nruns = 1\nseed = 1\n"
      "[sweep]\nkernels = [10]\nsigma = [1000.0]\n"
      "[khepera]\narena_file = \"arenas/default.toml\"\n"
      "[khepera.sensors]\nnoise_model = \"threshold\"\n");
  const std::string printed = resolved_job_toml(study);
  EXPECT_NE(printed.find("\n# noise_fraction = 0.04  (unused: noise_model is \"threshold\")\n"),
            std::string::npos)
      << printed;
  EXPECT_NE(printed.find("\ndetection_threshold = "), std::string::npos);
  EXPECT_NE(printed.find("\nnoise_sd = "), std::string::npos);
  EXPECT_TRUE(resolved_of(study_of(printed)) == resolved_of(study));
}

TEST(Study, ParseJobRefusesAStudy) {
  try {
    parse_job(maze_job("\"maze.slip\" = [0.0, 0.1]"), jobs_dir() / "study.toml", task_tables(),
              no_output_check());
    FAIL() << "a study was taken as a single job";
  } catch (const JobError& e) {
    EXPECT_NE(std::string(e.what()).find("is a study"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ggk::engine

namespace ggk::engine {
namespace {

// An [adaptive] table (job/adaptive_rule.hpp) on a study over maze.slip.
std::string adaptive_job(const std::string& adaptive) {
  return "name = \"study\"\ntask = \"maze\"\nruns = 20\nseed = 7\n"
         "[sweep]\nbasis = [\"ggk\", \"ogk\"]\nkernels = [4, 8]\nsigma = [10.0]\n"
         "\"maze.slip\" = [0.0, 0.1]\n"
         "[maze]\nmap_file = \"maps/four-rooms.txt\"\nseries = 4\n[adaptive]\n" +
         adaptive;
}

TEST(AdaptiveRule, ReadsTheTableWithItsDefaults) {
  const Study study = study_of(adaptive_job(
      "compare = [\"basis=ggk,ogk\", \"maze.slip=0,0.1\"]\nmetrics = \"success_rate\"\n"
      "[adaptive.range]\nmean_steps_to_goal = [0.0, 100.0]\n"));
  ASSERT_TRUE(study.job().adaptive.has_value());
  const AdaptiveRule& rule = *study.job().adaptive;
  ASSERT_EQ(rule.comparisons.size(), 2u);
  EXPECT_EQ(rule.comparisons[1].text(), "maze.slip=0,0.1");
  EXPECT_EQ(rule.metrics, std::vector<std::string>{"success_rate"});
  EXPECT_EQ(rule.batch, 5);
  EXPECT_DOUBLE_EQ(rule.level, 0.95);
  EXPECT_EQ(rule.target, AdaptiveTarget::kSign);
  EXPECT_EQ(rule.correction, AdaptiveCorrection::kBonferroni);
  ASSERT_TRUE(rule.declared_range("mean_steps_to_goal").has_value());
  EXPECT_DOUBLE_EQ(rule.declared_range("mean_steps_to_goal")->high, 100.0);
  // Every configuration carries the one rule, and it is part of the resolved job.
  EXPECT_TRUE(study.configurations.back().job.adaptive.has_value());
  EXPECT_TRUE(study.job().resolved.value("adaptive.batch").has_value());
}

TEST(AdaptiveRule, RefusesWhatTheStudyCannotFollow) {
  const std::string metrics = "metrics = [\"success_rate\"]\n";
  EXPECT_NE(error_of(adaptive_job("compare = \"kernel=4,8\"\n" + metrics)).find("no axis 'kernel'"),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"kernels=4,16\"\n" + metrics))
                .find("kernels has no value '16'"),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"basis=ggk\"\n" + metrics)).find("AXIS=A,B"),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"basis=ggk,ogk\"\n" + metrics + "batch = 21\n"))
                .find("batch"),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"basis=ggk,ogk\"\n" + metrics + "width = 0.1\n"))
                .find("give target = \"width\""),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"basis=ggk,ogk\"\n" + metrics + "level = 1.0\n"))
                .find("[adaptive] level"),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"basis=ggk,ogk\"\n" + metrics +
                                  "[adaptive.range]\nsuccess_rate = [1.0, 0.0]\n"))
                .find("LOW < HIGH"),
            std::string::npos);
  EXPECT_NE(error_of(adaptive_job("compare = \"basis=ggk,ogk\"\n")).find("metrics"),
            std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
