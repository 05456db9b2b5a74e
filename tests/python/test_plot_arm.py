"""results/plot_arm.py on a study's file (a run configuration per value of a
run-level axis): it draws every figure (it ended in KeyError 'run_000' before),
says which configuration the run figures show, and takes --where."""

import subprocess
import sys

import support
from support import Scratch, run_ggk

support.require("h5py", "numpy", "matplotlib")

SCRIPT = support.SOURCE / "results" / "plot_arm.py"


class PlotArmStudy(Scratch):
    def setUp(self):
        super().setUp()
        self.file = self.dir / "grid.h5"
        made = run_ggk("run", support.SOURCE / "jobs/ci-arm.toml", "-q", "--set", "runs=1",
                       "--sweep", "arm.grid_step_degrees=5,2.5", "--sweep", "kernels=16",
                       "-o", self.file)
        self.assertEqual(made.returncode, 0, made.stderr)

    def plot(self, *extra):
        return subprocess.run([sys.executable, str(SCRIPT), str(self.file), str(self.dir), *extra],
                              capture_output=True, text=True)

    def test_draws_a_studys_figures_and_takes_where(self):
        for extra in ((), ("--where", "arm.grid_step_degrees=2.5")):
            with self.subTest(extra=extra):
                result = self.plot(*extra)
                self.assertEqual(result.returncode, 0, result.stderr)
                for name in ("arm_state_space.png", "arm_values.png", "arm_success.png"):
                    self.assertTrue((self.dir / name).exists(), name)

    def test_names_the_configuration_shown(self):
        plot = __import__("importlib.util").util
        spec = plot.spec_from_file_location("plot_arm", SCRIPT)
        module = plot.module_from_spec(spec)
        spec.loader.exec_module(module)
        summary, configuration = module.select_where(
            module.read_summary(self.file, "arm"), ["arm.grid_step_degrees=2.5"])
        self.assertEqual(module.configuration_label(summary, configuration),
                         " (study configuration 1: arm.grid_step_degrees=2.5)")
