"""The metrics' declarations a results file holds (metric_specs: kind, unit,
meaning, range) and what ggk_results does with them: xarray attrs, intervals by
the declared kind and within the declared range, figure labels. A metric named
to fool the old guess by name (steps_fraction: "..._fraction" read as a share,
clipped to [0, 1] and drawn in %) is read as the file declares it, a step count."""

import math
import tempfile
import unittest
from pathlib import Path

import support
from support import maze_job, run_ggk

support.require("h5py", "numpy", "pandas", "scipy", "xarray", "matplotlib")
import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import numpy as np  # noqa: E402

from ggk_results import (curve, is_rate, legacy_spec, metric_ci, open_results,  # noqa: E402
                         paired, plot_metric)


def rename_metric(path, old, new):
    """Renames metric `old` to `new` in every table of the file (fit_metrics,
    summary, metric_specs), as a task that named it so would have written it."""
    with h5py.File(path, "r+") as f:
        tables = []
        f.visititems(lambda name, obj: tables.append(name)
                     if isinstance(obj, h5py.Dataset) and obj.dtype.names else None)
        for name in tables:
            dataset = f[name]
            data, attrs = dataset[:], dict(dataset.attrs)
            if old in data.dtype.names:
                data.dtype.names = [new if n == old else n for n in data.dtype.names]
            elif "name" in data.dtype.names:  # a metric_specs table
                data["name"] = [new.encode() if n in (old, old.encode()) else n
                                for n in data["name"]]
            else:
                continue
            del f[name]
            f.create_dataset(name, data=data, maxshape=(None,), chunks=True)
            for key, value in attrs.items():
                f[name].attrs[key] = value


class DeclaredMetrics(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.TemporaryDirectory(prefix="ggk-specs-")
        folder = Path(cls.scratch.name)
        cls.path = folder / "r.h5"
        job = maze_job(folder / "job.toml", runs=4, kernels=(4, 8))
        made = run_ggk("run", job, "-q", "-j", "1", "-o", cls.path)
        assert made.returncode == 0, made.stderr

    @classmethod
    def tearDownClass(cls):
        cls.scratch.cleanup()

    def test_the_file_declares_every_metric_column(self):
        results = open_results(self.path)
        self.assertEqual(list(results.metric_specs), results.metrics)
        success = results.metric_specs["success_rate"]
        self.assertEqual((success.kind, success.unit, success.low, success.high),
                         ("fraction", "1", 0.0, 1.0))
        steps = results.metric_specs["mean_steps_to_goal"]
        self.assertEqual((steps.kind, steps.unit, steps.low), ("mean", "steps", 0.0))
        self.assertEqual(steps.high, 100.0)  # the job's test_max_steps (maze default)
        self.assertTrue(math.isinf(results.metric_specs["graph_nodes"].high))
        self.assertEqual(results.metric_specs["fit_seconds"].unit, "s")
        for spec in results.metric_specs.values():
            self.assertTrue(spec.meaning, spec.name)

    def test_xarray_variables_carry_units_and_long_names(self):
        dataset = open_results(self.path).dataset()
        attrs = dataset.mean_steps_to_goal.attrs
        self.assertEqual(attrs["units"], "steps")
        self.assertIn("mean steps to a goal", attrs["long_name"])
        self.assertEqual(attrs["kind"], "mean")
        self.assertEqual(list(attrs["valid_range"]), [0.0, 100.0])
        self.assertEqual(dataset.success_rate.attrs["units"], "1")

    def test_a_name_that_fooled_the_old_guess_is_read_as_declared(self):
        with tempfile.TemporaryDirectory() as folder:
            fooled = Path(folder) / "fooled.h5"
            fooled.write_bytes(Path(self.path).read_bytes())
            rename_metric(fooled, "mean_steps_to_goal", "steps_fraction")
            self.assertTrue(is_rate("steps_fraction"))  # what the name alone suggests
            results = open_results(fooled)
            spec = results.metric_spec("steps_fraction")
            self.assertEqual((spec.kind, spec.unit, spec.high), ("mean", "steps", 100.0))
            frame = results.summary()
            # Intervals by the declared kind and range, never [0, 1].
            values = frame[(frame.basis == "ggk") & (frame.kernels == 8)].steps_fraction
            declared = metric_ci(values, "steps_fraction", spec=spec)
            self.assertGreater(declared[0], 1.0)
            self.assertGreater(declared[2], 1.0)
            guessed = metric_ci(values, "steps_fraction")  # no declaration: the old rule
            self.assertLessEqual(guessed[2], 1.0)
            xs, estimates, lows, highs = curve(frame, "steps_fraction", basis="ggk")
            self.assertTrue(np.all(highs[np.isfinite(highs)] > 1.0))
            compared = paired(frame, "steps_fraction")
            self.assertTrue((compared.method == "t").all())
            # The figure: a step count with its unit, not a percentage.
            fig, panels = plot_metric(fooled, "steps_fraction")
            self.assertEqual(panels[0][0].get_ylabel(), "steps_fraction [steps] (t 95 % CI)")
            self.assertLessEqual(panels[0][0].get_ylim()[1], 100.0 * 1.1)
            self.assertEqual(open_results(fooled).dataset().steps_fraction.attrs["units"], "steps")

    def test_a_bounded_mean_gets_a_bounded_interval(self):
        spec = open_results(self.path).metric_spec("mean_steps_to_goal")
        estimate, low, high = metric_ci([1.0, 99.0, 3.0, 97.0], spec=spec)
        self.assertEqual(estimate, 50.0)
        self.assertEqual((low, high), (0.0, 100.0))  # Student's t alone: [-38.2, 138.2]

    def test_a_file_without_declarations_is_read_as_before(self):
        with tempfile.TemporaryDirectory() as folder:
            old = Path(folder) / "old.h5"
            old.write_bytes(Path(self.path).read_bytes())
            with h5py.File(old, "r+") as f:
                names = []
                f.visititems(lambda name, obj: names.append(name)
                             if name.endswith("metric_specs") else None)
                for name in names:
                    del f[name]
            results = open_results(old)
            self.assertEqual(results.metric_specs, {})
            self.assertEqual(results.metric_spec("success_rate"), legacy_spec("success_rate"))
            self.assertEqual(results.metric_spec("success_rate").kind, "fraction")
            self.assertNotIn("units", results.dataset().success_rate.attrs)


if __name__ == "__main__":
    unittest.main()
