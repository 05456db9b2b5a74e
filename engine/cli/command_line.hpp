#pragma once
// The ggk command line: every command with its options (CLI11) and the values
// they set, and the check made before CLI11 parses (an unknown command or option
// gets the closest spelling; a bare KEY=VALUE the --set / --sweep it meant).
// Each command is a function of its own (engine/cli/*_command.hpp); main.cpp
// parses and dispatches.
//
// Thread-safety: one object, on the main thread; CLI11 holds pointers into it,
// so it is neither copied nor moved.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/run/job_runner.hpp"
#include "engine/store/results_diff.hpp"
#include "engine/store/results_info.hpp"
#include "engine/store/results_merge.hpp"

namespace ggk::engine {

struct CommandLine {
  CommandLine();  // defines every command and option
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  CLI::App app{"ggk: least-squares policy iteration with geodesic Gaussian kernels"};
  CLI::App* run = nullptr;
  CLI::App* validate = nullptr;
  CLI::App* info = nullptr;
  CLI::App* verify = nullptr;
  CLI::App* diff = nullptr;
  CLI::App* merge = nullptr;

  // run and validate
  std::string job_path;
  RunOptions options;
  std::string output;
  std::vector<std::string> overrides, sweeps;
  std::string runs_text, shard_text;
  double rank_timeout = 60.0;
  bool print_job = false;  // validate --print
  // -q on every command: nothing on standard output, no progress or summary on
  // standard error; errors and warnings (a damaged run redone) still print.
  bool quiet = false;
  // info
  std::string info_path;
  InfoOptions info_options;
  bool info_csv = false;
  std::string info_columns, info_paired;
  // verify, diff
  std::string verify_path;
  std::vector<std::string> diff_files;
  DiffOptions diff_options;
  // merge
  std::string merge_output, merge_job, merge_output_option;
  std::vector<std::string> merge_inputs, merge_overrides, merge_sweeps;
  MergeOptions merge_options;
};

// "Did you mean": CLI11 says only that an argument was not expected. Looks at
// the command line before CLI11 does: an unknown command, or an option the
// command does not have, is a UsageError naming the closest spelling.
void check_spelling(const CLI::App& app, int argc, char** argv);

}  // namespace ggk::engine
