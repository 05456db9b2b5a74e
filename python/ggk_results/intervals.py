"""95 % confidence intervals over runs, from scipy.stats.

Which interval fits a metric depends on what one run contributes:
  - a 0/1 success indicator per run (the arm's success_from_A: one walk from A)
    is a Bernoulli trial: Wilson's score interval (inside [0, 1], not of zero
    width at 0 % or 100 %);
  - any other value per run, a fraction of episodes or states included
    (Khepera's collision_fraction over test_episodes episodes, the maze's
    success_rate over all start cells), is a per-run mean: Student's t over the
    runs. Wilson on such a fraction would treat each run as one trial (all
    zeros over 4 runs would give [0, 49 %]); pooling the episodes with Wilson
    would ignore that episodes of one run share its policy.
A results file declares each metric's kind and range (metric_specs.py); every
interval is intersected with the range, as `ggk info` does.
"""

import math
import warnings

import numpy as np
from scipy import stats

from .metric_specs import legacy_spec

CONFIDENCE = 0.95
# Metrics that are one 0/1 outcome per run (a fit's test from one named start).
INDICATORS = ("success_from_A",)


def is_indicator(metric):
    """True for a metric that files without declarations (legacy_spec) read as
    one 0/1 success outcome per run. A file's own: its metric_specs."""
    return metric in INDICATORS or metric.startswith("success_from_")


def is_rate(metric):
    """True for a metric that files without declarations read as a share in
    [0, 1] (success_rate, success_from_A, collision_fraction). A file's own:
    its metric_specs."""
    return legacy_spec(metric).kind in ("fraction", "indicator")


def finite(values):
    values = np.asarray(values, dtype=float)
    return values[np.isfinite(values)]


def mean_ci(values, confidence=CONFIDENCE):
    """(mean, low, high): the mean over runs and its Student-t interval (NaNs
    dropped; NaN bounds for fewer than two values, zero width when every value
    is the same)."""
    values = finite(values)
    if len(values) == 0:
        return math.nan, math.nan, math.nan
    mean = float(values.mean())
    if len(values) == 1:
        return mean, math.nan, math.nan
    if np.all(values == values[0]):
        return mean, mean, mean  # scipy warns (precision loss) and gives the same
    interval = stats.ttest_1samp(values, 0.0).confidence_interval(confidence)
    return mean, float(interval.low), float(interval.high)


def wilson_ci(successes, trials, confidence=CONFIDENCE):
    """(rate, low, high): Wilson's score interval of a success rate."""
    if trials <= 0:
        return math.nan, math.nan, math.nan
    interval = stats.binomtest(int(successes), int(trials)).proportion_ci(
        confidence_level=confidence, method="wilson")
    return successes / trials, float(interval.low), float(interval.high)


def metric_ci(values, metric="", confidence=CONFIDENCE, spec=None):
    """(estimate, low, high) of one sweep point's values over runs, by the
    metric's declaration `spec` (metric_specs.MetricSpec: a file's, e.g.
    Results.metric_specs[metric]; without one, legacy_spec(metric)): Wilson's
    interval for an indicator (one 0/1 outcome per run), else Student's t;
    either intersected with the metric's range [low, high], which keeps the
    interval's coverage (the mean lies in the range), as `ggk info` does."""
    spec = spec or legacy_spec(metric)
    values = finite(values)
    if spec.kind == "indicator":
        if not np.all((values == 0) | (values == 1)):
            raise ValueError(f"{spec.name}: an indicator metric holds values other than 0 and 1")
        return wilson_ci(int(values.sum()), len(values), confidence)
    mean, low, high = mean_ci(values, confidence)
    return mean, clip(low, spec.low, spec.high), clip(high, spec.low, spec.high)


def clip(value, low, high):
    """value within [low, high]; NaN stays NaN."""
    return value if math.isnan(value) else min(max(value, low), high)


def paired_t_ci(a, b, confidence=CONFIDENCE):
    """(mean difference, low, high) of a - b paired by position: the interval of
    scipy's ttest_rel (NaN bounds for fewer than two pairs, zero width when every
    difference is the same)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    diff = a - b
    if len(diff) == 0:
        return math.nan, math.nan, math.nan
    mean = float(diff.mean())
    if len(diff) == 1:
        return mean, math.nan, math.nan
    if np.all(diff == diff[0]):
        return mean, mean, mean
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        interval = stats.ttest_rel(a, b).confidence_interval(confidence)
    return mean, float(interval.low), float(interval.high)


def newcombe_paired_ci(a, b, confidence=CONFIDENCE):
    """(difference of rates, low, high) of paired 0/1 outcomes a - b: Newcombe's
    hybrid score interval for paired proportions (Newcombe 1998, Stat. Med. 17,
    2635, method 10, with the correlation's correction as in Altman et al.,
    Statistics with Confidence, 2000, ch. 6), built from the Wilson intervals of
    the two rates. Inside [-1, 1]; not of zero width when no pair differs."""
    a, b = np.asarray(a, dtype=int), np.asarray(b, dtype=int)
    n = len(a)
    if n == 0:
        return math.nan, math.nan, math.nan
    both = int(np.sum((a == 1) & (b == 1)))
    only_a = int(np.sum((a == 1) & (b == 0)))
    only_b = int(np.sum((a == 0) & (b == 1)))
    neither = n - both - only_a - only_b
    p1, l1, u1 = wilson_ci(both + only_a, n, confidence)
    p2, l2, u2 = wilson_ci(both + only_b, n, confidence)
    # phi: the correlation of the pairs' outcomes, 0 when a margin is empty;
    # Newcombe shrinks a positive product difference by n/2 (continuity).
    margins = (both + only_a) * (only_b + neither) * (both + only_b) * (only_a + neither)
    phi = 0.0
    if margins > 0:
        product = both * neither - only_a * only_b
        corrected = max(product - n / 2, 0.0) if product > 0 else product
        phi = corrected / math.sqrt(margins)
    d = p1 - p2
    low = d - math.sqrt(max(0.0, (p1 - l1) ** 2 - 2 * phi * (p1 - l1) * (u2 - p2) + (u2 - p2) ** 2))
    high = d + math.sqrt(max(0.0,
                             (p2 - l2) ** 2 - 2 * phi * (p2 - l2) * (u1 - p1) + (u1 - p1) ** 2))
    return d, max(-1.0, low), min(1.0, high)
