"""results/plot_continuous.py: its replay of a fit's kernels (GGK over the stored
unit graph, OGK to the centres' prototypes) gives the kernel values ggk's fit
used at every sample (LSTD-Q's b = sum_i r_i phi(s_i, a_i), stored with
output.store_matrices) and the greedy action ggk stored at every SOM unit
(unit_policy); and it draws the figures of a continuous task."""

import importlib.util
import subprocess
import sys

import support
from support import Scratch, run_ggk

support.require("h5py", "numpy", "scipy", "matplotlib", "pandas")
import h5py  # noqa: E402
import numpy as np  # noqa: E402

SCRIPT = support.SOURCE / "results" / "plot_continuous.py"


def plot_module():
    spec = importlib.util.spec_from_file_location("plot_continuous", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class PlotContinuous(Scratch):
    def setUp(self):
        super().setUp()
        self.file = self.dir / "mc.h5"
        made = run_ggk("run", support.SOURCE / "jobs/ci-mountain-car.toml", "-q", "--set",
                       "runs=1", "--set", 'sweep.solver=["lstdq"]', "--set",
                       "output.store_matrices=true", "-o", self.file)
        self.assertEqual(made.returncode, 0, made.stderr)

    def assert_greedy(self, q, stored):
        top = np.sort(q, axis=1)
        clear = top[:, -1] - top[:, -2] > 1e-9 * np.abs(top[:, -1]).max()  # no near tie
        self.assertGreater(clear.sum(), 0.9 * len(q))
        np.testing.assert_array_equal(np.argmax(q, axis=1)[clear], stored[clear])

    def test_replayed_kernels_give_the_stored_fits(self):
        plot = plot_module()
        with h5py.File(self.file, "r") as f:
            run = f["mountain_car/run_000"]
            prototypes = run["som/prototypes"][:]
            samples = run["samples"]
            scaled = samples["observations"][:] / run["observation_scale"][:]
            actions, rewards = samples["actions"][:], samples["rewards"][:]
            checked = 0
            for basis in ("ggk", "ogk"):
                for name in run[f"fits/{basis}"]:
                    fit = run[f"fits/{basis}/{name}"]
                    k = plot.StateKernels(run, fit)(scaled)
                    b = np.concatenate([(rewards[actions == a, None] * k[actions == a]).sum(0)
                                        for a in range(3)])
                    np.testing.assert_allclose(b, fit["b"][:], rtol=1e-9,
                                               atol=1e-12 * np.abs(b).max())
                    self.assert_greedy(plot.q_values(run, fit, prototypes), fit["unit_policy"][:])
                    checked += 1
            self.assertEqual(checked, 4)

    def test_draws_the_figures(self):
        result = subprocess.run([sys.executable, str(SCRIPT), str(self.file), str(self.dir)],
                                capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        for name in ("mountain_car_steps.png", "mountain_car_values.png"):
            self.assertTrue((self.dir / name).stat().st_size > 10_000, name)
