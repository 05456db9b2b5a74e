"""What the plot scripts share: one panel per value of every swept axis a
figure does not show (facets), a metric's curve over one axis (kernel counts by
default) that refuses to pool another (curve), error bars, legends and saving;
metric_figure.py draws whole figures from them. `summary` is a dict of
numpy columns (read_summary)."""

from pathlib import Path

import numpy as np

from .intervals import metric_ci
from .metric_specs import spec_of
from .tables import AXES, INDEX_COLUMNS

FORMATS = ("png", "pdf", "svg")


def axes_of(summary):
    """The sweep axes, then a study's axis columns (every column before
    `status` that is neither an index column nor a sweep axis)."""
    names = list(summary)
    before_status = names[:names.index("status")] if "status" in names else []
    return list(AXES) + [c for c in before_status if c not in INDEX_COLUMNS and c not in AXES]


def axis_values(summary, axis, mask=None):
    column = summary[axis] if mask is None else summary[axis][mask]
    return sorted(set(column.tolist()))


def swept_axes(summary):
    """The axes with several values in the summary."""
    return [a for a in axes_of(summary) if len(axis_values(summary, a)) > 1]


def _mask(summary, fixed):
    mask = np.ones(len(summary["run"]), dtype=bool)
    for name, value in fixed.items():
        mask &= summary[name] == value
    return mask


def facets(summary, shown, fixed=None):
    """One dict of axis values per panel a figure needs so that no swept axis is
    pooled: every combination of the swept axes not in `shown` (a figure shows
    e.g. kernels on x and basis as lines) and not fixed by the caller."""
    fixed = dict(fixed or {})
    mask = _mask(summary, fixed)
    free = [a for a in axes_of(summary) if a not in shown and a not in fixed
            and len(axis_values(summary, a, mask)) > 1]
    combos = [dict(fixed)]
    for axis in free:
        combos = [dict(c, **{axis: v}) for c in combos for v in axis_values(summary, axis, mask)]
    return combos


def value_text(value):
    """An axis value as a title shows it: numbers without a trailing .0 (10, 1e-06)."""
    if isinstance(value, (float, np.floating)):
        return f"{float(value):g}"
    return str(value)


def facet_title(facet):
    return ", ".join(f"{k} {value_text(v)}" for k, v in facet.items())


def curve(summary, metric, x="kernels", spec=None, **fixed):
    """(values of axis x, estimates, CI low, CI high) of `metric` over runs, for
    the rows whose columns equal `fixed` (e.g. basis="ggk", solver="brm"); the
    interval is metric_ci's, by the metric's declaration `spec` (else the one
    summary.attrs["metric_specs"] holds: Results.summary()'s; spec_of). Refuses (ValueError) to pool rows of an axis that
    still has several values."""
    mask = _mask(summary, fixed)
    pooled = [a for a in axes_of(summary) if a != x and a not in fixed
              and len(axis_values(summary, a, mask)) > 1]
    if pooled:
        raise ValueError(f"{metric}: the rows selected by {fixed} sweep {', '.join(pooled)}; "
                         "fix each (a facet per value) instead of pooling them")
    xs = np.array(axis_values(summary, x, mask))
    spec = spec or spec_of(metric, summary)
    estimates, lows, highs = [], [], []
    for value in xs:
        e, lo, hi = metric_ci(summary[metric][mask & (summary[x] == value)], metric, spec=spec)
        estimates.append(e)
        lows.append(lo)
        highs.append(hi)
    return xs, np.array(estimates), np.array(lows), np.array(highs)


def error_bars(estimates, lows, highs):
    """matplotlib's yerr (2 x n, non-negative) from CI bounds; NaN bounds draw none."""
    below = np.nan_to_num(estimates - lows, nan=0.0)
    above = np.nan_to_num(highs - estimates, nan=0.0)
    return np.vstack([below, above])


def legend_below(ax, ncol=2):
    """The legend under the axes, where it cannot hide a point or an error bar."""
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=ncol, fontsize=8,
              frameon=False)


def add_format_argument(parser):
    parser.add_argument("--format", choices=FORMATS, default="png",
                        help="figure file format (default png)")


def save(fig, out_dir, stem, fmt="png", dpi=120):
    """Writes out_dir/stem.fmt and returns its path."""
    path = Path(out_dir) / f"{stem}.{fmt}"
    fig.savefig(path, dpi=dpi)
    return path
