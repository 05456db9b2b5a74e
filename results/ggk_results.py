"""Reading ggk results files (HDF5) for analysis: the per-task summary table and
confidence intervals over runs. Uses Debian's python3-h5py and numpy; run scripts
with /usr/bin/python3 where a pyenv python3 comes first on PATH."""

import math

import h5py
import numpy as np

# Two-sided 95 % quantiles of Student's t for 1..30 degrees of freedom.
_T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
         2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
         2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def t975(dof):
    if dof < 1:
        return math.nan
    return _T975[dof - 1] if dof <= len(_T975) else 1.96


def read_summary(path, task):
    """The /<task>/summary table as a dict of numpy columns (strings decoded)."""
    with h5py.File(path, "r") as f:
        table = f[f"/{task}/summary"][:]
    columns = {}
    for name in table.dtype.names:
        column = table[name]
        if column.dtype.kind == "S":
            column = np.char.decode(column, "utf-8")
        columns[name] = column
    return columns


def mean_ci(values):
    """Mean and half-width of the 95 % confidence interval over runs (NaNs dropped)."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    n = len(values)
    if n == 0:
        return math.nan, math.nan
    if n == 1:
        return float(values[0]), math.nan
    return float(values.mean()), t975(n - 1) * float(values.std(ddof=1)) / math.sqrt(n)


def curve(summary, metric, **fixed):
    """(kernel counts, means, CI half-widths) of `metric` over runs, for the rows
    whose columns equal `fixed` (e.g. basis="ggk", solver="brm")."""
    mask = np.ones(len(summary["run"]), dtype=bool)
    for name, value in fixed.items():
        mask &= summary[name] == value
    kernels = np.unique(summary["kernels"][mask])
    means, halves = [], []
    for k in kernels:
        m, h = mean_ci(summary[metric][mask & (summary["kernels"] == k)])
        means.append(m)
        halves.append(h)
    return kernels, np.array(means), np.array(halves)
