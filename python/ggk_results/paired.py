"""Paired comparisons: a - b of one metric between two values of one axis
(GGK - OGK by default), paired by run (run r of both shares its samples, graph
and centres), per point of the other axes."""

import numpy as np
import pandas as pd

from .intervals import CONFIDENCE, clip, newcombe_paired_ci, paired_t_ci
from .metric_specs import spec_of

# The columns that pair two rows besides `by`: the run and, in a study with
# run-level axes, its configuration (unless the compared axis is run-level).
PAIRING = ("run", "configuration")


def paired(frame, metric, compare="basis", a="ggk", b="ogk", by=("kernels",),
           confidence=CONFIDENCE, method=None, spec=None):
    """One row per group of `by`: the mean of `metric` under compare == a and
    under compare == b, their difference a - b paired by run, its interval and
    the number of pairs.

    The interval is scipy's ttest_rel interval of the mean difference, within
    +-(high - low) of the metric's range, or for a 0/1 indicator metric
    (success_from_A) Newcombe's paired score interval of the difference of the
    two success rates; `method` ("t" or "newcombe") overrides the choice. The
    kind and range are the metric's declaration: `spec`, else the one
    frame.attrs["metric_specs"] holds (Results.summary()'s), else
    metric_specs.legacy_spec's. Runs that lack either side, or whose metric is NaN on
    either side, are left out.

    Refuses (ValueError, naming the axes) to pair rows when some column other
    than `by`, `compare` and the pairing columns tells two rows of one run
    apart: an axis with several values would be pooled.

    Columns: the `by` columns, a, b (means over the pairs), difference, low,
    high, pairs, method."""
    by = [by] if isinstance(by, str) else list(by)
    spec = spec or spec_of(metric, frame)
    method = method or ("newcombe" if spec.kind == "indicator" else "t")
    width = spec.high - spec.low  # a difference of two values in the range lies in +-width
    if method not in ("t", "newcombe"):
        raise ValueError(f"paired: method {method!r} is not 't' or 'newcombe'")
    for column in [metric, compare, "run"] + by:
        if column not in frame.columns:
            raise KeyError(f"paired: no column {column!r} (columns: {', '.join(frame.columns)})")
    pairing = [c for c in PAIRING if c in frame.columns]
    if "configuration" in pairing and frame.groupby("configuration")[compare].nunique().max() <= 1:
        # A run-level study axis compared: its values are configurations of
        # their own, whose run r shares its seeds; pair by run alone.
        pairing.remove("configuration")
    chosen = frame[frame[compare].isin([a, b])]
    sides = chosen[compare].unique().tolist()
    for side in (a, b):
        if side not in sides:
            raise ValueError(f"paired: no row with {compare} == {side!r}")
    key = by + pairing + [compare]
    repeated = chosen[chosen.duplicated(key, keep=False)]
    if len(repeated):
        pooled = [c for c in _axis_columns(frame) if c not in key
                  and repeated.groupby(key, dropna=False)[c].nunique(dropna=False).gt(1).any()]
        raise ValueError(f"paired: {metric}: several rows per run and {compare} value at one "
                         f"point of {by}: {', '.join(pooled) or 'some column'} vary; add them "
                         "to `by` or select one value")
    rows = []
    # One key groups by its values, not by 1-tuples (pandas 1.5 warns).
    grouper = by[0] if len(by) == 1 else by
    groups = chosen.groupby(grouper, sort=True, dropna=False) if by else [((), chosen)]
    for point, group in groups:
        point = point if isinstance(point, tuple) else (point,)
        wide = group.set_index(pairing + [compare])[metric].unstack(compare)
        if a not in wide or b not in wide:
            continue
        wide = wide[[a, b]].dropna()
        x, y = wide[a].to_numpy(dtype=float), wide[b].to_numpy(dtype=float)
        if method == "newcombe":
            if not np.all(np.isin(x, (0, 1)) & np.isin(y, (0, 1))):
                raise ValueError(f"paired: {metric}: Newcombe's interval needs 0/1 outcomes")
            difference, low, high = newcombe_paired_ci(x, y, confidence)
        else:
            difference, low, high = paired_t_ci(x, y, confidence)
            low, high = clip(low, -width, width), clip(high, -width, width)
        rows.append(dict(zip(by, point), a=x.mean() if len(x) else np.nan,
                         b=y.mean() if len(y) else np.nan, difference=difference, low=low,
                         high=high, pairs=len(x), method=method))
    return pd.DataFrame(rows, columns=by + ["a", "b", "difference", "low", "high", "pairs",
                                            "method"])


def _axis_columns(frame):
    """The columns before `status` (the axes and index columns of a ggk table)."""
    names = list(frame.columns)
    return names[:names.index("status")] if "status" in names else names
