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


def dims_of(dataset, fallback):
    """A dataset's axis names: its `dims` attribute (engine/tasks/dataset_spec.hpp),
    or `fallback` for a file written before datasets named their axes."""
    dims = dataset.attrs.get("dims")
    return tuple(text(dims).split(",")) if dims is not None else tuple(fallback)


def labelled(dataset, fallback_dims=None, name=None, coords=None, description=None):
    """An h5py dataset as an xarray DataArray: dims from its `dims` attribute
    (`fallback_dims`, else dim_0, dim_1, ..., for older files), its `units` and
    `description` as attrs, and those of `coords` whose axis it has."""
    data = dataset[()]
    fallback = fallback_dims or tuple(f"dim_{i}" for i in range(data.ndim))
    dims = dims_of(dataset, fallback)
    attrs = {key: text(dataset.attrs[key]) for key in ("units", "description")
             if key in dataset.attrs}
    if description and "description" not in attrs:
        attrs["description"] = description
    coords = {axis: values for axis, values in (coords or {}).items()
              if axis in dims and len(values) == data.shape[dims.index(axis)]}
    return xr.DataArray(data, dims=dims, coords=coords,
                        name=name or dataset.name.rsplit("/", 1)[-1], attrs=attrs)


def read_fit(f, group_path, task):
    """The labelled arrays of the fit group at `group_path` of an open file:
    axes as the file names them (`dims`), with the run's action names, the
    centres' node ids and the goal test's start states as coordinates."""
    fit = f[group_path]
    run = fit.parent.parent.parent
    arrays = {}
    centres = fit["centers"][:]
    names = (tuple(text(n) for n in run["action_names"][:]) if "action_names" in run
             else action_names(task))
    if "start_states" in run:
        starts = run["start_states"][:]
    elif "steps_to_goal" in fit:
        state_count = len(fit["policy"]) if "policy" in fit else 0
        starts = _start_states(f, run, task, state_count, len(fit["steps_to_goal"]))
    else:
        starts = None
    coords = {"action": list(names), "centre": centres}
    if starts is not None:
        coords["start"] = starts
    state_dim = "state"
    for name in ("policy", "unit_policy", "state_values"):
        if name in fit:
            array = labelled(fit[name], ("node",) if name == "unit_policy" else (state_dim,))
            axis = array.dims[0]
            array = array.assign_coords({axis: np.arange(array.sizes[axis])})
            if name != "state_values":
                array.attrs["action_names"] = list(names)
            arrays[name] = array
    if "weights" in fit and len(centres):
        stored = labelled(fit["weights"], ("coefficient",))
        m = stored.size // len(centres)
        # Coefficient a*p + j of w is action a, centre j (dataset_schema.cpp).
        arrays["weights"] = xr.DataArray(
            stored.values.reshape(m, len(centres)), dims=("action", "centre"),
            coords={"action": list(action_names(task, m)) if len(names) != m else list(names),
                    "centre": centres},
            name="weights", attrs={"description": "w: Q(s, a) = sum_j w[a, j] phi_j(s, a)"})
    if "steps_to_goal" in fit:
        arrays["steps_to_goal"] = labelled(
            fit["steps_to_goal"], ("start",), coords=coords,
            description="greedy steps to a goal per start, -1 = failed")
    if "evaluation/returns" in fit:
        arrays["returns"] = labelled(fit["evaluation/returns"], ("episode",), name="returns")
        arrays["returns"] = arrays["returns"].assign_coords(
            episode=np.arange(arrays["returns"].sizes["episode"]))
    if "evaluation" in fit:
        for name in fit["evaluation"]:
            if name.startswith("trajectory_"):
                poses = labelled(fit["evaluation"][name], ("step", "pose"))
                arrays["evaluation_" + name] = poses.assign_coords(
                    {poses.dims[1]: ["x", "y", "heading"]})
    for name in fit:
        if name.startswith("trajectory_"):
            arrays[name] = labelled(fit[name], ("step",),
                                    description="states of the greedy walk")
    if "history" in fit:
        history = fit["history"]
        variables = {name: labelled(history[name], ("iteration", "coefficient")[
            :history[name].ndim]) for name in history}
        if variables:
            arrays["history"] = xr.Dataset(variables).assign_coords(
                iteration=np.arange(1, next(iter(variables.values())).sizes["iteration"] + 1))
    arrays["centers"] = labelled(fit["centers"], ("centre",),
                                 description="graph nodes used as kernel centres")
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

