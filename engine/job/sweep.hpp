#pragma once
// The points of a job's sweep: the Cartesian product of its axes.
//
// Order (fixed, documented in jobs/README.md): basis, kernels, sigma, solver,
// lambda, with the last axis varying fastest, each axis in the order the job file
// lists its values. Point i has index i. Every run of the job fits every point.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/job_spec.hpp"

namespace ggk::engine {

// The keys of a job file's [sweep] table, one per axis.
inline constexpr std::array<std::string_view, 5> kSweepTableKeys = {"basis", "kernels", "sigma",
                                                                    "solver", "lambda"};

// One key = value of a study axis (study.hpp), the value as canonical TOML text
// (resolved_config.hpp: 30 and 30.0 of a float key read alike).
struct AxisAssignment {
  std::string key;    // dotted job key, "khepera.motion.turn_deg"
  std::string value;  // canonical TOML text, "30.0"
};

struct SweepPoint {
  std::int32_t index = 0;  // position in expand_sweep()'s result
  KernelType basis = KernelType::ggk;
  std::int32_t kernels = 0;
  double sigma = 0.0;
  kernels::LspiSolver solver = kernels::LspiSolver::brm;
  double lambda = 0.0;
  // The fit-level study keys beyond the five axes (study.hpp: `lspi.*`): which of
  // the run configuration's fit variants, and the LSPI settings it makes (the
  // job's [lspi] for a job without such axes).
  std::int32_t variant = 0;
  LspiSettings lspi;
  // The variant's study keys as `key=value` joined by ',' ("lspi.max_iterations=50"),
  // string values unquoted; empty without fit-level study keys. Part of the fit's
  // group name (run_store.hpp).
  std::string variant_label;
  // Every study axis's value at this fit: the run configuration's, then the
  // variant's (the summary's axis columns). Empty for a job without study axes.
  std::vector<AxisAssignment> study_values;
};

std::vector<SweepPoint> expand_sweep(const JobSpec& job);

// The LSPI settings of one fit: the point's [lspi] settings (the job's, or its fit
// variant's) with the point's solver and ridge (lambda).
kernels::LspiOptions lspi_options(const SweepPoint& point);

}  // namespace ggk::engine
