"""One figure for any metric of any results file (plot_metric): the metric's
estimate over runs with its 95 % interval (metric_ci) against one axis, a curve
per value of the hue axes, one panel per combination of the other swept axes
(facets: nothing is pooled), each panel titled with its configuration.

Two things keep every curve readable:
  - dodge: the curves of a panel are shifted sideways, symmetrically about the
    true x, by a step of 3 % of the x span (less where neighbouring x values are
    closer), so that curves with equal values do not hide one another; every
    curve also has its own colour and marker (the first hue axis), line style
    (the further hue axes, or the first when it is the only one) and line width
    (each thinner than the one drawn before it), so that coinciding lines show
    both colours;
  - y limits: the metric's whole range where it is known (metric_range: a rate
    or fraction 0-100 %, a step count 0 to test_max_steps, the Khepera's return
    from the collision reward to test_max_steps forward steps), widened to hold
    every interval, so that no interval runs off the axes; otherwise the span of
    the estimates and intervals. A small margin keeps markers at a bound whole.
"""

import itertools
import math
import textwrap
import tomllib
from collections import Counter

import numpy as np

from .figures import (axes_of, axis_values, curve, error_bars, facet_title, facets, legend_below,
                      value_text)
from .intervals import is_rate
from .metric_specs import is_share, legacy_spec, read_metric_specs
from .tables import open_file, read_summary_table, select_where, task_of, text

# The bases' colour, marker and name in every figure.
BASIS_STYLE = {"ggk": ("tab:red", "o", "geodesic (GGK)"),
               "ogk": ("tab:blue", "s", "ordinary (OGK)"),
               "pvf": ("tab:green", "^", "proto-value functions (PVF)")}
# Other values of the first hue axis, in turn.
COLOURS = ("tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown",
           "tab:pink", "tab:olive", "tab:cyan", "tab:gray")
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*", "<", ">")
LINE_STYLES = ("-", "--", ":", "-.")
# Metrics that count steps of a test episode or walk: 0 to test_max_steps.
STEP_METRICS = ("mean_steps", "mean_steps_to_goal", "steps_from_A")
DODGE = 0.03  # a curve's sideways step, as a fraction of the x span
MARGIN = 0.03  # room beyond the y limits, as a fraction of their span


def job_settings(path):
    """The file's resolved job (root attribute `job_resolved`: one key per
    setting, defaults included, e.g. "khepera.test_max_steps") as a dict; {}
    for a file older than the attribute."""
    with open_file(path) as f:
        if "job_resolved" not in f.attrs:
            return {}
        return tomllib.loads(text(f.attrs["job_resolved"]))


def metric_range(metric, task=None, job=None, spec=None):
    """(low, high): the values `metric` can take, None where unknown: the
    metric's declaration `spec` (a file's metric_specs) where it has one. For a
    file written before the declarations: rates and fractions in [0, 1]; with
    the job's settings (job_settings) step counts in [0, test_max_steps] and the
    Khepera's return in [collision reward, forward reward x test_max_steps] (+1
    per forward move, an episode stopped by its first collision)."""
    if spec is not None:
        return (spec.low if math.isfinite(spec.low) else None,
                spec.high if math.isfinite(spec.high) else None)
    if is_rate(metric):
        return 0.0, 1.0
    steps = (job or {}).get(f"{task}.test_max_steps")
    if steps is None:
        return None, None
    if metric in STEP_METRICS:
        return 0.0, float(steps)
    if task == "khepera" and metric == "mean_return":
        forward = float(job.get("khepera.rewards.forward", 1.0))
        collision = float(job.get("khepera.rewards.collision", -2.0))
        return min(0.0, collision), max(0.0, forward * steps)
    return None, None


def metric_label(metric, spec=None):
    """The y label of a metric: its name, its unit and its interval, by its
    declaration (else legacy_spec's)."""
    spec = spec or legacy_spec(metric)
    if spec.kind == "indicator":
        return f"{metric} (% of runs, Wilson 95 % CI)"
    if is_share(spec):
        return f"{metric} (%, t 95 % CI)"
    unit = f" [{spec.unit}]" if spec.unit and spec.unit != "1" else ""
    return f"{metric}{unit} (t 95 % CI)"


def hue_axes(hue):
    """`hue` as a tuple of axis names ("basis" or ("basis", "solver"))."""
    return (hue,) if isinstance(hue, str) else tuple(hue)


def metric_panels(summary, x="kernels", hue="basis"):
    """The panels plot_metric draws (facets): one dict of axis values per
    combination of the swept axes that are neither x nor a hue axis."""
    return facets(summary, shown=(x, *hue_axes(hue)))


def dodge_step(positions, curves):
    """The sideways step between neighbouring curves at x `positions`: DODGE of
    the x span, or less where the closest two x values are nearer: the curves
    at one x then share 80 % of that gap, and stay clear of the next x."""
    positions = np.unique(np.asarray(positions, dtype=float))
    if curves < 2:
        return 0.0
    if len(positions) < 2:
        return DODGE * max(1.0, abs(float(positions[0])) if len(positions) else 1.0)
    closest = float(np.min(np.diff(positions)))
    return min(DODGE * float(np.ptp(positions)), 0.8 * closest / curves)


def y_limits(values, value_range):
    """(bottom, top) that hold every finite value (estimates and interval ends,
    as drawn) and the metric's known range, with a margin of MARGIN."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    low, high = value_range
    bottom = min([v for v in (low, values.min() if values.size else None) if v is not None],
                 default=0.0)
    top = max([v for v in (high, values.max() if values.size else None) if v is not None],
              default=1.0)
    span = top - bottom
    if span <= 0:
        span = max(abs(top), 1.0)
    return bottom - MARGIN * span, top + MARGIN * span


def panel_configuration(summary, facet, shown):
    """The panel's configuration as text: every axis not shown (on x or as hue)
    with its one value in the panel's rows, e.g. "sigma 5, solver brm, lambda 1e-06"."""
    mask = np.ones(len(summary["run"]), dtype=bool)
    for name, value in facet.items():
        mask &= summary[name] == value
    fixed = {}
    for axis in axes_of(summary):
        if axis in shown or axis not in summary:
            continue
        values = axis_values(summary, axis, mask)
        if len(values) == 1:
            fixed[axis] = values[0]
    return facet_title(fixed)


def runs_text(summary, facet, shown):
    """How many runs each point of the panel averages ("3 runs", "2-3 runs"):
    a point's rows are its runs, one fit each."""
    mask = np.ones(len(summary["run"]), dtype=bool)
    for name, value in facet.items():
        mask &= summary[name] == value
    counts = sorted(set(Counter(zip(*[summary[a][mask] for a in shown])).values()))
    if not counts:
        return "no runs"
    fewest, most = counts[0], counts[-1]
    if fewest == most:
        return "1 run" if most == 1 else f"{most} runs"
    return f"{fewest}-{most} runs"


def curve_style(hue, values, index_of):
    """(colour, marker, line style, label) of the curve of hue `values`: the
    first hue axis picks colour and marker (a basis its own), the others the line
    style; with one hue axis, it picks the line style too (so that a dashed line
    under a dotted one still shows through its gaps)."""
    first = values[0]
    if hue[0] == "basis" and first in BASIS_STYLE:
        colour, marker, name = BASIS_STYLE[first]
    else:
        i = index_of[0][first]
        colour, marker = COLOURS[i % len(COLOURS)], MARKERS[i % len(MARKERS)]
        name = f"{hue[0]} {value_text(first)}"
    rest = tuple(values[1:])
    place = index_of[1][rest] if rest else index_of[0][first]
    style = LINE_STYLES[place % len(LINE_STYLES)]
    parts = [name] + [str(v).upper() if axis == "solver" else facet_title({axis: v})
                      for axis, v in zip(hue[1:], rest)]
    return colour, marker, style, ", ".join(parts)


def draw_panel(ax, summary, metric, x, hue, facet, scale, value_range, spec=None):
    """One panel: a dodged curve with error bars per hue combination present in
    the facet's rows, and the y limits."""
    mask = np.ones(len(summary["run"]), dtype=bool)
    for name, value in facet.items():
        mask &= summary[name] == value
    hue_values = [axis_values(summary, axis, mask) for axis in hue]
    combos = list(itertools.product(*hue_values))
    # Styles by the value's place among the file's values, so that panels agree.
    index_of = ({v: i for i, v in enumerate(axis_values(summary, hue[0]))},
                {c: i for i, c in enumerate(itertools.product(
                    *[axis_values(summary, a) for a in hue[1:]]))})
    categorical = summary[x].dtype.kind not in "iuf"
    # Categorical x values (a solver, a basis) sit at 0, 1, ... in the file's order.
    place = {v: i for i, v in enumerate(axis_values(summary, x))}
    curves = []
    for values in combos:
        xs, est, low, high = curve(summary, metric, x=x, spec=spec, **facet,
                                   **dict(zip(hue, values)))
        if len(xs):
            positions = np.array([place[v] for v in xs] if categorical else xs, dtype=float)
            curves.append((values, positions, est, low, high))
    if categorical:  # one unit between categories: a fixed share of it
        step = min(0.15, 0.6 / len(curves)) if len(curves) > 1 else 0.0
    else:
        step = dodge_step(np.concatenate([c[1] for c in curves]) if curves else [], len(curves))
    drawn = []
    for slot, (values, positions, est, low, high) in enumerate(curves):
        colour, marker, style, label = curve_style(hue, values, index_of)
        offset = (slot - (len(curves) - 1) / 2) * step
        # Each curve a little thinner than the one before, drawn over it: where
        # two lines coincide (equal values) both colours still show.
        width = 1.5 + 1.0 * (len(curves) - 1 - slot) / max(1, len(curves) - 1)
        ax.errorbar(positions + offset, scale * est, yerr=scale * error_bars(est, low, high),
                    color=colour, marker=marker, linestyle=style, linewidth=width,
                    elinewidth=1.2, capsize=3, label=label)
        drawn.extend([scale * est, scale * low, scale * high])
    if categorical:
        ax.set_xticks(range(len(place)), [str(v) for v in place])
        ax.set_xlim(-0.5, len(place) - 0.5)
    lows, highs = value_range
    ax.set_ylim(*y_limits(np.concatenate(drawn) if drawn else [],
                          (None if lows is None else scale * lows,
                           None if highs is None else scale * highs)))


def plot_metric(source, metric, x="kernels", hue="basis", where=(), axes=None,
                value_range=None, ylabel=None, title="", columns=3, legend=True):
    """Draws `metric` against axis `x` with 95 % intervals over runs, a curve per
    value of `hue` (an axis, or a tuple of axes: the first picks colour and
    marker, the others line style), one panel per combination of the remaining
    swept axes. Returns (figure, [(matplotlib axes, facet dict), ...]).

    source: a results file's path (its summary is read; the task's bounds come
            from its job) or a summary (dict of numpy columns, read_summary);
    where:  KEY=VALUE strings selecting rows first (select_where), e.g.
            ["khepera.motion.turn_deg=45"];
    axes:   matplotlib axes to draw into, one per panel in metric_panels'
            order (a script's column of panels); default a new figure of
            `columns` panels a row;
    value_range: (low, high) the metric can take (None where unknown);
            default metric_range's for the file (a summary: rates only);
    title:  text before each panel's configuration (e.g. "maze").
    Rates and fractions are drawn in percent. Refuses (ValueError) an unknown
    metric or axis."""
    task, job, specs = None, {}, {}
    if isinstance(source, dict):
        summary = source
    else:
        with open_file(source) as f:
            task = task_of(f)
            summary = read_summary_table(f, task).columns
            specs = read_metric_specs(f, task)
        job = job_settings(source)
    if where:
        summary, _ = select_where(summary, list(where))
    hue = hue_axes(hue)
    if metric not in summary:
        raise ValueError(f"no metric {metric!r} (the file's: "
                         f"{', '.join(metric_columns(summary))})")
    for axis in (x, *hue):
        if axis not in axes_of(summary):
            raise ValueError(f"no axis {axis!r} (the file's: {', '.join(axes_of(summary))})")
    # A further hue axis with one value tells no curves apart: the titles name it.
    hue = hue[:1] + tuple(a for a in hue[1:] if len(axis_values(summary, a)) > 1)
    spec = specs.get(metric)  # the file's declaration (None: a summary, an older file)
    if value_range is None:
        value_range = metric_range(metric, task, job, spec)
    scale = 100.0 if is_share(spec or legacy_spec(metric)) else 1.0
    panels = metric_panels(summary, x, hue)
    if axes is None:
        import matplotlib.pyplot as plt  # only here: a caller with its own axes needs no pyplot
        columns = max(1, min(columns, len(panels)))
        rows = math.ceil(len(panels) / columns)
        fig, grid = plt.subplots(rows, columns, figsize=(5.5 * columns, 4.6 * rows),
                                 squeeze=False)
        for spare in list(grid.flat)[len(panels):]:
            spare.axis("off")
        axes = list(grid.flat)
    else:
        axes = list(np.ravel(axes))
        if len(axes) < len(panels):
            raise ValueError(f"{metric}: {len(panels)} panels, {len(axes)} axes given")
        fig = axes[0].figure
    shown = (x, *hue)
    for ax, facet in zip(axes, panels):
        draw_panel(ax, summary, metric, x, hue, facet, scale, value_range, spec)
        configuration = panel_configuration(summary, facet, shown)
        heading = ", ".join(t for t in (title, configuration) if t)
        # "3 runs, 95 % CI" on one line: no-break spaces (textwrap breaks at ASCII ones).
        tail = f"{runs_text(summary, facet, shown)}, 95 % CI".replace(" ", "\u00a0")
        ax.set_title(textwrap.fill("; ".join(t for t in (heading, tail) if t), 70), fontsize=9)
        ax.set_xlabel("number of kernels" if x == "kernels" else x)
        ax.set_ylabel(ylabel or metric_label(metric, spec))
        ax.grid(alpha=0.3)
        if legend:
            legend_below(ax)
    return fig, list(zip(axes, panels))


def metric_columns(summary):
    """The summary's metrics: every column after `status`."""
    names = list(summary)
    return names[names.index("status") + 1:] if "status" in names else []
