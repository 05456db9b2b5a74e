#pragma once
// A validated sweep job: what job_file.hpp's load_job_file() returns. Plain data;
// every value is already checked against the ranges documented in jobs/README.md.
//
// The sweep axes form a Cartesian product (see sweep.hpp); everything else is
// fixed for the whole job. The task's own parameters sit in `task_config`, of
// the type its table parser returned (task_table.hpp): this file names no task.

#include <any>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

#include "engine/job/adaptive_rule.hpp"
#include "engine/job/job_input.hpp"
#include "engine/job/resolved_config.hpp"
#include "kernels/graph_laplacian.hpp"
#include "kernels/lspi.hpp"
#include "kernels/state_action_basis.hpp"

namespace ggk::engine {

// The state basis: Gaussian kernels on shortest paths of the sample graph
// (geodesic, Eq. (8)) or on Euclidean distances (ordinary, Eq. (7)), or the
// proto-value functions, the smallest eigenvectors of the sample graph's
// Laplacian (Mahadevan & Maggioni 2007; [pvf], PvfSettings).
enum class KernelType { ggk, ogk, pvf };

// Names as written in job files: "ggk"/"ogk"/"pvf", "brm"/"lstdq", "shift"/"copy".
std::string_view kernel_type_name(KernelType type);
std::string_view solver_name(kernels::LspiSolver solver);
std::string_view basis_scheme_name(kernels::BasisScheme scheme);

// The swept axes, each non-empty with distinct values, in the order the job file
// lists them.
struct SweepAxes {
  std::vector<KernelType> basis;
  std::vector<std::int32_t> kernels;  // number of kernel centres p
  std::vector<double> sigma;          // kernel width
  std::vector<kernels::LspiSolver> solver;
  std::vector<double> lambda;  // ridge term
};

struct BasisSettings {
  kernels::BasisScheme scheme = kernels::BasisScheme::shift;
  double truncation = 0.0;  // kernel values below it become structural zeros
};

// [pvf]: the proto-value functions of basis "pvf" (jobs/README.md gives each
// default's source in Mahadevan & Maggioni 2007, JMLR 8).
struct PvfSettings {
  kernels::LaplacianKind laplacian = kernels::LaplacianKind::normalized;
  kernels::EdgeAffinity edge_weights = kernels::EdgeAffinity::unit;
  // How the state basis becomes a state-action basis: "copy" (the PVF papers'
  // phi(s, a), the state basis in action a's block) or "shift" (Eq. (9), as
  // [basis] scheme does for the kernels).
  kernels::BasisScheme actions = kernels::BasisScheme::copy;
};

struct LspiSettings {
  double gamma = 0.9;
  std::int32_t max_iterations = 20;
  bool fold_duplicates = true;  // merge identical transitions into weighted samples
  double min_rcond = 1e-14;     // smaller reciprocal 1-norm condition estimates fail the fit
  kernels::LspiStopping stopping = kernels::LspiStopping::policy_unchanged;
  double weight_tolerance = 1e-5;    // epsilon of the "weights" rule
  bool evaluate_iterations = false;  // store and test every iteration's weights
  kernels::LinearAlgebra linear_algebra = kernels::LinearAlgebra::automatic;
  // lambda as given ("absolute") or times the system's scale ("relative",
  // kernels::RidgeScale says which scale).
  kernels::RidgeScale ridge = kernels::RidgeScale::absolute;
};

struct OutputSettings {
  std::filesystem::path file;    // relative to the working directory
  std::int32_t compression = 4;  // gzip level 0..9
  bool store_matrices = false;   // write LSPI's A and b for every fit
};

struct JobSpec {
  std::string name;  // [A-Za-z0-9_-]+
  std::string task;  // a registered task's name ("maze", "arm", "khepera")
  std::int32_t runs = 1;
  std::uint64_t seed = 0;
  SweepAxes sweep;
  std::any task_config;  // what the task's table parser returned
  BasisSettings basis;
  PvfSettings pvf;
  LspiSettings lspi;
  OutputSettings output;
  // An adaptive study's rule ([adaptive], adaptive_rule.hpp); none: a fixed number of runs.
  std::optional<AdaptiveRule> adaptive;

  std::filesystem::path source_file;  // the job file as it was named
  // Its TOML text, verbatim (stored with the results); with overrides, the job
  // they make, as TOML, under a comment naming the file and the overrides.
  std::string source_text;
  std::vector<std::string> overrides;  // `ggk run --set KEY=VALUE` arguments, in order
  std::vector<std::string> sweeps;     // `ggk run --sweep KEY=V1,V2` arguments, in order
  std::vector<JobInput> inputs;        // the files it names (map, arena), read when loaded
  // Every key with the value used, defaults filled in (resolved_config.hpp): what
  // --resume compares, so that respellings and defaults never count.
  ResolvedConfig resolved;
  // A run configuration of a study (study.hpp) with run-level axes: the group
  // under /<task> its runs live in ("config_003"). Empty for a plain job, whose
  // runs are /<task>/run_NNN.
  std::string configuration_group;
};

// The job's task configuration as the type its task's table parser returns.
// Throws std::logic_error (a programmer error) when it holds another type.
template <class Config>
const Config& task_config_as(const JobSpec& job) {
  if (const Config* config = std::any_cast<Config>(&job.task_config)) return *config;
  throw std::logic_error("job '" + job.name + "' (task '" + job.task + "') holds no " +
                         typeid(Config).name() + " configuration");
}

}  // namespace ggk::engine
