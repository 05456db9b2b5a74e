#pragma once
// Any Python environment with the Gymnasium API as a ggk task, on the
// continuous protocol (engine/tasks/continuous_protocol.hpp): `task =
// "python_env"` with `[python_env] factory = "package.module:callable"`, its
// keyword arguments (`[python_env.kwargs]`) and a module `path` (relative to the
// job file; PYTHONPATH is honoured too). The object the callable returns must
// have reset(seed=...) -> (observation, info), step(action) -> (observation,
// reward, terminated, truncated, info), a discrete action_space (its n) and a
// flat real-vector observation.
//
// ggk draws every seed and action from its own streams: a walk's series and a
// test episode start with reset(seed=s), s from the run's sample or evaluation
// stream; the walks' actions are ggk's uniform draws (never action_space.sample
// or numpy's global state). `terminated` ends a series or episode as absorbing,
// `truncated` ends it without. Metrics: mean_return, success_rate (test episodes
// that terminated, not truncated, within test_max_steps) and mean_steps.
//
// The job is read by importing the module, calling the factory and resetting
// the object once (seed 0): a factory that does not import, an object without
// the API, a non-discrete action space or a non-flat observation is refused
// there (JobError at `factory`: exit 2, nothing written). Each walk and each
// fit's test creates its own object; environment calls hold the GIL, a fit's
// numerics do not. A step that raises during the walks fails the run; during a
// fit's test, the fit (status environment_failed, the exception's last line).
// Results are bit-identical for any -j, rank count and shard split whenever the
// environment is deterministic given its seed.

#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

TaskDefinition python_env_task_definition();

}  // namespace ggk::engine
