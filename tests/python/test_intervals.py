"""ggk_results.intervals against scipy.stats, and which interval a metric gets:
Wilson for a 0/1 success per run, Student's t for a per-run fraction of episodes
(Khepera's collision_fraction) or any other per-run value; Newcombe's paired
interval for paired 0/1 outcomes."""

import math
import unittest

import numpy as np
from scipy import stats

import support  # noqa: F401  (ggk_results from this checkout)
from ggk_results import curve, mean_ci, metric_ci, newcombe_paired_ci, paired_t_ci, wilson_ci


class Intervals(unittest.TestCase):
    def test_mean_ci_is_scipys_t_interval(self):
        values = np.array([0.2, 0.5, 0.1, 0.7, 0.4])
        mean, low, high = mean_ci(values)
        t_low, t_high = stats.t.interval(0.95, len(values) - 1, loc=values.mean(),
                                         scale=stats.sem(values))
        self.assertAlmostEqual(mean, values.mean(), places=15)
        self.assertAlmostEqual(low, t_low, places=12)
        self.assertAlmostEqual(high, t_high, places=12)
        # NaNs are dropped; one value has no interval; equal values a zero-width one.
        self.assertEqual(mean_ci([1.0, math.nan, 3.0])[0], 2.0)
        self.assertTrue(math.isnan(mean_ci([4.0])[1]))
        self.assertEqual(mean_ci([2.0, 2.0, 2.0]), (2.0, 2.0, 2.0))

    def test_wilson_ci_is_scipys(self):
        for successes, trials in ((0, 4), (3, 10), (30, 30)):
            rate, low, high = wilson_ci(successes, trials)
            expected = stats.binomtest(successes, trials).proportion_ci(method="wilson")
            self.assertEqual(rate, successes / trials)
            self.assertAlmostEqual(low, expected.low, places=12)
            self.assertAlmostEqual(high, expected.high, places=12)
        # The textbook value: 0 of 4 gives [0, 0.490] (z = 1.96).
        self.assertAlmostEqual(wilson_ci(0, 4)[2], 0.4899, places=3)

    def test_success_from_a_keeps_wilson(self):
        values = [1, 0, 0, 1, 1, 1, 0, 1, 1, 1]
        self.assertEqual(metric_ci(values, "success_from_A"), wilson_ci(7, 10))
        with self.assertRaises(ValueError):
            metric_ci([0.5, 1.0], "success_from_A")

    def test_collision_fraction_is_a_t_interval_over_runs(self):
        # Per-run fractions of 10 episodes: a mean over runs, not a Bernoulli trial
        # per run. All zeros over 4 runs is [0, 0], not Wilson's [0, 49 %].
        mean, low, high = metric_ci([0.0, 0.0, 0.0, 0.0], "collision_fraction")
        self.assertEqual((mean, low, high), (0.0, 0.0, 0.0))
        fractions = np.array([0.0, 0.1, 0.0, 0.3])
        mean, low, high = metric_ci(fractions, "collision_fraction")
        t_low, t_high = stats.t.interval(0.95, 3, loc=fractions.mean(), scale=stats.sem(fractions))
        self.assertAlmostEqual(mean, 0.1)
        self.assertEqual(low, 0.0)  # t_low < 0, clipped to the rate's range
        self.assertLess(t_low, 0.0)
        self.assertAlmostEqual(high, t_high, places=12)
        # Runs whose every episode collided or none did (0 or 1 per run) still get
        # the t interval of a per-run mean, not Wilson's.
        mean, low, high = metric_ci([0.0, 1.0, 0.0, 0.0], "collision_fraction")
        t_low, t_high = stats.t.interval(0.95, 3, loc=0.25, scale=stats.sem([0, 1, 0, 0]))
        self.assertEqual((low, high), (max(0.0, t_low), min(1.0, t_high)))
        self.assertNotAlmostEqual(high, wilson_ci(1, 4)[2], places=3)

    def test_curve_uses_the_metrics_interval(self):
        summary = {
            "run": np.array([0, 1, 2, 3] * 2), "basis": np.array(["ggk"] * 8, dtype=object),
            "kernels": np.array([10] * 4 + [20] * 4), "sigma": np.full(8, 1000.0),
            "solver": np.array(["brm"] * 8, dtype=object), "lambda": np.full(8, 1e-6),
            "status": np.array(["converged"] * 8, dtype=object),
            "collision_fraction": np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.1, 0.0, 0.3]),
        }
        kernels, estimates, lows, highs = curve(summary, "collision_fraction", basis="ggk")
        self.assertEqual(kernels.tolist(), [10, 20])
        self.assertEqual((lows[0], highs[0]), (0.0, 0.0))
        self.assertAlmostEqual(highs[1], metric_ci([0.0, 0.1, 0.0, 0.3], "collision_fraction")[2])

    def test_paired_t_ci_is_ttest_rels(self):
        a = np.array([0.61, 0.40, 0.72, 0.55, 0.58, 0.49])
        b = np.array([0.50, 0.41, 0.60, 0.47, 0.60, 0.30])
        difference, low, high = paired_t_ci(a, b)
        expected = stats.ttest_rel(a, b).confidence_interval()
        self.assertAlmostEqual(difference, (a - b).mean(), places=15)
        self.assertAlmostEqual(low, expected.low, places=12)
        self.assertAlmostEqual(high, expected.high, places=12)


class Newcombe(unittest.TestCase):
    def test_is_built_from_the_two_wilson_intervals(self):
        # b never succeeds (an empty margin): phi = 0, and the interval is the
        # square-and-add of the two rates' Wilson intervals (Newcombe's method 10).
        a = np.array([1] * 24 + [0] * 6)
        b = np.zeros(30, dtype=int)
        d, low, high = newcombe_paired_ci(a, b)
        p1, l1, u1 = wilson_ci(24, 30)
        p2, l2, u2 = wilson_ci(0, 30)
        self.assertAlmostEqual(d, 0.8)
        self.assertAlmostEqual(low, d - math.hypot(p1 - l1, u2 - p2), places=12)
        self.assertAlmostEqual(high, d + math.hypot(p2 - l2, u1 - p1), places=12)

    def test_is_antisymmetric_and_never_zero_width(self):
        rng = np.random.default_rng(3)
        a, b = rng.integers(0, 2, 20), rng.integers(0, 2, 20)
        d, low, high = newcombe_paired_ci(a, b)
        d2, low2, high2 = newcombe_paired_ci(b, a)
        self.assertAlmostEqual(d, -d2)
        self.assertAlmostEqual(low, -high2)
        self.assertAlmostEqual(high, -low2)
        # Identical outcomes: difference 0 with an interval of positive width,
        # where the t interval of the differences is [0, 0].
        same = np.array([1, 0, 1, 1, 0, 0, 1, 0])
        d, low, high = newcombe_paired_ci(same, same)
        self.assertEqual(d, 0.0)
        self.assertLess(low, 0.0)
        self.assertGreater(high, 0.0)
        self.assertEqual(paired_t_ci(same, same)[1:], (0.0, 0.0))

    def test_covers_the_true_difference(self):
        # 95 % nominal: over 2000 simulated studies of 30 pairs the interval covers
        # the true difference at least ~93 % of the time (Newcombe reports coverage
        # close to nominal), where the t interval of the differences falls short.
        rng = np.random.default_rng(11)
        p_a, p_b, n, studies = 0.15, 0.05, 30, 2000
        covered_newcombe = covered_t = 0
        for _ in range(studies):
            u = rng.random(n)
            a = (u < p_a).astype(int)
            b = (rng.random(n) < p_b).astype(int)
            _, low, high = newcombe_paired_ci(a, b)
            covered_newcombe += low <= p_a - p_b <= high
            _, low, high = paired_t_ci(a, b)
            covered_t += low <= p_a - p_b <= high
        self.assertGreaterEqual(covered_newcombe / studies, 0.93)
        self.assertLess(covered_t / studies, covered_newcombe / studies)


if __name__ == "__main__":
    unittest.main()
