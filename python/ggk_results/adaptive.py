"""An adaptive study's cells (issue 35; engine/store/adaptive_state.hpp is the
C++ original, `ggk info --adaptive --csv` prints the same table): the looks
replayed from the file's complete runs, each cell (per comparison AXIS=A,B and
metric, a point of the other axes) judged by the anytime-valid confidence
sequence of its paired differences A - B over runs 0 .. n-1."""

import math
import tomllib

import h5py
import numpy as np
import pandas as pd

from .metric_specs import is_share, read_metric_specs, spec_of
from .results_file import summary_frame
from .sequential import asymptotic_confidence_sequence, confidence_sequence

# The columns of a summary that are no axis of a fit.
NOT_AXES = ("run", "configuration", "sweep_point", "status")


def adaptive_rule(path):
    """The [adaptive] table of the job stored with the results file at `path`
    (a dict), or None for a study of a fixed number of runs."""
    with h5py.File(path, "r") as f:
        job = f.attrs["job"]
        runs = int(f.attrs["runs"])
    job = job.decode() if isinstance(job, bytes) else job
    table = tomllib.loads(job).get("adaptive")
    if table is None:
        return None
    compare = table["compare"]
    return {
        "compare": [compare] if isinstance(compare, str) else list(compare),
        "metrics": [table["metrics"]] if isinstance(table["metrics"], str) else list(table["metrics"]),
        "target": table.get("target", "sign"),
        "width": float(table.get("width", 0.0)),
        "batch": int(table.get("batch", 5)),
        "level": float(table.get("level", 0.95)),
        "correction": table.get("correction", "bonferroni"),
        "method": table.get("method", "bernstein"),
        "range": {k: (float(v[0]), float(v[1])) for k, v in table.get("range", {}).items()},
        "max_runs": runs,
    }


def _same(stored, given):
    if str(stored) == given:
        return True
    try:
        return float(stored) == float(given)
    except (TypeError, ValueError):
        return False


def adaptive_cells(path, rule=None):
    """The cells of the adaptive study at `path` as a DataFrame: compare, the other
    axes, metric, state (+, -, narrow, open, capped, failed), runs, difference
    (the mean), cs_low, cs_high; its attrs hold looks, done, runs_wanted (per
    configuration), cell_level, and fits_wanted / fits_whole (the fits the runs
    hold, a decided cell's left out of the runs after it, and those of whole runs).

    `rule` (a dict as adaptive_rule returns, keys left out taking the file's or
    the defaults) replays another rule on the file's runs: what it would have
    decided, and after how many runs, on any study whose runs it covers (a fixed
    one included: run r is the same whoever asks for it)."""
    stored = adaptive_rule(path)
    if rule is not None:
        with h5py.File(path, "r") as f:
            runs = int(f.attrs["runs"])
        defaults = {"target": "sign", "width": 0.0, "batch": 5, "level": 0.95,
                    "correction": "bonferroni", "method": "bernstein", "range": {},
                    "max_runs": runs}
        rule = {**defaults, **(stored or {}), **rule}
        for key in ("compare", "metrics"):
            if isinstance(rule.get(key), str):
                rule[key] = [rule[key]]
    else:
        rule = stored
    if rule is None:
        raise ValueError(f"{path}: no adaptive study (its job has no [adaptive] table)")
    frame = summary_frame(path)
    with h5py.File(path, "r") as f:
        task = f.attrs["task"]
        task = task.decode() if isinstance(task, bytes) else task
        configurations = max(1, sum(1 for k in f[task] if k.startswith("config_")))
        specs = read_metric_specs(f, task)
        # A shard of the study (ggk run --shard I/N): its configurations, judged
        # at the level of the whole study's cells.
        judged = (set(int(c) for c in f.attrs["configurations_selected"])
                  if "configurations_selected" in f.attrs else set(range(configurations)))
        study_cells = int(f.attrs["adaptive_cells"]) if "adaptive_cells" in f.attrs else None
    if "configuration" not in frame.columns:
        frame = frame.assign(configuration=0)
    metric_columns = set(frame.columns[frame.columns.get_loc("status") + 1:])
    axes = [c for c in frame.columns if c not in NOT_AXES and c not in metric_columns]
    batch, max_runs = rule["batch"], rule["max_runs"]
    wanted = [min(batch, max_runs) if c in judged else 0 for c in range(configurations)]
    ranges = {}
    for metric in rule["metrics"]:
        if metric not in metric_columns or metric == "fit_seconds":
            raise ValueError(f"{path}: the task reports no metric {metric!r}")
        # As ggk decides: the rule's range, else [0, 1] for a declared share.
        share = is_share(spec_of(metric, specs))
        ranges[metric] = rule["range"].get(metric, (0.0, 1.0) if share else None)
        if ranges[metric] is None and rule["method"] == "asymptotic":
            ranges[metric] = (-math.inf, math.inf)
        if ranges[metric] is None:
            raise ValueError(f"{path}: {metric} has no range: give [adaptive.range]")
    pairings = []  # (comparison, key, {run: row a}, {run: row b}, conf a, conf b)
    for c, text in enumerate(rule["compare"]):
        axis, values = text.split("=", 1)
        a, b = values.split(",")
        others = [x for x in axes if x != axis]
        side_a = frame[[_same(v, a) for v in frame[axis]]]
        side_b = frame[[_same(v, b) for v in frame[axis]]]
        order = {}
        for row in side_a.to_dict("records"):
            key = tuple(str(row[o]) for o in others)
            point = (int(row["configuration"]) << 32) + int(row["sweep_point"])
            order[key] = min(order.get(key, point), point)
        for key in sorted(order, key=order.get):
            mask_a = np.all([side_a[o].astype(str) == k for o, k in zip(others, key)], axis=0)
            mask_b = np.all([side_b[o].astype(str) == k for o, k in zip(others, key)], axis=0)
            rows_a, rows_b = side_a[mask_a].set_index("run"), side_b[mask_b].set_index("run")
            pairings.append((c, others, key, rows_a, rows_b,
                             int(rows_a["configuration"].iloc[0]),
                             int(rows_b["configuration"].iloc[0]) if len(rows_b) else -1,
                             [(int(rows["configuration"].iloc[0]), int(rows["sweep_point"].iloc[0]))
                              for rows in (rows_a, rows_b) if len(rows)]))
    count = study_cells if study_cells is not None else len(pairings) * len(rule["metrics"])
    alpha = 1.0 - rule["level"]
    cell_level = 1.0 - alpha / count if rule["correction"] == "bonferroni" and count else rule["level"]
    # The points each stored run holds, and the points each configuration's runs
    # need from a first run on (as ggk decides: a look's new runs hold the points
    # of the cells still open, and those in no cell).
    held = [{} for _ in range(configurations)]
    for conf, run, point in zip(frame["configuration"], frame["run"], frame["sweep_point"]):
        held[int(conf)].setdefault(int(run), set()).add(int(point))
    all_points = [sorted({p for points in held[c].values() for p in points})
                  for c in range(configurations)]
    segments = [[(0, all_points[c])] for c in range(configurations)]
    cells_of_point = {}
    for i, pairing in enumerate(pairings):
        for point in pairing[7]:
            cells_of_point.setdefault(point, []).append(i * len(rule["metrics"]))

    def needed(conf, run):
        return [points for first, points in segments[conf] if first <= run][-1]

    def holds(conf, runs):
        return all(r in held[conf] and set(needed(conf, r)) <= held[conf][r] for r in range(runs))

    looks = 1
    decided = {}  # cell index -> the cell as a complete look decided it
    while True:
        complete = all(holds(c, wanted[c]) for c in judged)
        cells = []
        for c, others, key, rows_a, rows_b, conf_a, conf_b, _ in pairings:
            for metric in rule["metrics"]:
                if len(cells) in decided:
                    cells.append(decided[len(cells)])
                    continue
                low, high = ranges[metric]
                width = high - low
                n = min(wanted[conf_a], wanted[conf_b]) if conf_b >= 0 else 0
                differences, failed = [], False
                for r in range(n):
                    if r not in rows_a.index or r not in rows_b.index:
                        break
                    x, y = float(rows_a.at[r, metric]), float(rows_b.at[r, metric])
                    if math.isnan(x) or math.isnan(y):
                        failed = True
                        break
                    differences.append(x - y)
                state, mean, lower, upper = "open", math.nan, math.nan, math.nan
                if failed:
                    state = "failed"
                elif differences:
                    mean = sum(differences) / len(differences)
                    if rule["method"] == "bernstein":
                        lows, highs = confidence_sequence(differences, -width, width, cell_level)
                    else:
                        lows, highs = asymptotic_confidence_sequence(differences, cell_level,
                                                                     max_runs)
                    lower, upper = lows[-1], highs[-1]
                    if rule["target"] == "sign" and lower > 0:
                        state = "+"
                    elif rule["target"] == "sign" and upper < 0:
                        state = "-"
                    elif rule["target"] == "width" and upper - lower < rule["width"]:
                        state = "narrow"
                if state == "open" and complete and len(differences) >= max_runs:
                    state = "capped"
                axis_text = rule["compare"][c].split("=", 1)
                sides = axis_text[1].split(",")
                cells.append({"compare": f"{axis_text[0]} {sides[0]} - {sides[1]}",
                              **dict(zip(others, key)), "metric": metric, "state": state,
                              "runs": len(differences), "difference": mean, "cs_low": lower,
                              "cs_high": upper, "_confs": (conf_a, conf_b)})
                if complete and state in ("+", "-", "narrow"):
                    decided[len(cells) - 1] = cells[-1]
        done = False
        if complete:
            following = list(wanted)
            for cell in cells:
                if cell["state"] != "open":
                    continue
                asked = min(cell["runs"] + batch, max_runs)
                for conf in cell["_confs"]:
                    if conf >= 0:
                        following[conf] = max(following[conf], asked)
            if following == wanted:
                done = True
            else:
                for conf in range(configurations):
                    if following[conf] == wanted[conf]:
                        continue
                    keep = [p for p in all_points[conf]
                            if (conf, p) not in cells_of_point
                            or any(cells[first + m]["state"] == "open"
                                   for first in cells_of_point[(conf, p)]
                                   for m in range(len(rule["metrics"])))]
                    if keep != segments[conf][-1][1]:
                        segments[conf].append((wanted[conf], keep))
                wanted, looks = following, looks + 1
                continue
        table = pd.DataFrame([{k: v for k, v in cell.items() if k != "_confs"} for cell in cells])
        # The fits the look's runs hold (a decided cell's left out of the runs
        # after it) and those of whole runs, as `ggk info --adaptive` counts them.
        fits_wanted = sum(len(needed(c, r)) for c in judged for r in range(wanted[c]))
        fits_whole = sum(len(all_points[c]) * wanted[c] for c in judged)
        table.attrs.update(looks=looks, done=done, runs_wanted=wanted, cell_level=cell_level,
                           fits_wanted=fits_wanted, fits_whole=fits_whole)
        return table
