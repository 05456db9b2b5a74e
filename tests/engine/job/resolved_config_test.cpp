#include "engine/job/resolved_config.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

std::filesystem::path shipped_jobs_dir() {
  const char* source = std::getenv("GGK_SOURCE_DIR");
  return std::filesystem::path(source != nullptr ? source : ".") / "jobs";
}

ResolvedConfig resolved_of(const std::string& text) {
  JobLoadOptions options;
  options.check_output = false;
  return parse_job(text, shipped_jobs_dir() / "x.toml", task_tables(), options).resolved;
}

const std::string kHead =
    "name = \"x\"\ntask = \"maze\"\nruns = 2\nseed = 1\n[sweep]\nkernels = [4]\n";

TEST(ResolvedConfig, CanonicalValues) {
  EXPECT_EQ(canonical_number(30), "30.0");
  EXPECT_EQ(canonical_number(0.1), "0.1");
  EXPECT_EQ(canonical_number(1e-6), "1e-06");
  EXPECT_EQ(canonical_integer(-3), "-3");
  EXPECT_EQ(canonical_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\n\"");
  EXPECT_EQ(canonical_boolean(true), "true");
}

TEST(ResolvedConfig, RespellingsAndDefaultsReadAlike) {
  // sigma = [5] and [5.0]; slip = 0 and 0.0; a key at its default and absent;
  // comments, order and table style.
  const ResolvedConfig a = resolved_of(kHead + "sigma = [5]\n[maze]\nslip = 0\n");
  const ResolvedConfig b = resolved_of("# a comment\n" + kHead +
                                       "sigma = [5.0]\nsolver = [\"brm\"]\n[maze]\nslip = 0.0\n"
                                       "series = 20\n[lspi]\nmax_iterations = 20\n");
  EXPECT_EQ(a.difference(b, "a", "b"), std::nullopt);
  EXPECT_TRUE(a == b);
  EXPECT_EQ(a.value("sweep.sigma"), "[5.0]");
  EXPECT_EQ(a.value("lspi.gamma"), "0.9");  // a default, filled in
  EXPECT_EQ(a.given_keys().count("lspi.gamma"), 0u);
  EXPECT_EQ(a.given_keys().count("maze.slip"), 1u);
}

TEST(ResolvedConfig, ADifferenceIsNamed) {
  const ResolvedConfig a = resolved_of(kHead + "sigma = [5]\n[maze]\nslip = 0.1\n");
  const ResolvedConfig b = resolved_of(kHead + "sigma = [5]\n[maze]\nslip = 0.2\n");
  EXPECT_EQ(a.difference(b, "the file", "the job"), "maze.slip: 0.1 in the file, 0.2 in the job");
  EXPECT_EQ(a.difference(b, "x", "y", {"maze.slip"}), std::nullopt);
  // The internal key of a study's axes is named as a person knows it (issue 37).
  ResolvedConfig study_a = a, study_b = a;
  study_a.record("study.axes", "[\"maze.slip\"]", true);
  study_b.record("study.axes", "[\"maze.series\"]", true);
  const auto axes = study_a.difference(study_b, "the file", "the job");
  ASSERT_TRUE(axes);
  EXPECT_EQ(axes->rfind("the study's axes ([sweep] keys and --sweep options): ", 0), 0u) << *axes;
}

// A file written before a key existed lacks it: the job at that key's default
// (the old behaviour) is the same job, the job giving the key is not.
TEST(ResolvedConfig, AKeyNewerThanTheFileMatchesOnlyAtItsDefault) {
  const ResolvedConfig job = resolved_of(kHead + "sigma = [5]\n");
  std::string text = job.text();
  const std::size_t line = text.find("\"lspi.ridge\" = \"absolute\"\n");
  ASSERT_NE(line, std::string::npos) << text;
  text.erase(line, std::string("\"lspi.ridge\" = \"absolute\"\n").size());
  const std::optional<ResolvedConfig> older = ResolvedConfig::from_text(text);
  ASSERT_TRUE(older.has_value());
  EXPECT_EQ(older->difference(job, "the file", "the job"), std::nullopt);
  const ResolvedConfig relative =
      resolved_of(kHead + "sigma = [5]\n[lspi]\nridge = \"relative\"\n");
  EXPECT_EQ(older->difference(relative, "the file", "the job"), "lspi.ridge: only in the job");
  const ResolvedConfig absolute =
      resolved_of(kHead + "sigma = [5]\n[lspi]\nridge = \"absolute\"\n");
  EXPECT_EQ(older->difference(absolute, "the file", "the job"), "lspi.ridge: only in the job");
}

TEST(ResolvedConfig, TextRoundTrips) {
  const ResolvedConfig a =
      resolved_of(kHead + "sigma = [5]\n[maze]\nmap = \"\"\"\n#G#\n#.#\n\"\"\"\n");
  const std::optional<ResolvedConfig> back = ResolvedConfig::from_text(a.text());
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->difference(a, "back", "original"), std::nullopt);
  EXPECT_EQ(back->text(), a.text());
  EXPECT_FALSE(ResolvedConfig::from_text("not a config\n").has_value());
  EXPECT_FALSE(ResolvedConfig::from_text("\"a\" = 1").has_value());  // no final newline
  EXPECT_FALSE(ResolvedConfig::from_text("\"a\" = 1\n\"a\" = 2\n").has_value());
}

TEST(ResolvedConfig, UnreadKeysAreKeptAsWritten) {
  // Every key of the job is in the resolved configuration, also those that no
  // typed getter reads (here: the whole arm table's nested arrays).
  JobLoadOptions options;
  options.check_output = false;
  const JobSpec arm = load_job_file(shipped_jobs_dir() / "ci-arm.toml", task_tables(), options);
  EXPECT_TRUE(arm.resolved.contains("arm.links"));
  EXPECT_TRUE(arm.resolved.contains("name"));
  EXPECT_GT(arm.resolved.size(), 20u);
}

}  // namespace
}  // namespace ggk::engine
