"""Reading ggk results files (HDF5) for analysis: the per-task summary table,
confidence intervals over runs, and the sweep axes a figure must not pool.
Uses Debian's python3-h5py, numpy, scipy and pandas; run scripts with
/usr/bin/python3 where a pyenv python3 comes first on PATH."""

import math
from pathlib import Path

import h5py
import numpy as np
from scipy import stats

# The sweep axes of every summary row, in sweep order (jobs/README.md).
AXES = ("basis", "kernels", "sigma", "solver", "lambda")


def _decoded(column):
    """A table column with its strings as str: h5py hands the strings of a
    compound dataset (fixed or variable length) over as bytes."""
    if column.dtype.kind == "S":
        return np.char.decode(column, "utf-8")
    if column.dtype.kind == "O":
        return np.array([v.decode("utf-8") if isinstance(v, bytes) else v for v in column],
                        dtype=object)
    return column


def task_of(path):
    with h5py.File(path, "r") as f:
        task = f.attrs["task"]
    return task.decode() if isinstance(task, bytes) else task


def read_summary(path, task=None):
    """The /<task>/summary table as a dict of numpy columns, strings as str.
    task defaults to the file's."""
    task = task or task_of(path)
    with h5py.File(path, "r") as f:
        table = f[f"/{task}/summary"][:]
    return {name: _decoded(table[name]) for name in table.dtype.names}


def summary_frame(path, task=None):
    """The summary as a pandas DataFrame with str columns, so that
    df[df.basis == "ggk"] selects rows."""
    import pandas as pd

    return pd.DataFrame(read_summary(path, task))



def run_group(f, task, run=None, needs=()):
    """The group /<task>/run_NNN of an open file (the first stored run when `run`
    is None) holding every member named in `needs`; exits with a message naming
    the file, the group and the stored runs when there is none."""
    path = f.filename
    if task not in f:
        raise SystemExit(f"{path}: no /{task} group (not a {task} results file)")
    runs = sorted(name for name in f[task] if name.startswith("run_"))
    if not runs:
        raise SystemExit(f"{path}: no stored run")
    name = f"run_{run:03d}" if run is not None else runs[0]
    group = f[task].get(name)
    missing = [n for n in needs if group is not None and n not in group]
    if group is None or missing:
        what = f"/{task}/{name}" + (f"/{missing[0]}" if missing else "")
        raise SystemExit(f"{path}: {what} not found (runs: {', '.join(runs)}"
                         + ("; files written before issue 11 lack it)" if missing else ")"))
    return group


def mean_ci(values):
    """Mean and half-width of the 95 % Student-t confidence interval over runs
    (NaNs dropped; the half-width is NaN for fewer than two values)."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    n = len(values)
    if n == 0:
        return math.nan, math.nan
    if n == 1:
        return float(values[0]), math.nan
    half = stats.t.ppf(0.975, n - 1) * float(values.std(ddof=1)) / math.sqrt(n)
    return float(values.mean()), half


def wilson_ci(successes, trials, z=None):
    """(rate, low, high): Wilson's 95 % score interval of a success rate. Inside
    [0, 1] and of non-zero width at 0 % and 100 %, unlike mean +- t sd."""
    if trials <= 0:
        return math.nan, math.nan, math.nan
    z = stats.norm.ppf(0.975) if z is None else z
    p = successes / trials
    centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
    half = z / (1 + z * z / trials) * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials ** 2))
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == trials else min(1.0, centre + half)
    return p, low, high


def is_rate(metric):
    """A rate or fraction in [0, 1] (success_rate, success_from_A, collision_fraction)."""
    return metric.startswith("success") or "rate" in metric or "fraction" in metric


def metric_ci(values, metric=""):
    """(estimate, low, high) of one sweep point's values over runs, as `ggk info`
    computes it: for a rate, Wilson's interval when every value is 0 or 1 (a
    per-run success such as success from A), else Student's t clipped to [0, 1];
    for any other metric Student's t."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if is_rate(metric):
        if len(values) >= 1 and np.all((values == 0) | (values == 1)):
            return wilson_ci(int(values.sum()), len(values))
        mean, half = mean_ci(values)
        return mean, max(0.0, mean - half), min(1.0, mean + half)
    mean, half = mean_ci(values)
    return mean, mean - half, mean + half


def axis_values(summary, axis, mask=None):
    column = summary[axis] if mask is None else summary[axis][mask]
    return sorted(set(column.tolist()))


def swept_axes(summary):
    """The axes with several values in the summary."""
    return [a for a in AXES if len(axis_values(summary, a)) > 1]


def facets(summary, shown, fixed=None):
    """One dict of axis values per panel a figure needs so that no swept axis is
    pooled: every combination of the swept axes not in `shown` (a figure shows
    e.g. kernels on x and basis as lines) and not fixed by the caller."""
    fixed = dict(fixed or {})
    mask = _mask(summary, fixed)
    free = [a for a in AXES if a not in shown and a not in fixed
            and len(axis_values(summary, a, mask)) > 1]
    combos = [dict(fixed)]
    for axis in free:
        combos = [dict(c, **{axis: v}) for c in combos for v in axis_values(summary, axis, mask)]
    return combos


def facet_title(facet):
    return ", ".join(f"{k} {v}" for k, v in facet.items())


def _mask(summary, fixed):
    mask = np.ones(len(summary["run"]), dtype=bool)
    for name, value in fixed.items():
        mask &= summary[name] == value
    return mask


def curve(summary, metric, **fixed):
    """(kernel counts, estimates, CI low, CI high) of `metric` over runs, for the
    rows whose columns equal `fixed` (e.g. basis="ggk", solver="brm"). Refuses
    (ValueError) to pool rows of an axis that still has several values."""
    mask = _mask(summary, fixed)
    pooled = [a for a in AXES if a != "kernels" and a not in fixed
              and len(axis_values(summary, a, mask)) > 1]
    if pooled:
        raise ValueError(f"{metric}: the rows selected by {fixed} sweep {', '.join(pooled)}; "
                         "fix each (a facet per value) instead of pooling them")
    kernels = np.array(axis_values(summary, "kernels", mask))
    estimates, lows, highs = [], [], []
    for k in kernels:
        e, lo, hi = metric_ci(summary[metric][mask & (summary["kernels"] == k)], metric)
        estimates.append(e)
        lows.append(lo)
        highs.append(hi)
    return kernels, np.array(estimates), np.array(lows), np.array(highs)


def error_bars(estimates, lows, highs):
    """matplotlib's yerr (2 x n, non-negative) from CI bounds; NaN bounds draw none."""
    below = np.nan_to_num(estimates - lows, nan=0.0)
    above = np.nan_to_num(highs - estimates, nan=0.0)
    return np.vstack([below, above])


def legend_below(ax, ncol=2):
    """The legend under the axes, where it cannot hide a point or an error bar."""
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=ncol, fontsize=8,
              frameon=False)


FORMATS = ("png", "pdf", "svg")


def add_format_argument(parser):
    parser.add_argument("--format", choices=FORMATS, default="png",
                        help="figure file format (default png)")


def save(fig, out_dir, stem, fmt="png", dpi=120):
    """Writes out_dir/stem.fmt and returns its path."""
    path = Path(out_dir) / f"{stem}.{fmt}"
    fig.savefig(path, dpi=dpi)
    return path
