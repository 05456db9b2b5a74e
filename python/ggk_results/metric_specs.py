"""What each metric of a results file is, as the file declares it: the table
metric_specs beside each run's fit_metrics and beside the summary (name, kind,
unit, meaning, low, high; results/README.md). Kinds decide the interval
(intervals.metric_ci), ranges bound it, units and meanings label figures and
xarray's variables. Nothing is guessed from a metric's name, but for a file
written before the declarations (ggk before 2026-11-29): legacy_spec says how
those files were read."""

import math
from collections import namedtuple

from .runs import complete_runs

# kind: "mean" (Student's t over runs), "indicator" (one 0/1 outcome per run:
# Wilson), "fraction" (a per-run share in [0, 1]: Student's t); every interval
# is then intersected with [low, high] (-inf / inf where the task knows no bound).
MetricSpec = namedtuple("MetricSpec", "name kind unit meaning low high")
KINDS = ("mean", "indicator", "fraction")
TABLE = "metric_specs"


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read_table(dataset):
    """The declarations of one metric_specs dataset, by name, in its order."""
    specs = {}
    for row in dataset[:]:
        spec = MetricSpec(_text(row["name"]), _text(row["kind"]), _text(row["unit"]),
                          _text(row["meaning"]), float(row["low"]), float(row["high"]))
        if spec.kind not in KINDS:
            raise ValueError(f"{dataset.file.filename}: {dataset.name}: metric {spec.name!r} "
                             f"has the unknown kind {spec.kind!r} ({', '.join(KINDS)})")
        specs[spec.name] = spec
    return specs


def united(a, b):
    """One declaration per metric of two sets: a's order and words, each range
    the smallest holding both (the runs of a study's configurations)."""
    result = dict(a)
    for name, spec in b.items():
        if name in result:
            old = result[name]
            result[name] = old._replace(low=min(old.low, spec.low), high=max(old.high, spec.high))
        else:
            result[name] = spec
    return result


def read_metric_specs(f, task):
    """The declarations of an open file's metrics, by name: /<task>/metric_specs
    when the summary has them, else its complete runs' united; {} for a file
    written before the declarations."""
    if task in f and TABLE in f[task]:
        return read_table(f[task][TABLE])
    specs = {}
    for run in complete_runs(f, task):
        if TABLE in f[run]:
            specs = united(specs, read_table(f[run][TABLE]))
    return specs


def legacy_spec(metric):
    """How a file without declarations was read: success_from_<name> an
    indicator; success_rate and a name ending in _fraction a fraction in [0, 1];
    anything else an unbounded mean. No unit, no meaning."""
    if metric.startswith("success_from_"):
        return MetricSpec(metric, "indicator", "", "", 0.0, 1.0)
    if metric == "success_rate" or metric.endswith("_fraction"):
        return MetricSpec(metric, "fraction", "", "", 0.0, 1.0)
    return MetricSpec(metric, "mean", "", "", -math.inf, math.inf)


def spec_of(metric, specs=None):
    """The declaration of `metric` in `specs` (a dict of MetricSpec by name, or
    a DataFrame whose attrs["metric_specs"] holds one: Results.summary()'s),
    else legacy_spec's (a plain summary of columns declares nothing)."""
    if specs is not None and hasattr(specs, "attrs"):
        specs = specs.attrs.get("metric_specs")
    spec = specs.get(metric) if isinstance(specs, dict) else None
    return spec if isinstance(spec, MetricSpec) else legacy_spec(metric)


def bounded(spec):
    """True when both ends of the metric's range are known."""
    return math.isfinite(spec.low) and math.isfinite(spec.high)


def is_share(spec):
    """A fraction or an indicator: a share in [0, 1], drawn in %."""
    return spec.kind in ("fraction", "indicator")
