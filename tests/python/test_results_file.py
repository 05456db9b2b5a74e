"""ggk_results.open_results and fit on files the real ggk writes: complete,
interrupted (killed mid-job: no summary yet) and a study's layout (config_NNN
groups, study axis columns named by the study_axes attribute)."""

import signal
import subprocess
import tempfile
import time
import unittest
import warnings
from pathlib import Path

import numpy as np

import support
from support import Scratch, maze_job, run_ggk

support.require("h5py", "pandas", "xarray")
import h5py  # noqa: E402

import ggk_results  # noqa: E402
from ggk_results import PartialResultsWarning, fit, open_results  # noqa: E402


class CompleteFile(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.TemporaryDirectory(prefix="ggk-python-")
        folder = Path(cls.scratch.name)
        cls.path = folder / "r.h5"
        job = maze_job(folder / "job.toml", runs=3, kernels=(4, 8), solvers=("brm", "lstdq"))
        result = run_ggk("run", job, "-q", "-j", "1", "-o", cls.path)
        assert result.returncode == 0, result.stderr

    @classmethod
    def tearDownClass(cls):
        cls.scratch.cleanup()

    def test_summary_has_str_columns_and_every_row(self):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a complete file warns nothing
            results = open_results(self.path)
        df = results.summary()
        self.assertTrue(results.complete)
        self.assertEqual(len(df), 3 * 2 * 2 * 2)
        self.assertIsInstance(df.basis.iloc[0], str)
        self.assertEqual(len(df[df.basis == "ggk"]), 12)
        self.assertEqual(results.axes, ["basis", "kernels", "sigma", "solver", "lambda"])
        self.assertIn("success_rate", results.metrics)
        self.assertNotIn("status", results.metrics)
        with h5py.File(self.path, "r") as f:
            table = f["/maze/summary"][:]
        np.testing.assert_array_equal(df.success_rate.to_numpy(), table["success_rate"])

    def test_every_dataset_names_its_axes_and_xarray_sees_them(self):
        # The file's own dims/units/description (engine/store/dataset_schema.cpp).
        import xarray as xr
        seen = []
        with h5py.File(self.path, "r") as f:
            def check(name, obj):
                if isinstance(obj, h5py.Dataset):
                    array = ggk_results.labelled(obj)
                    self.assertIsInstance(array, xr.DataArray)
                    self.assertEqual(len(array.dims), obj.ndim, name)
                    self.assertFalse(any(d.startswith("dim_") for d in array.dims), name)
                    self.assertIn("description", array.attrs, name)
                    self.assertIn("units", array.attrs, name)
                    seen.append(name)
            f["maze/run_000"].visititems(check)
            samples = xr.Dataset({name: ggk_results.labelled(f["maze/run_000/samples"][name])
                                  for name in f["maze/run_000/samples"]})
            self.assertEqual(samples.actions.dims, ("sample",))
            self.assertEqual(samples.observations.dims, ("sample", "observation_dim"))
            self.assertEqual(f["maze/run_000/action_names"].asstr()[:].tolist(),
                             ["up", "down", "left", "right"])
            starts = f["maze/run_000/start_states"][:]
            self.assertEqual(f["maze/summary"].dtype["lspi_iterations"], np.int64)
            self.assertEqual(f["maze/summary"].dtype["success_rate"], np.float64)
        self.assertIn("fit_metrics", seen)
        one = fit(self.path, run=0, basis="ggk", kernels=8, solver="brm")
        self.assertEqual(one.steps_to_goal.dims, ("start",))
        np.testing.assert_array_equal(one.steps_to_goal.start.values, starts)
        self.assertEqual(one.policy.dims, ("state",))
        self.assertEqual(one.weights.dims, ("action", "centre"))
        self.assertEqual(one.history.weight_change.dims, ("iteration",))
        self.assertIsInstance(one.point["lspi_iterations"], int)

    def test_dataset_has_named_dims_and_coordinates(self):
        results = open_results(self.path)
        ds = results.dataset()
        self.assertEqual(list(ds.success_rate.dims),
                         ["run", "basis", "kernels", "sigma", "solver", "lambda"])
        self.assertEqual(ds.basis.values.tolist(), ["ggk", "ogk"])
        self.assertEqual(ds.kernels.values.tolist(), [4, 8])
        self.assertEqual(ds.run.values.tolist(), [0, 1, 2])
        df = results.summary()
        row = df[(df.run == 2) & (df.basis == "ogk") & (df.kernels == 8) & (df.solver == "lstdq")]
        value = ds.success_rate.sel(run=2, basis="ogk", kernels=8, solver="lstdq").squeeze()
        self.assertEqual(float(value), row.success_rate.iloc[0])
        self.assertEqual(str(ds.status.sel(run=2, basis="ogk", kernels=8, solver="lstdq").squeeze()
                             .item()), row.status.iloc[0])
        # The README's question: GGK - OGK at 8 kernels, paired by run.
        diff = (ds.success_rate.sel(basis="ggk") - ds.success_rate.sel(basis="ogk")).sel(kernels=8)
        self.assertEqual(diff.dims, ("run", "sigma", "solver", "lambda"))

    def test_fit_returns_labelled_weights_policy_and_values(self):
        one = fit(self.path, run=1, basis="ggk", kernels=8, solver="brm")
        name = "/maze/run_001/fits/ggk/k_0008_sigma10_brm_lambda1e-06"
        with h5py.File(self.path, "r") as f:
            group = f[name]
            weights, centres = group["weights"][:], group["centers"][:]
            policy, steps = group["policy"][:], group["steps_to_goal"][:]
            values = group["state_values"][:]
        self.assertEqual(one.group, name.lstrip("/"))
        self.assertEqual(one.point["basis"], "ggk")
        self.assertEqual(one.point["kernels"], 8)
        self.assertEqual(one.weights.dims, ("action", "centre"))
        self.assertEqual(one.weights.action.values.tolist(), ["up", "down", "left", "right"])
        self.assertEqual(one.weights.centre.values.tolist(), centres.tolist())
        # Column a*p + j of the stored vector is action a, centre j.
        self.assertEqual(float(one.weights.sel(action="left", centre=centres[5])),
                         weights[2 * 8 + 5])
        np.testing.assert_array_equal(one.policy.values, policy)
        np.testing.assert_array_equal(one.state_values.values, values)
        # steps_to_goal indexes the non-goal states: its coordinate says which.
        self.assertEqual(len(one.steps_to_goal.start), len(steps))
        self.assertEqual(len(set(one.steps_to_goal.start.values)), len(steps))
        self.assertLess(len(steps), len(policy))
        self.assertIn("policy_changes", one.history)
        with self.assertRaisesRegex(KeyError, "solver"):
            fit(self.path, run=1, basis="ggk", kernels=8)  # brm or lstdq?
        with self.assertRaisesRegex(KeyError, "runs"):
            fit(self.path, run=7, basis="ggk", kernels=8, solver="brm")


class ArmAndKheperaFits(Scratch):
    def test_arrays_are_named_by_what_they_index(self):
        made = run_ggk("run", support.SOURCE / "jobs/arm-quick.toml", "-q", "-o",
                       self.dir / "arm.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        arm = fit(self.dir / "arm.h5", run=0, basis="ogk", kernels=16)
        with h5py.File(self.dir / "arm.h5", "r") as f:
            state_of, goal = f["arm/run_000/grid/state_of"][:], f["arm/run_000/grid/goal"][:]
        goals = set(state_of[goal == 1].tolist())
        starts = arm.steps_to_goal.start.values
        self.assertEqual(len(goals), 16)
        self.assertEqual(len(starts) + len(goals), len(arm.policy))
        self.assertFalse(goals & set(starts.tolist()))
        self.assertEqual(arm.weights.action.values.tolist(),
                         ["shoulder+", "shoulder-", "elbow+", "elbow-"])
        self.assertEqual(int(arm.trajectory_A[-1]) in goals, arm.point["success_from_A"] == 1)

        made = run_ggk("run", support.SOURCE / "jobs/khepera-quick.toml", "-q", "-o",
                       self.dir / "khepera.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        khepera = fit(self.dir / "khepera.h5", run=1, basis="ggk", kernels=10, solver="brm")
        self.assertEqual(khepera.policy.dims, ("state",))  # a Khepera state: a reading
        self.assertEqual(khepera.unit_policy.dims, ("node",))  # a SOM unit
        self.assertEqual(khepera.evaluation_trajectory_0.pose.values.tolist(),
                         ["x", "y", "heading"])
        self.assertAlmostEqual(float(khepera.returns.mean()), khepera.point["mean_return"])


class InterruptedFile(Scratch):
    def test_a_killed_job_loads_from_its_complete_runs(self):
        out = self.dir / "killed.h5"
        job = maze_job(self.dir / "job.toml", runs=3000)
        process = subprocess.Popen([support.ggk(), "run", str(job), "-q", "-j", "1", "-o",
                                    str(out)], stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL)
        try:
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline and process.poll() is None:
                if out.exists():
                    try:
                        with h5py.File(out, "r") as f:
                            if len(ggk_results.complete_runs(f, "maze")) >= 2:
                                break
                    except OSError:
                        pass  # ggk holds the lock for the moment of a commit
                time.sleep(0.05)
            self.assertIsNone(process.poll(), "the job ended before it was interrupted")
        finally:
            process.send_signal(signal.SIGKILL)
            process.wait()
        with self.assertWarnsRegex(PartialResultsWarning, "no /maze/summary"):
            results = open_results(out)
        self.assertFalse(results.complete)
        runs = len(results.runs)
        self.assertGreaterEqual(runs, 2)
        self.assertLess(runs, 3000)
        df = results.summary()
        self.assertEqual(len(df), 4 * runs)
        self.assertEqual(sorted(set(df.run)), list(range(runs)))
        self.assertIsInstance(df.solver.iloc[0], str)
        ds = results.dataset()
        self.assertEqual(ds.sizes["run"], runs)
        one = results.fit(0, basis="ogk", kernels=4)
        self.assertEqual(one.weights.shape, (4, 4))
        # The plot scripts' reader gives the same rows.
        with self.assertWarns(PartialResultsWarning):
            columns = ggk_results.read_summary(out)
        self.assertEqual(len(columns["run"]), 4 * runs)


def write_study(path, summary):
    """A study's file as the engine lays it out (engine/store/run_store.hpp):
    /maze/config_NNN/run_NNN with fit_metrics whose columns gain `configuration`
    and one column per study axis (study_axes names them); with or without the
    summary."""
    string = h5py.string_dtype("utf-8")
    dtype = np.dtype([("run", "<i4"), ("configuration", "<i4"), ("sweep_point", "<i4"),
                      ("basis", string), ("kernels", "<i4"), ("sigma", "<f8"),
                      ("solver", string), ("lambda", "<f8"), ("maze.slip", "<f8"),
                      ("status", string), ("success_rate", "<f8"), ("fit_seconds", "<f8")])
    rows = []
    with h5py.File(path, "w") as f:
        f.attrs["task"] = "maze"
        for configuration, slip in enumerate((0.0, 0.2)):
            for run in range(2):
                group = f.create_group(f"maze/config_{configuration:03d}/run_{run:03d}")
                table = []
                for point, basis in enumerate(("ggk", "ogk")):
                    rate = 0.5 + 0.1 * run + 0.01 * point - slip
                    table.append((run, configuration, point, basis, 4, 10.0, "brm", 1e-6, slip,
                                  "converged", rate, 0.01))
                    fit = group.create_group(f"fits/{basis}/k_0004_sigma10_brm_lambda1e-06")
                    fit.attrs["sweep_point"] = point
                    fit.attrs["basis"] = basis
                    fit["centers"] = np.arange(4, dtype=np.int32)
                    fit["weights"] = np.full(16, 10.0 * configuration + run, dtype=float)
                    fit["policy"] = np.zeros(10, dtype=np.int32)
                metrics = group.create_dataset("fit_metrics", data=np.array(table, dtype=dtype))
                metrics.attrs["study_axes"] = "maze.slip"
                group.attrs["complete"] = 1
                rows += table
        if summary:
            table = f.create_dataset("maze/summary", data=np.array(rows, dtype=dtype))
            table.attrs["study_axes"] = "maze.slip"


class StudyLayout(Scratch):
    def check(self, results):
        self.assertEqual(results.study_axes, ["maze.slip"])
        self.assertEqual(results.axes[-1], "maze.slip")
        df = results.summary()
        self.assertEqual(len(df), 8)
        ds = results.dataset(["success_rate"])
        self.assertEqual(list(ds.success_rate.dims),
                         ["run", "basis", "kernels", "sigma", "solver", "lambda", "maze.slip"])
        self.assertAlmostEqual(
            float(ds.success_rate.sel({"run": 1, "basis": "ogk", "maze.slip": 0.2}).squeeze()),
            0.5 + 0.1 + 0.01 - 0.2)
        # The fit of configuration 1 (slip 0.2), run 1 lives in config_001/run_001.
        one = results.fit(1, basis="ggk", **{"maze.slip": 0.2})
        self.assertEqual(one.group,
                         "maze/config_001/run_001/fits/ggk/k_0004_sigma10_brm_lambda1e-06")
        self.assertEqual(float(one.weights[0, 0]), 11.0)
        with self.assertRaisesRegex(KeyError, "maze.slip"):
            results.fit(1, basis="ggk")

    def test_a_finished_study(self):
        write_study(self.dir / "study.h5", summary=True)
        self.check(open_results(self.dir / "study.h5"))

    def test_a_summary_older_than_the_runs_gives_way_to_them(self):
        write_study(self.dir / "study.h5", summary=True)
        with h5py.File(self.dir / "study.h5", "a") as f:
            rows = f["maze/summary"][:]
            del f["maze/summary"]
            old = f.create_dataset("maze/summary", data=rows[:4])  # configuration 0 only
            old.attrs["study_axes"] = "maze.slip"
        with self.assertWarnsRegex(PartialResultsWarning, "covers 2 of its 4 complete runs"):
            results = open_results(self.dir / "study.h5")
        self.check(results)

    def test_a_running_study_reads_its_configuration_groups(self):
        write_study(self.dir / "study.h5", summary=False)
        with self.assertWarns(PartialResultsWarning):
            results = open_results(self.dir / "study.h5")
        self.assertEqual(len(results.runs), 4)
        self.assertEqual(results.runs[0], "maze/config_000/run_000")
        self.check(results)


if __name__ == "__main__":
    unittest.main()
