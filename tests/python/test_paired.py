"""ggk_results.paired: GGK - OGK paired by run per kernel count, with scipy's
ttest_rel interval (Newcombe's for a 0/1 success); it refuses to pool an axis."""

import unittest

import numpy as np
import pandas as pd
from scipy import stats

import support  # noqa: F401  (ggk_results from this checkout)
from ggk_results import newcombe_paired_ci, paired


def frame(runs=8, kernels=(16, 64), sigmas=(5.0,), seed=2):
    """A summary-like frame: run, basis, kernels, sigma, solver, lambda, status,
    success_rate (per-run fraction) and success_from_A (0/1)."""
    rng = np.random.default_rng(seed)
    rows = []
    for run in range(runs):
        for basis in ("ggk", "ogk"):
            for k in kernels:
                for sigma in sigmas:
                    rows.append(dict(run=run, sweep_point=0, basis=basis, kernels=k, sigma=sigma,
                                     solver="brm", **{"lambda": 1e-6}, status="converged",
                                     success_rate=rng.random(),
                                     success_from_A=int(rng.random() < (0.7 if basis == "ggk"
                                                                        else 0.3))))
    return pd.DataFrame(rows)


class Paired(unittest.TestCase):
    def test_t_intervals_equal_ttest_rels_per_kernel_count(self):
        df = frame()
        points = paired(df, "success_rate", compare="basis", a="ggk", b="ogk", by=["kernels"])
        self.assertEqual(points.kernels.tolist(), [16, 64])
        for _, point in points.iterrows():
            part = df[df.kernels == point.kernels]
            ggk = part[part.basis == "ggk"].set_index("run").success_rate.sort_index()
            ogk = part[part.basis == "ogk"].set_index("run").success_rate.sort_index()
            expected = stats.ttest_rel(ggk, ogk).confidence_interval()
            self.assertEqual(point.method, "t")
            self.assertEqual(point.pairs, 8)
            self.assertAlmostEqual(point.difference, (ggk - ogk).mean(), places=14)
            self.assertAlmostEqual(point.low, expected.low, places=12)
            self.assertAlmostEqual(point.high, expected.high, places=12)
            self.assertAlmostEqual(point.a, ggk.mean(), places=14)
            self.assertAlmostEqual(point.b, ogk.mean(), places=14)

    def test_pairs_by_run_not_by_row_order(self):
        df = frame()
        shuffled = df.sample(frac=1.0, random_state=4)
        pd.testing.assert_frame_equal(paired(df, "success_rate"), paired(shuffled, "success_rate"))

    def test_a_run_missing_on_one_side_is_left_out(self):
        df = frame()
        df = df[~((df.basis == "ogk") & (df.run == 3))]
        df.loc[(df.basis == "ggk") & (df.run == 5), "success_rate"] = np.nan
        points = paired(df, "success_rate")
        self.assertEqual(points.pairs.tolist(), [6, 6])

    def test_success_indicators_get_newcombes_interval(self):
        df = frame(runs=30, kernels=(64,))
        point = paired(df, "success_from_A").iloc[0]
        ggk = df[df.basis == "ggk"].set_index("run").success_from_A.sort_index()
        ogk = df[df.basis == "ogk"].set_index("run").success_from_A.sort_index()
        self.assertEqual(point.method, "newcombe")
        self.assertEqual((point.difference, point.low, point.high),
                         newcombe_paired_ci(ggk.to_numpy(), ogk.to_numpy()))
        # method="t" asks for the t interval of the 0/1 differences instead.
        t_point = paired(df, "success_from_A", method="t").iloc[0]
        expected = stats.ttest_rel(ggk, ogk).confidence_interval()
        self.assertAlmostEqual(t_point.low, expected.low, places=12)

    def test_refuses_to_pool_an_axis(self):
        df = frame(sigmas=(5.0, 10.0))
        with self.assertRaisesRegex(ValueError, "sigma"):
            paired(df, "success_rate", by=["kernels"])
        points = paired(df, "success_rate", by=["kernels", "sigma"])
        self.assertEqual(len(points), 4)
        self.assertEqual(points.columns[:2].tolist(), ["kernels", "sigma"])

    def test_names_a_missing_side_or_column(self):
        with self.assertRaisesRegex(ValueError, "pvf"):
            paired(frame(), "success_rate", a="pvf")
        with self.assertRaisesRegex(KeyError, "mean_return"):
            paired(frame(), "mean_return")


if __name__ == "__main__":
    unittest.main()


class InfoPaired(support.Scratch):
    """`ggk info --paired basis=ggk,ogk --csv` prints what paired() gives."""

    def test_ggk_info_paired_equals_paired(self):
        import io
        from ggk_results import open_results
        job = support.maze_job(self.dir / "job.toml", runs=4, kernels=(4, 8),
                               solvers=("brm", "lstdq"))
        made = support.run_ggk("run", job, "-q", "-j", "1", "-o", self.dir / "r.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        self.assertEqual(made.stdout + made.stderr, "", "-q prints nothing but errors")
        shown = support.run_ggk("info", self.dir / "r.h5", "--paired", "basis=ggk,ogk", "--csv",
                                "--columns", "success_rate,mean_steps_to_goal,lspi_iterations")
        self.assertEqual(shown.returncode, 0, shown.stderr)
        table = pd.read_csv(io.StringIO(shown.stdout))
        self.assertEqual([c for c in table.columns if not c.startswith(
            ("success_rate", "mean_steps_to_goal", "lspi_iterations"))],
            ["kernels", "sigma", "solver", "lambda"])
        df = open_results(self.dir / "r.h5").summary()
        by = ["kernels", "sigma", "solver", "lambda"]
        for metric in ("success_rate", "mean_steps_to_goal", "lspi_iterations"):
            expected = paired(df, metric, by=by).sort_values(by).reset_index(drop=True)
            got = table.sort_values(by).reset_index(drop=True)
            self.assertEqual(len(got), 4)
            for column, name in (("a", "_a"), ("b", "_b"), ("difference", "_difference"),
                                 ("low", "_ci_low"), ("high", "_ci_high"), ("pairs", "_pairs")):
                np.testing.assert_allclose(got[metric + name].to_numpy(dtype=float),
                                           expected[column].to_numpy(dtype=float),
                                           rtol=1e-8, atol=1e-12, equal_nan=True,  # scipy t: 4e-10 off
                                           err_msg=f"{metric}{name}")
        # -q: nothing; an unknown column or axis value: exit 2 naming it.
        quiet = support.run_ggk("info", self.dir / "r.h5", "-q")
        self.assertEqual((quiet.returncode, quiet.stdout, quiet.stderr), (0, "", ""))
        bad = support.run_ggk("info", self.dir / "r.h5", "--columns", "success_rate,nope")
        self.assertEqual(bad.returncode, 2)
        self.assertIn("'nope' is no metric", bad.stderr)
        bad = support.run_ggk("info", self.dir / "r.h5", "--paired", "basis=ggk,pvf")
        self.assertEqual(bad.returncode, 2)
        self.assertIn("no value 'pvf'", bad.stderr)
        bad = support.run_ggk("info", self.dir / "r.h5", "--paired", "basis")
        self.assertEqual(bad.returncode, 2)
        self.assertIn("AXIS=A,B", bad.stderr)

    def test_a_run_level_study_axis_is_paired_by_run(self):
        # Its two values are two configurations (run r of each shares the seeds):
        # pairs by run, in ggk info and paired() alike.
        import io
        from ggk_results import open_results
        job = support.maze_job(self.dir / "job.toml", runs=3, kernels=(4,))
        made = support.run_ggk("run", job, "-q", "-j", "1", "--sweep", "maze.slip=0.0,0.1",
                               "-o", self.dir / "s.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        shown = support.run_ggk("info", self.dir / "s.h5", "--paired", "maze.slip=0.0,0.1",
                                "--csv", "--columns", "success_rate")
        self.assertEqual(shown.returncode, 0, shown.stderr)
        got = pd.read_csv(io.StringIO(shown.stdout)).sort_values("basis").reset_index(drop=True)
        df = open_results(self.dir / "s.h5").summary()
        expected = paired(df, "success_rate", compare="maze.slip", a=0.0, b=0.1,
                          by=["basis", "kernels"]).sort_values("basis").reset_index(drop=True)
        self.assertEqual(expected.pairs.tolist(), [3, 3])
        for column, name in (("difference", "_difference"), ("low", "_ci_low"),
                             ("high", "_ci_high"), ("pairs", "_pairs")):
            np.testing.assert_allclose(got["success_rate" + name].to_numpy(dtype=float),
                                       expected[column].to_numpy(dtype=float), rtol=1e-8,
                                       atol=1e-12, equal_nan=True, err_msg=name)
