#include "engine/tasks/python_env/python_env_task.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <pybind11/embed.h>
#include <toml++/toml.h>

#include "engine/job/job_input.hpp"
#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/continuous_table.hpp"
#include "engine/tasks/continuous_task.hpp"
#include "engine/tasks/python_env/python_runtime.hpp"

namespace ggk::engine {

namespace {

namespace py = pybind11;
namespace fs = std::filesystem;

// The task's configuration: plain data (the job is copied between threads).
struct PythonEnvTask {
  std::string factory;      // "package.module:callable"
  toml::table kwargs;       // [python_env.kwargs]
  std::string module_path;  // absolute folder put first on sys.path; empty: none
  std::int32_t observation_dimension = 0;
  std::int32_t num_actions = 0;
  ContinuousProtocol protocol;
};

constexpr std::array<std::string_view, 9> kKeys = {
    "series",  "steps_per_series", "test_episodes", "test_max_steps", "som", "scale",
    "factory", "kwargs",           "path"};

// The exception's type and message, without pybind11's traceback ("At:").
std::string exception_line(const py::error_already_set& error) {
  std::string text = error.what();
  if (const std::size_t at = text.find("\n\nAt:"); at != std::string::npos) text.resize(at);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  if (const std::size_t last = text.rfind('\n'); last != std::string::npos) {
    text = text.substr(last + 1);
  }
  return text;
}

py::object to_python(const toml::node& node) {
  if (const auto* t = node.as_table()) {
    py::dict dict;
    for (const auto& [key, value] : *t) dict[py::str(std::string(key.str()))] = to_python(value);
    return dict;
  }
  if (const auto* a = node.as_array()) {
    py::list list;
    for (const toml::node& element : *a) list.append(to_python(element));
    return list;
  }
  if (const auto* v = node.as_integer()) return py::int_(v->get());
  if (const auto* v = node.as_floating_point()) return py::float_(v->get());
  if (const auto* v = node.as_boolean()) return py::bool_(v->get());
  if (const auto* v = node.as_string()) return py::str(v->get());
  throw EnvironmentError("[python_env.kwargs] holds a date or time: give it as a string");
}

// The environment object of `task` (the GIL held): the module imported from
// the task's path, the factory called with its keyword arguments. Throws
// EnvironmentError saying what failed.
py::object make_environment(const PythonEnvTask& task) {
  const std::size_t colon = task.factory.find(':');
  const std::string module_name = task.factory.substr(0, colon);
  const std::string callable_name = task.factory.substr(colon + 1);
  py::module_ module;
  try {
    if (!task.module_path.empty()) {
      py::list path = py::module_::import("sys").attr("path");
      if (!path.contains(task.module_path)) path.insert(0, task.module_path);
    }
    module = py::module_::import(module_name.c_str());
  } catch (const py::error_already_set& error) {
    std::string tried = task.module_path.empty() ? "" : task.module_path + ", then ";
    throw EnvironmentError("cannot import '" + module_name + "': " + exception_line(error) +
                           " (looked in " + tried + "PYTHONPATH and the standard places)");
  }
  if (!py::hasattr(module, callable_name.c_str())) {
    throw EnvironmentError("module '" + module_name + "' has no '" + callable_name + "'");
  }
  try {
    py::dict kwargs = to_python(task.kwargs);
    return module.attr(callable_name.c_str())(**kwargs);
  } catch (const py::error_already_set& error) {
    throw EnvironmentError(task.factory + "(...) raised " + exception_line(error));
  }
}

// The numbers of a flat, finite observation (`from` names the call that returned
// it); throws EnvironmentError naming what is wrong.
std::vector<double> observation_values(const py::handle& observation, std::string_view from) {
  if (py::hasattr(observation, "shape")) {
    const py::tuple shape = observation.attr("shape");
    if (shape.size() != 1) {
      throw EnvironmentError(std::string(from) + " returned an observation of shape " +
                             std::string(py::repr(shape)) +
                             ": ggk needs a flat vector (a 1-D Box)");
    }
  }
  std::vector<double> values;
  try {
    for (const py::handle& x : py::iter(observation)) values.push_back(x.cast<double>());
  } catch (const py::error_already_set& error) {
    throw EnvironmentError(std::string(from) + " returned an observation that is not a flat " +
                           "sequence of numbers: " + exception_line(error));
  } catch (const py::cast_error&) {
    throw EnvironmentError(std::string(from) + " returned an observation that is not a flat " +
                           "sequence of numbers");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw EnvironmentError(std::string(from) + " returned a non-finite observation (element " +
                             std::to_string(i) + " is " + std::to_string(values[i]) + ")");
    }
  }
  return values;
}

void write_observation(const py::handle& observation, std::string_view from,
                       std::span<double> out) {
  const std::vector<double> values = observation_values(observation, from);
  if (values.size() != out.size()) {
    throw EnvironmentError(std::string(from) + " returned " + std::to_string(values.size()) +
                           " numbers, the first reset " + std::to_string(out.size()));
  }
  std::copy(values.begin(), values.end(), out.begin());
}

// One environment object behind the continuous protocol; every call holds the GIL.
class PythonEpisode final : public ContinuousEpisode {
 public:
  explicit PythonEpisode(const PythonEnvTask& task) {
    py::gil_scoped_acquire gil;
    env_ = make_environment(task);
  }
  ~PythonEpisode() override {
    py::gil_scoped_acquire gil;
    env_ = py::object();
  }
  PythonEpisode(const PythonEpisode&) = delete;
  PythonEpisode& operator=(const PythonEpisode&) = delete;

  void start_walk(kernels::RandomStream& random, std::span<double> observation) override {
    reset(random, observation);
  }
  void start_test(kernels::RandomStream& random, std::span<double> observation) override {
    reset(random, observation);
  }
  ContinuousStep step(std::int32_t action, kernels::RandomStream&,
                      std::span<double> observation) override {
    py::gil_scoped_acquire gil;
    py::object result;
    try {
      result = env_.attr("step")(action);
    } catch (const py::error_already_set& error) {
      throw EnvironmentError("step(" + std::to_string(action) + ") raised " +
                             exception_line(error));
    }
    if (!py::isinstance<py::tuple>(result) || py::len(result) != 5) {
      throw EnvironmentError(
          "step must return (observation, reward, terminated, truncated, info), got " +
          std::string(py::repr(result)).substr(0, 200));
    }
    const py::tuple t = result;
    write_observation(t[0], "step", observation);
    last_.assign(observation.begin(), observation.end());
    ContinuousStep step;
    try {
      step.reward = t[1].cast<double>();
      step.terminal = t[2].cast<bool>();
      step.truncated = t[3].cast<bool>();
    } catch (const py::cast_error&) {
      throw EnvironmentError("step returned a reward that is no number or flags that are no bools");
    }
    if (!std::isfinite(step.reward)) throw EnvironmentError("step returned a non-finite reward");
    return step;
  }
  void trace(std::vector<double>& out) const override {
    out.insert(out.end(), last_.begin(), last_.end());
  }

 private:
  void reset(kernels::RandomStream& random, std::span<double> observation) {
    const std::int64_t seed = random.uniform_index(std::int64_t{1} << 31);
    py::gil_scoped_acquire gil;
    py::object result;
    try {
      result = env_.attr("reset")(py::arg("seed") = seed);
    } catch (const py::error_already_set& error) {
      throw EnvironmentError("reset(seed=" + std::to_string(seed) + ") raised " +
                             exception_line(error));
    }
    if (!py::isinstance<py::tuple>(result) || py::len(result) != 2) {
      throw EnvironmentError("reset must return (observation, info), got " +
                             std::string(py::repr(result)).substr(0, 200));
    }
    write_observation(py::tuple(result)[0], "reset", observation);
    last_.assign(observation.begin(), observation.end());
  }

  py::object env_;
  std::vector<double> last_;  // the latest observation: the trajectories' points
};

// What the job needs to know of the environment, by creating and resetting one
// (seed 0): its action count, its observation's length and the Box's bounds.
struct Inspection {
  std::int32_t actions = 0;
  std::int32_t dimension = 0;
  std::vector<double> low, high;  // empty where the Box gives none
};

Inspection inspect(const PythonEnvTask& task) {
  python::ensure_interpreter();
  py::gil_scoped_acquire gil;
  const py::object env = make_environment(task);
  for (const char* method : {"reset", "step"}) {
    if (!py::hasattr(env, method)) {
      throw EnvironmentError("the object " + task.factory + " returned has no " + method +
                             "(): ggk needs the Gymnasium API (reset, step, action_space)");
    }
  }
  Inspection result;
  if (!py::hasattr(env, "action_space") || !py::hasattr(env.attr("action_space"), "n")) {
    throw EnvironmentError(
        "its action_space has no n: ggk needs a discrete action set "
        "(gymnasium.spaces.Discrete)");
  }
  try {
    const auto n = env.attr("action_space").attr("n").cast<std::int64_t>();
    if (n < 1 || n > 1'000'000) throw EnvironmentError("action_space.n is " + std::to_string(n));
    result.actions = static_cast<std::int32_t>(n);
    if (py::hasattr(env.attr("action_space"), "start") &&
        env.attr("action_space").attr("start").cast<std::int64_t>() != 0) {
      throw EnvironmentError("its Discrete action space starts at " +
                             std::string(py::repr(env.attr("action_space").attr("start"))) +
                             ": ggk's actions are 0 .. n-1");
    }
  } catch (const py::cast_error&) {
    throw EnvironmentError("action_space.n is no integer: ggk needs a discrete action set");
  }
  py::object reset;
  try {
    reset = env.attr("reset")(py::arg("seed") = 0);
  } catch (const py::error_already_set& error) {
    throw EnvironmentError("reset(seed=0) raised " + exception_line(error));
  }
  if (!py::isinstance<py::tuple>(reset) || py::len(reset) != 2) {
    throw EnvironmentError("reset(seed=0) must return (observation, info), got " +
                           std::string(py::repr(reset)).substr(0, 200));
  }
  const std::vector<double> first = observation_values(py::tuple(reset)[0], "reset(seed=0)");
  if (first.empty()) throw EnvironmentError("reset(seed=0) returned an empty observation");
  result.dimension = static_cast<std::int32_t>(first.size());
  if (py::hasattr(env, "observation_space")) {
    const py::object space = env.attr("observation_space");
    try {
      if (py::hasattr(space, "low") && py::hasattr(space, "high")) {
        for (const py::handle& x : py::iter(space.attr("low")))
          result.low.push_back(x.cast<double>());
        for (const py::handle& x : py::iter(space.attr("high")))
          result.high.push_back(x.cast<double>());
      }
    } catch (const std::exception&) {
      result.low.clear();
      result.high.clear();
    }
  }
  return result;
}

PythonEnvTask parse_table(const TomlTableReader& job, const fs::path& job_dir) {
  const std::optional<TomlTableReader> table = job.subtable("python_env", kKeys);
  if (!table)
    job.fail("python_env", "required table [python_env] is missing (task = \"python_env\")");
  PythonEnvTask task;
  task.factory = table->string("factory");
  const std::size_t colon = task.factory.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == task.factory.size() ||
      task.factory.find(':', colon + 1) != std::string::npos) {
    table->fail("factory", "expected \"package.module:callable\", got \"" + task.factory + "\"");
  }
  if (table->has("path")) {
    const std::string path = table->string("path");
    fs::path folder = fs::absolute(job_dir / path).lexically_normal();
    std::error_code error;
    // As for maps and arenas (job_input.hpp): a relative folder missing beside a
    // job copied out of the project is looked up in the project's jobs/ folder.
    const fs::path shipped = project_jobs_dir();
    if (!fs::is_directory(folder, error) && fs::path(path).is_relative() && !shipped.empty() &&
        fs::is_directory(shipped / path, error)) {
      folder = (shipped / path).lexically_normal();
    }
    if (!fs::is_directory(folder, error)) {
      table->fail("path", "no folder " + folder.string() +
                              " (relative to the job file's folder, else to the project's jobs/)");
    }
    task.module_path = folder.string();
  }
  if (const toml::node* kwargs = table->find("kwargs")) {
    if (!kwargs->is_table()) table->fail("kwargs", "expected a table of keyword arguments");
    task.kwargs = *kwargs->as_table();
  }
  Inspection found;
  try {
    found = inspect(task);
  } catch (const EnvironmentError& error) {
    table->fail("factory", error.what());
  }
  task.observation_dimension = found.dimension;
  task.num_actions = found.actions;
  // The scale's default: the Box's range per dimension where it is finite, else 1.
  std::vector<std::string> names;
  std::vector<ObservationDimension> dimensions;
  names.reserve(static_cast<std::size_t>(found.dimension));
  for (std::int32_t d = 0; d < found.dimension; ++d) names.push_back("dim_" + std::to_string(d));
  for (std::int32_t d = 0; d < found.dimension; ++d) {
    const auto i = static_cast<std::size_t>(d);
    double scale = 1.0;
    if (found.low.size() == names.size() && found.high.size() == names.size()) {
      const double range = found.high[i] - found.low[i];
      if (std::isfinite(range) && range > 0.0) scale = range;
    }
    dimensions.push_back({names[i], scale});
  }
  ContinuousProtocol defaults;
  defaults.series = 200;
  defaults.steps_per_series = 100;
  defaults.test_episodes = 10;
  defaults.test_max_steps = 500;
  defaults.som_grid_from_samples = true;
  task.protocol = read_continuous_protocol(*table, defaults, dimensions);
  check_kernel_widths(job, continuous_distance_scale(task.protocol, found.dimension));
  return task;
}

// The share of test episodes that ended before the cap (a fraction).
constexpr char kEnded[] = "success_rate";

ContinuousEnvironment environment(const PythonEnvTask& task) {
  python::ensure_interpreter();
  ContinuousEnvironment env;
  env.observation_dimension = task.observation_dimension;
  env.num_actions = task.num_actions;
  for (std::int32_t a = 0; a < task.num_actions; ++a) env.action_names.push_back(std::to_string(a));
  env.new_episode = [&task] { return std::make_unique<PythonEpisode>(task); };
  env.trace_dimension = task.observation_dimension;  // the observation: no hidden state is seen
  env.ended_metric = kEnded;
  return env;
}

ContinuousSizes sizes(const PythonEnvTask& task) {
  const double d = task.observation_dimension;
  return {d, static_cast<double>(task.num_actions), d, 0.0, 0.0};
}

}  // namespace

TaskDefinition python_env_task_definition() {
  return continuous_task_definition<parse_table, environment, sizes>("python_env");
}

}  // namespace ggk::engine
