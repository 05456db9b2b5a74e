// ggk.random_walks and ggk.greedy_episodes: samples from, and tests in, any
// object with the Gymnasium API (reset(seed=...) -> (obs, info), step(action) ->
// (obs, reward, terminated, truncated, info), action_space.n), driven as the
// engine's python_env task drives it (engine/tasks/continuous_episodes.cpp):
// uniformly random actions and reset seeds from ggk's own streams, never the
// environment's sampler; `terminated` ends a series as absorbing, `truncated`
// without. With the task's seed and run, the walks are the task's bit for bit.
#include <cmath>

#include <pybind11/stl.h>

#include "kernels/random_stream.hpp"
#include "kernels/sample_batch.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"

namespace ggk::python {

namespace {

// engine/tasks/seeds.hpp: stream (seed, run, purpose << 24) of a run's samples (1)
// and its evaluation (3).
constexpr std::uint32_t kSamplesPurpose = 1u << 24;
constexpr std::uint32_t kEvaluationPurpose = 3u << 24;

struct RandomWalks {
  kernels::RowMatrixXd observations;  // the series' observations in order, unscaled
  kernels::SampleBatch samples;       // states index the observations' rows
};

std::int32_t action_count(const py::handle& env) {
  try {
    return env.attr("action_space").attr("n").cast<std::int32_t>();
  } catch (const py::error_already_set&) {
    throw py::type_error("the environment has no discrete action_space.n (Gymnasium's Discrete)");
  } catch (const py::cast_error&) {
    throw py::type_error("the environment's action_space.n is not an integer");
  }
}

// The observation as a flat vector of finite floats; ValueError naming `where`.
std::vector<double> observation_of(const py::handle& value, const std::string& where) {
  const auto array = DoubleArray::ensure(value);
  if (!array || array.ndim() != 1 || array.size() == 0) {
    throw py::value_error(where + ": the observation is not a flat vector of numbers");
  }
  std::vector<double> values(array.data(), array.data() + array.size());
  for (const double v : values) {
    if (!std::isfinite(v)) throw py::value_error(where + ": the observation is not finite");
  }
  return values;
}

std::vector<double> reset(const py::handle& env, kernels::RandomStream& random,
                          const std::string& where) {
  const std::int64_t seed = random.uniform_index(std::int64_t{1} << 31);
  const py::object result = env.attr("reset")(py::arg("seed") = seed);
  if (!py::isinstance<py::tuple>(result) || py::len(result) != 2) {
    throw py::value_error(where + ": reset must return (observation, info)");
  }
  return observation_of(py::tuple(result)[0], where);
}

struct Step {
  std::vector<double> observation;
  double reward = 0.0;
  bool terminated = false;
  bool truncated = false;
};

Step step(const py::handle& env, std::int32_t action, const std::string& where) {
  const py::object result = env.attr("step")(action);
  if (!py::isinstance<py::tuple>(result) || py::len(result) != 5) {
    throw py::value_error(where +
                          ": step must return (observation, reward, terminated, truncated, info)");
  }
  const py::tuple t = result;
  Step s{observation_of(t[0], where), t[1].cast<double>(), t[2].cast<bool>(), t[3].cast<bool>()};
  if (!std::isfinite(s.reward)) throw py::value_error(where + ": the reward is not finite");
  return s;
}

RandomWalks random_walks(const py::handle& env, std::int32_t series, std::int32_t steps_per_series,
                         std::uint64_t seed, std::int32_t run) {
  if (series < 1 || steps_per_series < 1) {
    throw py::value_error("series and steps_per_series must be >= 1");
  }
  const std::int32_t m = action_count(env);
  kernels::RandomStream random(seed, static_cast<std::uint32_t>(run), kSamplesPurpose);
  std::vector<std::vector<double>> rows;
  RandomWalks walks;
  for (std::int32_t k = 0; k < series; ++k) {
    const std::string where = "series " + std::to_string(k);
    rows.push_back(reset(env, random, where + ", its start"));
    for (std::int32_t t = 0; t < steps_per_series; ++t) {
      const auto action = static_cast<std::int32_t>(random.uniform_index(m));
      Step s = step(env, action, where + ", step " + std::to_string(t));
      if (s.observation.size() != rows.front().size()) {
        throw py::value_error(where + ", step " + std::to_string(t) +
                              ": the observation changed its length");
      }
      const auto state = static_cast<std::int32_t>(rows.size() - 1);
      walks.samples.add(state, action, s.reward, state + 1, s.terminated);
      rows.push_back(std::move(s.observation));
      if (s.terminated || s.truncated) break;
    }
  }
  walks.observations.resize(static_cast<Eigen::Index>(rows.size()),
                            static_cast<Eigen::Index>(rows.front().size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < rows[i].size(); ++j) {
      walks.observations(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
    }
  }
  return walks;
}

py::dict greedy_episodes(const py::handle& env, const py::function& policy, std::int32_t episodes,
                         std::int32_t max_steps, std::uint64_t seed, std::int32_t run) {
  if (episodes < 1 || max_steps < 1) throw py::value_error("episodes and max_steps must be >= 1");
  const std::int32_t m = action_count(env);
  kernels::RandomStream random(seed, static_cast<std::uint32_t>(run), kEvaluationPurpose);
  std::vector<double> returns;
  std::vector<std::int32_t> lengths;
  std::vector<std::uint8_t> success;
  py::module_ numpy = py::module_::import("numpy");
  for (std::int32_t e = 0; e < episodes; ++e) {
    const std::string where = "test episode " + std::to_string(e);
    std::vector<double> observation = reset(env, random, where + ", its start");
    double total = 0.0;
    std::int32_t steps = 0;
    bool ended = false;
    for (; steps < max_steps; ++steps) {
      const auto action = policy(numpy.attr("array")(observation)).cast<std::int32_t>();
      if (action < 0 || action >= m) {
        throw py::value_error(where + ", step " + std::to_string(steps) + ": the policy chose " +
                              std::to_string(action) + ", not an action in [0, " +
                              std::to_string(m) + ")");
      }
      Step s = step(env, action, where + ", step " + std::to_string(steps));
      total += s.reward;
      observation = std::move(s.observation);
      if (s.terminated || s.truncated) {
        ended = s.terminated;
        ++steps;
        break;
      }
    }
    returns.push_back(total);
    lengths.push_back(steps);
    success.push_back(ended ? 1 : 0);
  }
  py::dict result;
  result["returns"] = to_numpy(std::move(returns));
  result["lengths"] = to_numpy(std::move(lengths));
  result["success"] = to_numpy(std::move(success)).attr("astype")("bool");
  return result;
}

}  // namespace

void bind_environments(py::module_& module) {
  py::class_<RandomWalks>(module, "RandomWalks", "Samples of random walks in an environment.")
      .def_readonly("observations", &RandomWalks::observations,
                    "n x d, the series' observations in order (unscaled)")
      .def_readonly("samples", &RandomWalks::samples,
                    "ggk.Samples whose states and next_states index observations' rows");

  module.def("random_walks", &random_walks, py::arg("env"), py::arg("series"),
             py::arg("steps_per_series"), py::arg("seed"), py::arg("run") = 0,
             R"(Series of uniformly random actions in a Gymnasium-API environment: each series
starts at reset(seed=s), s and the actions drawn from ggk's stream (seed, run,
samples); terminated ends a series as absorbing, truncated without. The python_env
task's walks of run `run` for a job with this seed, bit for bit.)");

  module.def("greedy_episodes", &greedy_episodes, py::arg("env"), py::arg("policy"),
             py::arg("episodes"), py::arg("max_steps"), py::arg("seed"), py::arg("run") = 0,
             R"(Test episodes of policy(observation) -> action from reset(seed=s), s from ggk's
evaluation stream (seed, run): the same starts for every policy (common random
numbers). {"returns", "lengths", "success"} per episode; success: terminated
(not truncated) within max_steps.)");
}

}  // namespace ggk::python
