#include "engine/run/resume_command.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "engine/job/shell_words.hpp"
#include "engine/run/job_runner.hpp"

namespace ggk::engine {

namespace {

// The invocation as typed, or the command that a library caller's options mean.
std::vector<std::string> invocation_words(const JobSpec& job, const RunOptions& options,
                                          const std::filesystem::path& output) {
  if (!options.invocation.empty()) return options.invocation;
  std::vector<std::string> words = {"ggk", "run", job.source_file.string()};
  for (const std::string& text : job.overrides) {
    words.push_back("--set");
    words.push_back(text);
  }
  for (const std::string& text : job.sweeps) {
    words.push_back("--sweep");
    words.push_back(text);
  }
  if (options.runs) {
    words.push_back("--runs");
    words.push_back(std::to_string(options.runs->first) + ":" + std::to_string(options.runs->last));
  }
  if (options.configuration_shard) {
    words.push_back("--shard");
    words.push_back(std::to_string(options.configuration_shard->index) + "/" +
                    std::to_string(options.configuration_shard->count));
  }
  words.push_back("-o");
  words.push_back(output.string());
  if (options.overwrite) words.push_back("--overwrite");
  if (options.resume) words.push_back("--resume");
  return words;
}

bool has_word(const std::vector<std::string>& words, const std::string& word) {
  return std::find(words.begin(), words.end(), word) != words.end();
}

}  // namespace

std::string resume_command(const JobSpec& job, const RunOptions& options,
                           const std::filesystem::path& output) {
  std::vector<std::string> words = invocation_words(job, options, output);
  // Neither flag takes a value, and no value of another option can be either
  // word (a -o of "--resume" is not a results file name, a --set is KEY=VALUE),
  // so a word equal to one of them is the flag.
  std::replace(words.begin(), words.end(), std::string("--overwrite"), std::string("--resume"));
  if (!has_word(words, "--resume")) {
    // Before a "--", after which every word is the job's.
    words.insert(std::find(words.begin(), words.end(), std::string("--")), "--resume");
  }
  return shell_command(words);
}

GoOnText go_on_text(const JobSpec& job, const RunOptions& options,
                    const std::filesystem::path& output, bool under_mpi) {
  const std::string launcher =
      under_mpi ? " (under mpirun as before, with any number of ranks, or alone)" : "";
  GoOnText text;
  text.published = "every run written to " + output.string() +
                   " is complete; finish the job with `" + resume_command(job, options, output) +
                   "`" + launcher;
  const std::vector<std::string> words = invocation_words(job, options, output);
  text.unpublished = output.string() +
                     " is as it was (no run of this job was written); start the job again with `" +
                     shell_command(words) + "`" + launcher;
  if (has_word(words, "--overwrite")) {
    text.unpublished += ", whose --overwrite deletes the runs " + output.string() + " holds";
  }
  return text;
}

}  // namespace ggk::engine
