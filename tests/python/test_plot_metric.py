"""ggk_results.plot_metric and `python3 -m ggk_results plot` on files the binary
writes: a panel per value of the axes a figure does not show, the configuration
in every title, curves of equal values dodged apart, y limits that hold every
interval and a rate's 0-100 %; and the shipped scripts' metric figures drawn with
it: every curve of arm_success (OGK was drawn at PVF's x, under it),
khepera_return (GGK under OGK, an interval off the axes), maze_success and a
continuous task's steps figure visible, every interval inside the axes."""

import importlib.util
import itertools
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import support
from support import Scratch, run_ggk

support.require("h5py", "numpy", "scipy", "matplotlib")
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.container import ErrorbarContainer  # noqa: E402

from ggk_results import curve, plot_metric, read_summary  # noqa: E402

# Markers of two curves closer than this share of the axes' width overlap by more
# than half (a marker is 6 points, about 2 % of a panel 4.5 inches wide).
APART = 0.01


def curves_of(ax):
    return [c for c in ax.containers if isinstance(c, ErrorbarContainer)]


def x_of(container):
    return np.asarray(container.lines[0].get_xdata(), dtype=float)


def y_drawn(container):
    """Every y the curve draws: its estimates and its error bars' ends."""
    ys = [np.asarray(container.lines[0].get_ydata(), dtype=float)]
    for bars in container.lines[2]:
        for segment in bars.get_segments():
            ys.append(np.asarray(segment)[:, 1])
    values = np.concatenate(ys)
    return values[np.isfinite(values)]


def assert_readable(test, fig, curves=None):
    """Every panel of `fig` with curves: `curves` of them (when given), markers of
    two curves at least APART of the axes' width from each other, every
    estimate and interval inside the y limits."""
    panels = [ax for ax in fig.axes if curves_of(ax)]
    test.assertTrue(panels, "no panel with curves")
    for ax in panels:
        drawn = curves_of(ax)
        if curves is not None:
            test.assertEqual(len(drawn), curves, ax.get_title())
        left, right = ax.get_xlim()
        for a, b in itertools.combinations(drawn, 2):
            gap = np.min(np.abs(x_of(a)[:, None] - x_of(b)[None, :]))
            test.assertGreaterEqual(gap, APART * (right - left),
                                    f"{a.get_label()} and {b.get_label()} overlap in "
                                    f"{ax.get_title()!r}")
        bottom, top = ax.get_ylim()
        for c in drawn:
            ys = y_drawn(c)
            test.assertGreaterEqual(ys.min(), bottom, f"{c.get_label()} below the axes")
            test.assertLessEqual(ys.max(), top, f"{c.get_label()} above the axes")


def script(name):
    path = support.SOURCE / "results" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def figures_of(name, *arguments):
    """Runs results/<name>.py's main with `arguments`; returns {file stem: figure}
    of the figures it saves (they are kept, not written)."""
    module = script(name)
    saved = {}

    def keep(fig, out_dir, stem, fmt="png", dpi=120):
        saved[stem] = fig
        return Path(out_dir) / f"{stem}.{fmt}"

    module.save = keep
    argv = sys.argv
    sys.argv = [name, *map(str, arguments)]
    try:
        module.main()
    finally:
        sys.argv = argv
    return saved


class PlotMetric(unittest.TestCase):
    """The function and the command on the CI arm job with two kernel widths."""

    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.TemporaryDirectory(prefix="ggk-python-")
        cls.dir = Path(cls.scratch.name)
        cls.file = cls.dir / "arm.h5"
        made = run_ggk("run", support.SOURCE / "jobs/ci-arm.toml", "-q", "--sweep", "sigma=5,10",
                       "-o", cls.file)
        assert made.returncode == 0, made.stderr

    @classmethod
    def tearDownClass(cls):
        cls.scratch.cleanup()

    def tearDown(self):
        plt.close("all")

    def test_a_panel_per_value_of_the_other_axes_titled_with_its_configuration(self):
        fig, panels = plot_metric(self.file, "success_rate")
        self.assertEqual([facet for _, facet in panels], [{"sigma": 5.0}, {"sigma": 10.0}])
        for (ax, _), sigma in zip(panels, ("5", "10")):
            title = ax.get_title().replace("\n", " ")
            for part in (f"sigma {sigma},", "solver brm", "lambda 1e-06", "3\u00a0runs"):
                self.assertIn(part, title)
            self.assertEqual([c.get_label() for c in curves_of(ax)],
                             ["geodesic (GGK)", "ordinary (OGK)", "proto-value functions (PVF)"])
        assert_readable(self, fig, curves=3)

    def test_curves_of_equal_values_are_dodged_apart_symmetrically(self):
        summary = read_summary(self.file)
        ogk, pvf = summary["basis"] == "ogk", summary["basis"] == "pvf"
        # Rows come in the same (run, kernels, sigma) order for every basis.
        np.testing.assert_array_equal(summary["kernels"][ogk], summary["kernels"][pvf])
        summary["success_rate"][ogk] = summary["success_rate"][pvf]
        fig, panels = plot_metric(summary, "success_rate")
        for ax, facet in panels:
            ggk_curve, ogk_curve, pvf_curve = curves_of(ax)
            np.testing.assert_array_equal(ogk_curve.lines[0].get_ydata(),
                                          pvf_curve.lines[0].get_ydata())
            self.assertTrue(np.all(x_of(ogk_curve) != x_of(pvf_curve)))
            kernels, *_ = curve(summary, "success_rate", basis="ogk", **facet)
            # The three curves sit symmetrically about the true kernel counts.
            mean_x = (x_of(ggk_curve) + x_of(ogk_curve) + x_of(pvf_curve)) / 3
            np.testing.assert_allclose(mean_x, kernels)
        assert_readable(self, fig, curves=3)

    def test_y_limits_hold_every_interval_and_a_rates_range(self):
        summary = read_summary(self.file)
        for metric in ("success_rate", "success_from_A", "lspi_iterations"):
            fig, panels = plot_metric(self.file, metric)
            scale = 1 if metric == "lspi_iterations" else 100
            for ax, facet in panels:
                bottom, top = ax.get_ylim()
                for basis in ("ggk", "ogk", "pvf"):
                    _, estimates, lows, highs = curve(summary, metric, basis=basis, **facet)
                    for values in (estimates, lows, highs):
                        values = scale * values[np.isfinite(values)]
                        self.assertTrue(np.all((bottom <= values) & (values <= top)), metric)
                if scale == 100:  # a rate: 0-100 %, with a margin for the markers only
                    self.assertTrue(-5 <= bottom <= 0 and 100 <= top <= 105, (metric, bottom, top))
            assert_readable(self, fig, curves=3)
            plt.close(fig)

    def test_refuses_an_unknown_metric_or_axis(self):
        with self.assertRaisesRegex(ValueError, "no metric 'success'.*success_rate"):
            plot_metric(self.file, "success")
        with self.assertRaisesRegex(ValueError, "no axis 'width'"):
            plot_metric(self.file, "success_rate", x="width")

    def test_any_axis_on_x_and_as_hue(self):
        fig, panels = plot_metric(self.file, "success_rate", x="sigma", hue="basis")
        self.assertEqual([facet for _, facet in panels], [{"kernels": 16}, {"kernels": 48}])
        self.assertIn("kernels 16,", panels[0][0].get_title())
        assert_readable(self, fig, curves=3)
        fig, panels = plot_metric(self.file, "success_rate", x="basis", hue="sigma")
        self.assertEqual([t.get_text() for t in panels[0][0].get_xticklabels()],
                         ["ggk", "ogk", "pvf"])
        assert_readable(self, fig, curves=2)

    def test_command_writes_the_figure(self):
        env = dict(os.environ, PYTHONPATH=str(support.SOURCE / "python"))
        command = [sys.executable, "-m", "ggk_results", "plot", str(self.file)]
        out = self.dir / "figures"
        done = subprocess.run([*command, "success_from_A", "-o", str(out)], capture_output=True,
                              text=True, env=env)
        self.assertEqual(done.returncode, 0, done.stderr)
        path = out / "arm_success_from_A_kernels.png"
        self.assertEqual(done.stdout.strip(), str(path))
        self.assertGreater(path.stat().st_size, 10_000)
        done = subprocess.run([*command, "success_rate", "--x", "sigma", "--where", "kernels=16",
                               "--format", "svg", "--name", "widths", "-o", str(out)],
                              capture_output=True, text=True, env=env)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertTrue((out / "widths.svg").exists())
        for bad, says in ((["nope"], "no metric 'nope'"),
                          (["success_rate", "--where", "kernels=7"], "kernels=7: no rows")):
            done = subprocess.run([*command, *bad], capture_output=True, text=True, env=env)
            self.assertEqual(done.returncode, 2, done.stderr)
            self.assertIn(says, done.stderr)


class ShippedFigures(Scratch):
    """The scripts' metric-vs-kernels figures on the CI jobs' files."""

    def tearDown(self):
        plt.close("all")
        super().tearDown()

    def results(self, job, *settings):
        path = self.dir / f"{job}.h5"
        made = run_ggk("run", support.SOURCE / f"jobs/{job}.toml", "-q", *settings, "-o", path)
        self.assertEqual(made.returncode, 0, made.stderr)
        return path

    def test_arm_success_shows_ggk_ogk_and_pvf(self):
        figures = figures_of("plot_arm", self.results("ci-arm"), self.dir)
        assert_readable(self, figures["arm_success"], curves=3)

    def test_arm_success_of_a_study_has_a_row_per_configuration(self):
        path = self.results("ci-arm", "--set", "runs=1", "--sweep", "arm.grid_step_degrees=5,2.5",
                            "--sweep", "kernels=16,48")
        fig = figures_of("plot_arm", path, self.dir)["arm_success"]
        titles = [ax.get_title() for ax in fig.axes if curves_of(ax)]
        self.assertEqual(len(titles), 4)
        # Rows by the axis' values in order, each metric a column.
        for title, step in zip(titles, ("2.5", "2.5", "5", "5")):
            self.assertIn(f"arm.grid_step_degrees {step};", title.replace("\n", " "))
        assert_readable(self, fig, curves=3)

    def test_khepera_return_shows_every_curve_inside_the_axes(self):
        figures = figures_of("plot_khepera", self.results("ci-khepera"), self.dir)
        assert_readable(self, figures["khepera_return"], curves=3)

    def test_maze_success(self):
        figures = figures_of("plot_maze", self.results("ci", "--set", "runs=3"), self.dir)
        assert_readable(self, figures["maze_success"], curves=3)

    def test_continuous_steps(self):
        path = self.results("ci-mountain-car")
        figures = figures_of("plot_continuous", path, self.dir, "--grid", "10")
        assert_readable(self, figures["mountain_car_steps"], curves=3)


if __name__ == "__main__":
    unittest.main()
