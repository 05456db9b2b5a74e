"""The module `ggk` replays the engine: a mountain-car job run by the binary, its
samples read back from the results file, and every step of the continuous-state
protocol redone with the module (the SOM, the best matches, the unit graph, the
shortest paths, the GGK / OGK / PVF tables, LSPI) gives the file's prototypes,
graph, weights, policy and iteration history bit for bit, for both solvers."""

import tomllib
import unittest

import numpy as np

import support
from support import Scratch, run_ggk

support.require("h5py", "scipy")
ggk = support.ggk_module()
import h5py  # noqa: E402


JOB = """name = "module-replay"
task = "mountain_car"
runs = 1
seed = 1990
[sweep]
basis = ["ggk", "ogk", "pvf"]
kernels = [10, 25]
sigma = [0.49]
solver = ["brm", "lstdq"]
lambda = [1e-6]
[mountain_car]
series = 40
steps_per_series = 100
test_episodes = 1
test_max_steps = 50
walk_start = "state_box"
[basis]
scheme = "copy"
[lspi]
gamma = 0.99
"""


def walk_observations(observations, next_observations):
    """The walks' observations in series order (the engine's state ids), and each
    sample's state and next state among them: a series starts where a sample's
    observation is not the previous sample's next observation."""
    rows, states, next_states = [], [], []
    for i in range(len(observations)):
        if i == 0 or not np.array_equal(observations[i], next_observations[i - 1]):
            rows.append(observations[i])
        states.append(len(rows) - 1)
        rows.append(next_observations[i])
        next_states.append(len(rows) - 1)
    return np.array(rows), np.array(states, np.int32), np.array(next_states, np.int32)


class ModuleReplaysTheEngine(Scratch):
    @classmethod
    def setUpClass(cls):
        import tempfile
        from pathlib import Path
        cls._folder = tempfile.TemporaryDirectory(prefix="ggk-module-")
        folder = Path(cls._folder.name)
        (folder / "job.toml").write_text(JOB)
        made = run_ggk("run", folder / "job.toml", "-q", "-o", folder / "r.h5")
        if made.returncode != 0:
            raise AssertionError(made.stderr)
        cls.file = h5py.File(folder / "r.h5", "r")
        cls.job = tomllib.loads(cls.file.attrs["job_resolved"])
        cls.run_group = cls.file["mountain_car/run_000"]

    @classmethod
    def tearDownClass(cls):
        cls.file.close()
        cls._folder.cleanup()

    def setUp(self):
        super().setUp()
        run = self.run_group
        samples = run["samples"]
        raw, self.states, self.next_states = walk_observations(
            samples["observations"][()], samples["next_observations"][()])
        self.observations = raw / run["observation_scale"][()]
        self.samples = ggk.Samples(self.states, samples["actions"][()], samples["rewards"][()],
                                   self.next_states, samples["terminals"][()])
        if self.job["lspi.fold_duplicates"]:
            self.samples = self.samples.folded()
        grid = run["som/grid"][()]
        self.som = ggk.SelfOrganizingMap(int(grid[:, 0].max()) + 1, int(grid[:, 1].max()) + 1,
                                         run["som/prototypes"][()])
        self.units, self.distances = self.som.best_matching_units(self.observations)
        self.graph = ggk.transition_graph(self.som.prototypes, self.units[self.states],
                                          self.units[self.next_states])

    def test_the_som_and_the_unit_graph_are_the_files(self):
        run = self.run_group
        np.testing.assert_array_equal(self.units, run["state_units"][()])
        trained = ggk.train_som(self.observations, epochs=self.job["mountain_car.som.epochs"],
                                final_radius=self.job["mountain_car.som.final_radius"])
        np.testing.assert_array_equal(trained.prototypes, run["som/prototypes"][()])
        np.testing.assert_array_equal(self.graph.indptr, run["graph/indptr"][()])
        np.testing.assert_array_equal(self.graph.indices, run["graph/indices"][()])
        np.testing.assert_array_equal(self.graph.weights, run["graph/weights"][()])

    def state_kernels(self, basis, fit):
        p, sigma = int(fit.attrs["kernels"]), float(fit.attrs["sigma"])
        truncation = self.job["basis.truncation"]
        if basis == "pvf":
            occupied = self.run_group["graph/occupied"][()]
            _, vectors = ggk.proto_value_functions(
                self.graph, p, nodes=occupied, laplacian=self.job["pvf.laplacian"],
                affinity=self.job["pvf.edge_weights"])
            return vectors[self.units]
        centers = fit["centers"][()].astype(np.int32)
        if basis == "ggk":
            distances = ggk.shortest_paths(self.graph, centers)
            return ggk.continuous_geodesic_kernels(self.units, self.distances, distances, sigma,
                                                   truncation)
        return ggk.ordinary_kernels(self.observations, self.som.prototypes[centers], sigma,
                                    truncation)

    def test_every_fit_replays_bit_for_bit(self):
        fits = 0
        for basis, group in self.run_group["fits"].items():
            for name, fit in group.items():
                with self.subTest(basis=basis, fit=name):
                    kernels = self.state_kernels(basis, fit)
                    result = ggk.lspi(
                        self.samples, ggk.copy_basis(kernels, 3),
                        solver=fit.attrs["solver"].decode() if isinstance(
                            fit.attrs["solver"], bytes) else str(fit.attrs["solver"]),
                        gamma=self.job["lspi.gamma"], ridge=float(fit.attrs["lambda"]),
                        ridge_scale=self.job["lspi.ridge"],
                        max_iterations=self.job["lspi.max_iterations"],
                        stopping=self.job["lspi.stopping"],
                        weight_tolerance=self.job["lspi.weight_tolerance"],
                        linear_algebra=self.job["lspi.linear_algebra"],
                        min_rcond=self.job["lspi.min_rcond"])
                    np.testing.assert_array_equal(result.policy, fit["policy"][()])
                    np.testing.assert_array_equal(result.history["policy_changes"],
                                                  fit["history"]["policy_changes"][()])
                    if basis == "pvf":
                        # The engine sums a PVF fit's system over the distinct (unit,
                        # action) and (action, successor unit) pairs
                        # (fit_lspi_pooled_copy_basis), the module over the readings:
                        # the same system up to rounding.
                        np.testing.assert_allclose(result.weights, fit["weights"][()],
                                                   rtol=1e-8, atol=1e-10)
                        for column in ("weight_change", "rcond"):
                            np.testing.assert_allclose(result.history[column],
                                                       fit["history"][column][()], rtol=1e-6)
                    else:
                        np.testing.assert_array_equal(result.weights, fit["weights"][()])
                        for column in ("weight_change", "rcond"):
                            np.testing.assert_array_equal(result.history[column],
                                                          fit["history"][column][()])
                    # The greedy policy of the module's fit acts as the engine's.
                    np.testing.assert_array_equal(result(kernels), fit["policy"][()])
                    fits += 1
        self.assertEqual(fits, 12)


PYTHON_JOB = """name = "module-walks"
task = "python_env"
runs = 2
seed = 5
[sweep]
basis = ["ggk"]
kernels = [5]
sigma = [0.5]
solver = ["brm"]
lambda = [1e-6]
[python_env]
factory = "ggk_test_envs.mountain_car:MountainCarTwin"
path = "{envs}"
series = 20
steps_per_series = 30
test_episodes = 2
test_max_steps = 50
[python_env.kwargs]
max_episode_steps = 50
"""


class ModuleWalksAreThePythonTasks(Scratch):
    def test_random_walks_equal_the_python_env_tasks_samples(self):
        envs = support.SOURCE / "tests" / "python" / "envs"
        if "python_env embeds CPython" not in run_ggk("--version").stdout:
            self.skipTest("ggk built without Python (GGK_WITH_PYTHON=OFF)")
        job = self.dir / "job.toml"
        job.write_text(PYTHON_JOB.format(envs=envs))
        made = run_ggk("run", job, "-q", "-o", self.dir / "r.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        import sys
        sys.path.insert(0, str(envs))
        from ggk_test_envs.mountain_car import MountainCarTwin
        with h5py.File(self.dir / "r.h5", "r") as results:
            for run in (0, 1):
                walks = ggk.random_walks(MountainCarTwin(max_episode_steps=50), series=20,
                                         steps_per_series=30, seed=5, run=run)
                stored = results[f"python_env/run_{run:03d}/samples"]
                s = walks.samples
                np.testing.assert_array_equal(walks.observations[s.states],
                                              stored["observations"][()])
                np.testing.assert_array_equal(walks.observations[s.next_states],
                                              stored["next_observations"][()])
                np.testing.assert_array_equal(s.actions, stored["actions"][()])
                np.testing.assert_array_equal(s.rewards, stored["rewards"][()])
                np.testing.assert_array_equal(s.terminals, stored["terminals"][()])


if __name__ == "__main__":
    unittest.main()
