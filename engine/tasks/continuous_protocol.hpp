#pragma once
// The experiment protocol shared by tasks whose states are real vectors
// (Khepera, pendulum, mountain car, acrobot): per run, random-walk series of
// observations -> the observations scaled per dimension -> a self-organising map
// over them (the paper's quantiser, sec. 4.2) -> the graph over its units from
// the samples' transitions (weight = prototype distance) -> p random centres
// among the occupied units -> continuous GGK (ED(s, n(s)) + SP(n(s), c), n(s) the
// observation's nearest occupied unit), OGK (ED to the centre's prototype) or PVF
// (the nearest unit's values) -> copy or shift basis -> LSPI -> greedy test
// episodes (mean return, the share of episodes that ended, mean length).
//
// A task supplies only its simulator behind ContinuousEpisode (start of a walk,
// start of a test, one step), its actions, its per-dimension scale and the name
// of its ended-episode metric; continuous_table.hpp reads the protocol's keys.
// The samples are stored unscaled, exactly as the simulator produced them; the
// SOM's prototypes and every distance are in scaled units (observation / scale).
//
// A run's samples, SOM, graph and distances are computed once and shared by all
// its fits; fits run as oneTBB tasks; every random number comes from streams
// keyed by (seed, run, purpose), so the record is identical for any thread count.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/graph_protocol.hpp"
#include "engine/tasks/run_memory.hpp"
#include "engine/tasks/run_record.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/self_organizing_map.hpp"

namespace ggk::engine {

// Thrown by a ContinuousEpisode whose simulator fails (a Python environment
// raised, returned a bad observation): during the walks the run fails, naming
// the series and step; during a fit's test the fit is recorded with status
// "environment_failed" and the message, and the run goes on.
class EnvironmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What one step of a continuous environment reports (its observation is written
// into the caller's span).
struct ContinuousStep {
  double reward = 0.0;
  // The next state is absorbing: the sample does not bootstrap, the walk's
  // series and a test episode end (a goal reached, a pendulum fallen).
  bool terminal = false;
  // The series or episode ends without an absorbing state (a time limit).
  bool truncated = false;
  // Ends a test episode but not a walk's series (the Khepera's collision: the
  // move is undone and the random walk goes on).
  bool stop = false;
};

// One simulated system and its hidden state (the Khepera's pose, the pendulum's
// angle and velocity). Each walk and each test episode drives one object from
// one thread; objects are never shared.
class ContinuousEpisode {
 public:
  virtual ~ContinuousEpisode() = default;
  // A series of the random walks starts here (the task's sampling distribution);
  // writes its first observation.
  virtual void start_walk(kernels::RandomStream& random, std::span<double> observation) = 0;
  // A test episode starts here (the task's evaluation start); writes its first
  // observation.
  virtual void start_test(kernels::RandomStream& random, std::span<double> observation) = 0;
  virtual ContinuousStep step(std::int32_t action, kernels::RandomStream& random,
                              std::span<double> observation) = 0;
  // Appends the hidden state (ContinuousEnvironment::trace_fields values) for
  // the test episodes' trajectories.
  virtual void trace(std::vector<double>& out) const = 0;
};

struct ContinuousEnvironment {
  std::int32_t observation_dimension = 1;
  std::int32_t num_actions = 1;
  std::vector<std::string> action_names;  // of codes 0 .. num_actions - 1
  // A new episode object; called from parallel tasks, so it must be thread-safe.
  std::function<std::unique_ptr<ContinuousEpisode>()> new_episode;
  // Values per trajectory point (ContinuousEpisode::trace).
  std::int32_t trace_dimension = 1;
  // The fraction of test episodes that ended (terminal or stop) before the cap,
  // by its name: "collision_fraction" (Khepera), "success_rate" (a goal task),
  // "fall_fraction" (pendulum).
  std::string ended_metric = "ended_fraction";
  // A step's reward lies in [reward_low, reward_high] (the task's physics; the
  // pendulum's -1 or 0): the bounds of mean_return's declared range.
  double reward_low = -kUnbounded;
  double reward_high = kUnbounded;
  // mean_return's range for test episodes of at most `steps` steps, where the
  // task knows a tighter one (the Khepera's episode stops at its first
  // collision); unset: `steps` times the reward bounds (and 0).
  std::function<std::pair<double, double>(std::int32_t steps)> return_range;
  // Non-empty: the walks' per-sample stop flags are stored under this name
  // ("samples/collisions").
  std::string stop_flags_array;
  // Arrays the run stores before its SOM (the Khepera's arena, Fig. 4(a)).
  std::vector<NamedArray> run_arrays;
  // Stored as the run's array "observation_scale" when set (a task whose scale
  // is a key); the scale itself is ContinuousProtocol::scale.
  bool store_scale = true;
};

struct ContinuousProtocol {
  std::int32_t series = 1;            // random-walk series per run
  std::int32_t steps_per_series = 1;  // random actions per series (fewer if it ends)
  std::int32_t test_episodes = 1;     // greedy episodes per fit
  std::int32_t test_max_steps = 1;    // steps per test episode at most
  kernels::SomOptions som;
  bool som_grid_from_samples = false;  // rows x cols from the readings (som_grid_for)
  // Per observation dimension: the SOM and every distance see observation / scale.
  std::vector<double> scale;
};

// The per-fit metrics, in summary-column order: mean_return, env.ended_metric (a
// fraction of the episodes), mean_steps (all tested: in the iteration history
// too), then graph_metric_specs() over the unit graph (the stretch's ED between
// the units' prototypes; the kernel gap over every observation of the walks, GGK
// in its continuous form).
// Their ranges: mean_return's env.return_range, else test_max_steps steps of
// the environment's reward bounds (and 0); mean_steps within [0, test_max_steps].
std::vector<MetricSpec> continuous_metric_specs(const ContinuousEnvironment& env,
                                                const ContinuousProtocol& protocol);

// A continuous task's TaskDefinition::datasets: `own` (the task's declarations,
// which override the protocol's for the same path), then the continuous
// protocol's (observation_scale, the SOM, state_units, a fit's unit_policy and
// evaluation), then graph_dataset_specs().
std::vector<DatasetSpecs> continuous_dataset_specs(std::span<const DatasetSpecs> own = {});

// The runs: one run of the protocol for every sweep point. Throws only on
// programmer errors; a fit that cannot start (more kernels than occupied units,
// a failed eigensolve) or whose LSPI system fails is recorded with its status.
RunRecord run_continuous_protocol(const ContinuousEnvironment& env,
                                  const ContinuousProtocol& protocol, const JobSpec& job,
                                  std::int32_t run, std::span<const SweepPoint> points);

// What a run's memory depends on, known before the simulator is built.
struct ContinuousSizes {
  double observation_dimension = 1.0;
  double actions = 1.0;
  double trace_dimension = 1.0;
  double stop_flags = 0.0;       // 1 when the walks' stop flags are stored
  double simulator_bytes = 0.0;  // what the simulator and its run arrays hold
  // The steps a series counts where episodes end long before steps_per_series
  // (the pendulum's random episodes fall after about 9 steps): the estimate
  // follows the samples a run makes; 0: steps_per_series.
  double series_steps = 0.0;
};

// The peak memory of one run (run_memory.hpp) from the job's sizes alone: the
// walks' observations and samples in their copies, the SOM, the unit graph and
// distances, the proto-value functions, per fit the kernel table (and the
// shift scheme's feature table) over every observation and the LSPI system, and
// the fits' results. A series that ends early only lowers the peak.
RunMemoryEstimate estimate_continuous_run(const ContinuousSizes& sizes,
                                          const ContinuousProtocol& protocol, const JobSpec& job);

}  // namespace ggk::engine
