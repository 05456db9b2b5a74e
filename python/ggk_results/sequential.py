"""Anytime-valid confidence sequences for adaptive studies: the Python twin of
kernels/confidence_sequence.hpp (the same formulas, the same order of sums; the
module `ggk` exposes the C++ one, and tests/python/test_confidence_sequence.py
checks that the two agree and that the error rate holds under optional stopping).

The predictable plug-in empirical-Bernstein confidence sequence (PrPl-EB) of
Waudby-Smith & Ramdas (2023, JRSS B 86(1), Theorem 2): when the paired
differences x_1, x_2, ... lie in [low, high] and share their mean mu (given the
ones before), P(mu is outside [lower_t, upper_t] for some t) <= 1 - level,
however many times one looks and whenever one stops.
"""

import math

import numpy as np


def confidence_sequence(differences, low, high, level=0.95):
    """(lower, upper): numpy arrays, the bounds after each prefix of `differences`
    (in run order), each difference in [low, high] (e.g. [-1, 1] for paired
    success differences)."""
    x = np.asarray(differences, dtype=float)
    if x.ndim != 1:
        raise ValueError("differences must be a 1-D sequence")
    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise ValueError("the bounds must be finite with low < high")
    if not 0.0 < level < 1.0:
        raise ValueError("level must be in (0, 1)")
    if not np.all(np.isfinite(x)) or np.any(x < low) or np.any(x > high):
        raise ValueError(f"a difference lies outside [{low}, {high}]")
    log_term = math.log(2.0 / (1.0 - level))
    y = (x - low) / (high - low)
    lower_out, upper_out = np.empty(len(y)), np.empty(len(y))
    sum_y = sum_squares = sum_lambda = sum_lambda_y = sum_penalty = 0.0
    mu_before, s2_before = 0.5, 0.25
    lower, upper = 0.0, 1.0
    for i, value in enumerate(y):
        t = i + 1.0
        lam = min(math.sqrt(2.0 * log_term / (s2_before * t * math.log(1.0 + t))), 0.5)
        v = 4.0 * (value - mu_before) * (value - mu_before)
        sum_penalty += v * (-math.log(1.0 - lam) - lam) / 4.0
        sum_lambda += lam
        sum_lambda_y += lam * value
        centre = sum_lambda_y / sum_lambda
        radius = (log_term + sum_penalty) / sum_lambda
        lower = max(lower, centre - radius)
        upper = min(upper, centre + radius)
        lower_out[i] = low + (high - low) * lower
        upper_out[i] = low + (high - low) * upper
        sum_y += value
        mu = (0.5 + sum_y) / (t + 1.0)
        sum_squares += (value - mu) * (value - mu)
        mu_before = mu
        s2_before = (0.25 + sum_squares) / (t + 1.0)
    return lower_out, upper_out


def asymptotic_confidence_sequence(differences, level=0.95, horizon=20):
    """(lower, upper): the asymptotic confidence sequence (AsympCS) of
    Waudby-Smith, Arnold, Wu, Chang & Ramdas (2024, Ann. Statist. 52(6)), the
    twin of kernels::asymptotic_confidence_sequence: the two-sided normal-mixture
    boundary tightest at t = horizon, with the sample standard deviation and
    Student's t small-sample factor q_t / z. No range needed; its coverage at
    every t at once holds as the runs grow (not at every small t: see
    tests/python/test_confidence_sequence.py). Bounds after the first value are
    infinite; not intersected over t."""
    from scipy import stats

    x = np.asarray(differences, dtype=float)
    if x.ndim != 1:
        raise ValueError("differences must be a 1-D sequence")
    if not 0.0 < level < 1.0:
        raise ValueError("level must be in (0, 1)")
    if horizon < 1:
        raise ValueError("the horizon must be at least 1")
    if not np.all(np.isfinite(x)):
        raise ValueError("a difference is not finite")
    alpha = 1.0 - level
    rho2 = (-2.0 * math.log(alpha) + math.log(-2.0 * math.log(alpha) + 1.0)) / horizon
    z = stats.norm.ppf(1.0 - alpha / 2.0)
    lower_out, upper_out = np.empty(len(x)), np.empty(len(x))
    quantiles = stats.t.ppf(1.0 - alpha / 2.0, np.arange(1, max(len(x), 2), dtype=float))
    mean = squares = 0.0
    for i, value in enumerate(x):
        t = i + 1.0
        delta = value - mean
        mean += delta / t
        squares += delta * (value - mean)
        if i == 0:
            lower_out[i], upper_out[i] = -math.inf, math.inf
            continue
        sd = math.sqrt(squares / (t - 1.0))
        q = quantiles[i - 1]  # t - 1 degrees of freedom
        half = sd * math.sqrt(2.0 * (t * rho2 + 1.0) / (t * t * rho2)
                              * math.log(math.sqrt(t * rho2 + 1.0) / alpha)) * q / z
        lower_out[i], upper_out[i] = mean - half, mean + half
    return lower_out, upper_out
