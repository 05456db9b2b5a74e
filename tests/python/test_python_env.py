"""The python_env task through the real binary: a Python environment with the
Gymnasium API (the project's own, tests/python/envs) runs bit-identically for
any -j and shard split; every bad input is refused at the job's `factory` with
exit 2 and nothing written; an environment that fails mid-run fails the run (in
the walks, naming series and step) or the fit (in its test, status
environment_failed)."""

import subprocess

import support
from support import Scratch, run_ggk

support.require("h5py")
import h5py  # noqa: E402

ENVS = support.SOURCE / "tests" / "python" / "envs"


def python_job(path, factory, kwargs="", runs=1, series=20, extra=""):
    path.write_text(f"""name = "python-env-test"
task = "python_env"
runs = {runs}
seed = 5
[sweep]
basis = ["ggk", "ogk"]
kernels = [5]
sigma = [0.5]
solver = ["brm"]
lambda = [1e-6]
[python_env]
factory = "{factory}"
path = "{ENVS}"
series = {series}
steps_per_series = 30
test_episodes = 2
test_max_steps = 50
[python_env.kwargs]
{kwargs}
[basis]
scheme = "copy"
{extra}""")
    return path


class PythonEnv(Scratch):
    def has_python_env(self):
        version = run_ggk("--version").stdout
        if "python_env embeds CPython" not in version:
            self.skipTest("ggk built without Python (GGK_WITH_PYTHON=OFF)")

    def setUp(self):
        super().setUp()
        self.has_python_env()

    def test_same_results_for_any_threads_and_shard_split(self):
        job = python_job(self.dir / "mc.toml", "ggk_test_envs.mountain_car:MountainCarTwin",
                         "max_episode_steps = 50", runs=3)
        outputs = {}
        for name, arguments in (("j1", ["-j", "1"]), ("j2", ["-j", "2"])):
            outputs[name] = self.dir / f"{name}.h5"
            made = run_ggk("run", job, "-q", *arguments, "-o", outputs[name])
            self.assertEqual(made.returncode, 0, made.stderr)
        for shard, runs in (("a", "0:1"), ("b", "1:3")):
            made = run_ggk("run", job, "-q", "--runs", runs, "-o", self.dir / f"{shard}.h5")
            self.assertEqual(made.returncode, 0, made.stderr)
        merged = run_ggk("merge", self.dir / "merged.h5", self.dir / "a.h5", self.dir / "b.h5")
        self.assertEqual(merged.returncode, 0, merged.stderr)
        for other in (outputs["j2"], self.dir / "merged.h5"):
            same = run_ggk("diff", outputs["j1"], other)
            self.assertEqual(same.returncode, 0, same.stdout + same.stderr)

    def test_bad_inputs_are_refused_at_the_factory_with_nothing_written(self):
        cases = [
            ("no_such_module:Env", "", "cannot import 'no_such_module': ModuleNotFoundError"),
            ("ggk_test_envs.mountain_car:NoSuchEnv", "", "has no 'NoSuchEnv'"),
            ("ggk_test_envs.broken:raising_factory", "",
             "raised ValueError: this factory always fails"),
            ("ggk_test_envs.broken:NoStep", "", "has no step()"),
            ("ggk_test_envs.broken:BoxActions", "", "needs a discrete action set"),
            ("ggk_test_envs.broken:ImageObservation", "", "of shape (2, 2)"),
            ("ggk_test_envs.mountain_car:MountainCarTwin", "no_such_argument = 1",
             "unexpected keyword argument 'no_such_argument'"),
            ("not-a-factory", "", 'expected "package.module:callable"'),
        ]
        for factory, kwargs, expected in cases:
            with self.subTest(factory=factory):
                job = python_job(self.dir / "bad.toml", factory, kwargs)
                output = self.dir / "bad.h5"
                for command in ("validate", "run"):
                    result = run_ggk(command, job, "-o", output)
                    self.assertEqual(result.returncode, 2, result.stderr)
                    self.assertIn("[python_env] factory", result.stderr)
                    self.assertIn(expected, result.stderr)
                    self.assertFalse(output.exists())

    def test_a_missing_module_path_is_named(self):
        job = python_job(self.dir / "bad.toml", "ggk_test_envs.mountain_car:MountainCarTwin")
        job.write_text(job.read_text().replace(f'path = "{ENVS}"', 'path = "no/such/folder"'))
        result = run_ggk("validate", job)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("[python_env] path: no folder", result.stderr)

    def test_a_non_finite_observation_in_the_walks_fails_the_run_naming_where(self):
        job = python_job(self.dir / "nan.toml", "ggk_test_envs.broken:NanAfter", "step = 3")
        result = run_ggk("run", job, "-q", "-o", self.dir / "nan.h5")
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("run 0: the walks' series 0, step 2: step returned a non-finite observation",
                      result.stderr)

    def test_a_step_that_raises_in_the_test_fails_the_fit_not_the_run(self):
        job = python_job(self.dir / "raises.toml", "ggk_test_envs.broken:RaisesAfter",
                         "step = 2\nspared = 2")
        output = self.dir / "raises.h5"
        result = run_ggk("run", job, "-j", "1", "-o", output)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("2 fits (2 failed)", result.stderr)
        with h5py.File(output, "r") as f:
            fits = f["python_env/run_000/fits"]
            for basis in fits:
                for name in fits[basis]:
                    attrs = fits[basis][name].attrs
                    self.assertEqual(attrs["status"], "environment_failed")
                    self.assertIn("test episode 0, step 1: step(", attrs["message"])
                    self.assertIn("RuntimeError: broken on purpose at step 2", attrs["message"])


if __name__ == "__main__":
    import unittest
    unittest.main()
