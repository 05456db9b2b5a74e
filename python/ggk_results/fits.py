"""One fit of a results file as labelled arrays (xarray): its weights per
(action, centre), its greedy policy per state (maze, arm) or per reading
(Khepera), its values and test results, and its LSPI history per iteration."""

import tomllib

import numpy as np
import xarray as xr

from .actions import action_names
from .tables import text


class Fit:
    """A fit, read whole. `point` holds the fit group's attributes (the axis
    values, status, message and metrics); `arrays` the labelled arrays (see
    read_fit), also reachable as attributes (fit.weights, fit.policy, ...)."""

    def __init__(self, path, group, point, arrays):
        self.path = path
        self.group = group
        self.point = point
        self.arrays = arrays

    def __getattr__(self, name):
        arrays = self.__dict__.get("arrays", {})
        if name in arrays:
            return arrays[name]
        raise AttributeError(f"{self.group}: no {name!r} (arrays: {', '.join(arrays)})")

    def __repr__(self):
        return f"<Fit {self.path}:{self.group}: {', '.join(self.arrays)}>"


def _start_states(f, run, task, state_count, starts):
    """The state ids that steps_to_goal indexes: every non-goal state in id
    order (engine/tasks: the tests start from each), or None when the goals
    cannot be told from the file."""
    goals = None
    if task == "arm" and "grid/goal" in run and "grid/state_of" in run:
        state_of, goal = run["grid/state_of"][:], run["grid/goal"][:]
        goals = np.unique(state_of[(goal == 1) & (state_of >= 0)])
    elif task == "maze":
        map_text = None
        if "input:maze.map_file" in f.attrs:
            map_text = text(f.attrs["input:maze.map_file"])
        elif "job_resolved" in f.attrs:
            map_text = tomllib.loads(text(f.attrs["job_resolved"])).get("maze.map")
        if map_text is not None:
            # States are the '.' and 'G' cells in row-major order (sims/maze/maze.hpp).
            cells = [c for c in map_text if c in ".G"]
            goals = np.array([i for i, c in enumerate(cells) if c == "G"])
    if goals is None:
        return None
    states = np.setdiff1d(np.arange(state_count), goals)
    return states if len(states) == starts else None


def read_fit(f, group_path, task):
    """The labelled arrays of the fit group at `group_path` of an open file."""
    fit = f[group_path]
    run = fit.parent.parent.parent
    arrays = {}
    centres = fit["centers"][:]
    if "weights" in fit and len(centres):
        weights = fit["weights"][:]
        m = len(weights) // len(centres)
        names = action_names(task, m)
        # Column a*p + j of w is action a, centre j (results/README.md).
        arrays["weights"] = xr.DataArray(
            weights.reshape(m, len(centres)), dims=("action", "centre"),
            coords={"action": list(names), "centre": centres},
            name="weights", attrs={"description": "w: Q(s, a) = sum_j w[a, j] phi_j(s, a)"})
    names = action_names(task)
    state_dim = "reading" if task == "khepera" else "state"
    if "policy" in fit:
        policy = fit["policy"][:]
        arrays["policy"] = xr.DataArray(
            policy, dims=(state_dim,), coords={state_dim: np.arange(len(policy))}, name="policy",
            attrs={"description": "greedy action code per " + state_dim,
                   "action_names": list(names)})
    if "unit_policy" in fit:
        unit_policy = fit["unit_policy"][:]
        arrays["unit_policy"] = xr.DataArray(
            unit_policy, dims=("unit",), coords={"unit": np.arange(len(unit_policy))},
            name="unit_policy", attrs={"description": "greedy action code per SOM unit",
                                       "action_names": list(names)})
    if "state_values" in fit:
        values = fit["state_values"][:]
        arrays["state_values"] = xr.DataArray(
            values, dims=("state",), coords={"state": np.arange(len(values))},
            name="state_values", attrs={"description": "V(s) = max_a Q(s, a)"})
    if "steps_to_goal" in fit:
        steps = fit["steps_to_goal"][:]
        state_count = len(fit["policy"]) if "policy" in fit else 0
        starts = _start_states(f, run, task, state_count, len(steps))
        coords = {"start": starts} if starts is not None else {"start": np.arange(len(steps))}
        arrays["steps_to_goal"] = xr.DataArray(
            steps, dims=("start",), coords=coords, name="steps_to_goal",
            attrs={"description": "greedy steps to a goal from each non-goal start state "
                   "(the coordinate: its state id), -1 = failed"
                   if starts is not None else "greedy steps to a goal per start, -1 = failed"})
    if "evaluation/returns" in fit:
        returns = fit["evaluation/returns"][:]
        arrays["returns"] = xr.DataArray(
            returns, dims=("episode",), coords={"episode": np.arange(len(returns))},
            name="returns", attrs={"description": "return of each evaluation episode"})
    if "evaluation" in fit:
        for name in fit["evaluation"]:
            if name.startswith("trajectory_"):
                poses = fit["evaluation"][name][:]
                arrays["evaluation_" + name] = xr.DataArray(
                    poses, dims=("step", "pose"), coords={"pose": ["x", "y", "heading"]},
                    name=name, attrs={"description": "pose of each step of an evaluation episode "
                                      "(x, y in cm, heading in rad)"})
    for name in fit:
        if name.startswith("trajectory_"):
            trajectory = fit[name][:]
            arrays[name] = xr.DataArray(trajectory, dims=("step",), name=name,
                                        attrs={"description": "states of the greedy walk"})
    if "history" in fit:
        history = fit["history"]
        variables = {}
        for name in history:
            data = history[name][:]
            dims = ("iteration",) if data.ndim == 1 else ("iteration", "feature")
            variables[name] = xr.DataArray(data, dims=dims)
        if variables:
            arrays["history"] = xr.Dataset(variables).assign_coords(
                iteration=np.arange(1, next(iter(variables.values())).sizes["iteration"] + 1))
    arrays["centers"] = xr.DataArray(centres, dims=("centre",), name="centers",
                                     attrs={"description": "graph nodes used as kernel centres"})
    return arrays


def fit_point(fit_group):
    """A fit group's attributes as Python values (str for strings)."""
    return {k: text(v) if isinstance(v, (bytes, str)) else v.tolist() if hasattr(v, "tolist")
            else v for k, v in fit_group.attrs.items()}


def find_fit_group(f, run_path, row):
    """The fit group of run `run_path` whose sweep point is the summary row's."""
    fits = f[run_path]["fits"]
    basis = row["basis"]
    if basis not in fits:
        raise KeyError(f"{f.filename}: /{run_path}/fits has no {basis!r} fits")
    for name, group in fits[basis].items():
        if int(group.attrs["sweep_point"]) == int(row["sweep_point"]):
            return f"{run_path}/fits/{basis}/{name}"
    raise KeyError(f"{f.filename}: /{run_path}/fits/{basis}: no fit of sweep point "
                   f"{int(row['sweep_point'])}")

