"""The compiled module `ggk` (python/module) against numpy and scipy: the sample
graph and its shortest paths (scipy.sparse.csgraph), the kernel tables (a dense
exp), the proto-value functions (numpy.linalg.eigh of the Laplacian), the SOM's
best matches (a brute-force argmin), the copy and shift bases (built by hand) and
LSPI (a numpy transcription of BRM and LSTD-Q); errors as Python exceptions with
the engine's messages. test_module_engine.py checks fits against the engine's."""

import math
import unittest
from pathlib import Path

import numpy as np

import support

support.require("numpy", "scipy")
ggk = support.ggk_module()
import scipy.sparse as sp  # noqa: E402
from scipy.sparse.csgraph import connected_components, dijkstra  # noqa: E402

# exp as the C library computes it (std::exp in the kernels): numpy's own np.exp
# takes an AVX-512 path where the CPU has one, which differs in the last bit.
libm_exp = np.vectorize(math.exp, otypes=[float])


def grid_world(side=6, goal=None):
    """A side x side grid, 4 actions (up, down, left, right), every (s, a) once:
    deterministic successors, reward 1 for entering the goal (terminal)."""
    n = side * side
    goal = n - 1 if goal is None else goal
    s = np.repeat(np.arange(n), 4)
    a = np.tile(np.arange(4), n)
    row, col = s // side, s % side
    row = np.clip(row + np.select([a == 0, a == 1], [-1, 1], 0), 0, side - 1)
    col = np.clip(col + np.select([a == 2, a == 3], [-1, 1], 0), 0, side - 1)
    nxt = row * side + col
    terminal = (nxt == goal) & (s != goal)
    coords = np.stack([np.arange(n) // side, np.arange(n) % side], axis=1).astype(float)
    return coords, s.astype(np.int32), a.astype(np.int32), terminal.astype(float), \
        nxt.astype(np.int32), terminal.astype(np.uint8)


def numpy_lspi(table, m, s, a, r, nxt, term, solver, gamma, ridge, max_iterations=20):
    """LSPI as the paper writes it, dense numpy: BRM (Psi^T Psi + l I) w = Psi^T r,
    LSTD-Q (Phi^T (Phi - g Phi') + l I) w = Phi^T r; greedy ties to action 0."""
    table = table.toarray()
    k = table.shape[1]
    n_states = table.shape[0] // m
    phi = table[s * m + a]
    policy = np.zeros(n_states, dtype=np.int64)
    sample_states = np.unique(np.concatenate([s, nxt]))
    w = np.zeros(k)
    for _ in range(max_iterations):
        nxt_phi = table[nxt * m + policy[nxt]] * (1 - term)[:, None]
        if solver == "brm":
            psi = phi - gamma * nxt_phi
            w = np.linalg.solve(psi.T @ psi + ridge * np.eye(k), psi.T @ r)
        else:
            w = np.linalg.solve(phi.T @ (phi - gamma * nxt_phi) + ridge * np.eye(k), phi.T @ r)
        q = (table @ w).reshape(n_states, m)
        # Ties in exact arithmetic (a block of actions no reward reaches) are exact in
        # ggk and rounding residue (~1e-14) in a pivoted dense solve: round them away.
        new = np.argmax(np.round(q, 9), axis=1)
        changed = np.any(new[sample_states] != policy[sample_states])
        policy = new
        if not changed:
            break
    return w, policy


class Graphs(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(3)
        self.points = rng.random((60, 2))
        self.source = rng.integers(0, 60, 200).astype(np.int32)
        self.target = rng.integers(0, 60, 200).astype(np.int32)
        self.graph = ggk.transition_graph(self.points, self.source, self.target)

    def test_edges_are_the_transitions_at_euclidean_length(self):
        adjacency = self.graph.to_scipy().toarray()
        expected = np.zeros((60, 60))
        for u, v in zip(self.source, self.target):
            if u != v:
                # The squares summed in order, then the root: np.linalg.norm goes
                # through the BLAS's ddot, whose sums on AVX-512 machines differ
                # in the last bit.
                dx, dy = self.points[u] - self.points[v]
                expected[u, v] = expected[v, u] = math.sqrt(dx * dx + dy * dy)
        np.testing.assert_array_equal(adjacency, expected)
        self.assertEqual(self.graph.num_arcs, np.count_nonzero(expected))

    def test_shortest_paths_equal_scipy_dijkstra_bit_for_bit(self):
        sources = np.array([0, 5, 17, 59], dtype=np.int32)
        ours = ggk.shortest_paths(self.graph, sources)
        theirs = dijkstra(self.graph.to_scipy(), directed=True, indices=sources)
        self.assertEqual(ours.shape, (4, 60))
        np.testing.assert_array_equal(ours, theirs)

    def test_components_equal_scipy(self):
        graph = ggk.graph_from_edges(7, [0, 1, 3, 5], [1, 2, 4, 5], [1.0, 2.0, 1.0, 1.0])
        count, labels = graph.connected_components()
        theirs = connected_components(graph.to_scipy(), directed=False)
        self.assertEqual(count, theirs[0])
        np.testing.assert_array_equal(labels, theirs[1])
        np.testing.assert_array_equal(labels, [0, 0, 0, 1, 1, 2, 3])
        distances = ggk.shortest_paths(graph, np.array([0], dtype=np.int32))
        self.assertTrue(np.isinf(distances[0, 3:]).all())

    def test_bad_input_raises_with_the_engines_message(self):
        with self.assertRaisesRegex(ValueError, "source"):
            ggk.shortest_paths(self.graph, np.array([60], dtype=np.int32))
        with self.assertRaisesRegex(ValueError, "lengths"):
            ggk.transition_graph(self.points, [0, 1], [1])
        with self.assertRaisesRegex(ValueError, "weight"):
            ggk.graph_from_edges(3, [0], [1], [-1.0])


class KernelTables(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(4)
        self.points = rng.random((40, 3))
        self.graph = ggk.transition_graph(self.points, rng.integers(0, 40, 160).astype(np.int32),
                                          rng.integers(0, 40, 160).astype(np.int32))
        self.centers = np.array([1, 7, 30], dtype=np.int32)
        self.distances = ggk.shortest_paths(self.graph, self.centers)

    def test_geodesic_kernels_are_a_dense_exp_of_the_distances(self):
        table = ggk.geodesic_kernels(self.distances, 0.4, truncation=0.05)
        self.assertIsInstance(table, sp.csr_matrix)
        dense = libm_exp(-self.distances.T ** 2 / (2 * 0.4 ** 2))
        dense[~(dense >= 0.05)] = 0.0
        np.testing.assert_array_equal(table.toarray(), dense)

    def test_ordinary_kernels_are_a_dense_exp_of_euclidean_distances(self):
        centers = self.points[self.centers]
        table = ggk.ordinary_kernels(self.points, centers, 0.3)
        d = np.linalg.norm(self.points[:, None, :] - centers[None, :, :], axis=2)
        np.testing.assert_allclose(table.toarray(), np.exp(-d ** 2 / (2 * 0.3 ** 2)),
                                   rtol=1e-14, atol=0)

    def test_continuous_geodesic_kernels_add_the_step_to_the_nearest_node(self):
        nearest = np.array([0, 3, 39], dtype=np.int32)
        step = np.array([0.0, 0.1, 0.25])
        table = ggk.continuous_geodesic_kernels(nearest, step, self.distances, 0.5)
        geodesic = step[:, None] + self.distances.T[nearest]
        np.testing.assert_array_equal(table.toarray(),
                                      np.where(np.isinf(geodesic), 0.0,
                                               libm_exp(-geodesic ** 2 / (2 * 0.5 ** 2))))

    def test_nearest_visited_state_is_a_scan_with_ties_to_the_lowest_id(self):
        states = np.array([[0.0], [1.0], [2.0], [3.0], [4.0]])
        nearest, distance = ggk.nearest_visited_states(states, [1, 0, 0, 1, 0])
        np.testing.assert_array_equal(nearest, [0, 0, 3, 3, 3])
        np.testing.assert_array_equal(distance, [0.0, 1.0, 1.0, 0.0, 1.0])
        nearest, _ = ggk.nearest_visited_states(states, [0, 1, 0, 1, 0])  # state 2: a tie
        np.testing.assert_array_equal(nearest, [1, 1, 1, 3, 3])

    def test_non_finite_values_are_refused(self):
        bad = self.points.copy()
        bad[2, 1] = np.nan
        with self.assertRaisesRegex(ValueError, "state 2"):
            ggk.ordinary_kernels(bad, self.points[:2], 0.3)
        with self.assertRaisesRegex(ValueError, "sigma"):
            ggk.geodesic_kernels(self.distances, 0.0)


class ProtoValueFunctions(unittest.TestCase):
    def test_eigenpairs_equal_numpy_eigh_of_the_normalized_laplacian(self):
        rng = np.random.default_rng(5)
        points = rng.random((30, 2))
        order = np.argsort(points[:, 0]).astype(np.int32)  # a path through every node, so connected
        extra = rng.integers(0, 30, (2, 40)).astype(np.int32)
        graph = ggk.transition_graph(points, np.concatenate([order[:-1], extra[0]]),
                                     np.concatenate([order[1:], extra[1]]))
        values, vectors = ggk.proto_value_functions(graph, 6)
        w = (graph.to_scipy().toarray() > 0).astype(float)
        d = w.sum(axis=1)
        laplacian = np.eye(30) - w / np.sqrt(np.outer(d, d))
        expected_values, expected_vectors = np.linalg.eigh(laplacian)
        self.assertEqual(values[0], 0.0)
        np.testing.assert_allclose(values, expected_values[:6], atol=1e-10)
        for j in range(6):  # one vector per simple eigenvalue, up to its sign
            dot = abs(vectors[:, j] @ expected_vectors[:, j])
            self.assertAlmostEqual(dot, 1.0, places=9)
            self.assertGreater(vectors[np.argmax(np.abs(vectors[:, j])), j], 0)
        nodes, matrix, null_space = ggk.graph_laplacian(graph)
        np.testing.assert_allclose(matrix.toarray(), laplacian, atol=1e-15)
        np.testing.assert_allclose(null_space[:, 0], np.sqrt(d) / np.linalg.norm(np.sqrt(d)))

    def test_rows_off_the_nodes_are_zero(self):
        graph = ggk.graph_from_edges(5, [0, 1, 2], [1, 2, 3], [1.0, 1.0, 1.0])
        values, vectors = ggk.proto_value_functions(graph, 2, nodes=[1, 1, 1, 1, 0],
                                                    laplacian="combinatorial")
        np.testing.assert_array_equal(vectors[4], [0.0, 0.0])
        np.testing.assert_allclose(vectors[:4, 0], 0.5)
        with self.assertRaisesRegex(ValueError, "laplacian must be one of"):
            ggk.proto_value_functions(graph, 2, laplacian="random_walk")


class SelfOrganizingMaps(unittest.TestCase):
    def test_best_matches_are_a_brute_force_argmin_and_training_is_deterministic(self):
        rng = np.random.default_rng(6)
        samples = rng.random((400, 3))
        som = ggk.train_som(samples, epochs=10)
        self.assertEqual((som.rows, som.cols), ggk.som_grid(samples))
        self.assertEqual(som.prototypes.shape, (som.num_units, 3))
        self.assertEqual(len(som.quantization_errors), 10)
        np.testing.assert_array_equal(som.prototypes, ggk.train_som(samples, epochs=10).prototypes)
        queries = rng.random((50, 3))
        units, distances = som.best_matching_units(queries)
        squared = ((queries[:, None, :] - som.prototypes[None, :, :]) ** 2).sum(axis=2)
        np.testing.assert_array_equal(units, np.argmin(squared, axis=1))
        np.testing.assert_allclose(distances, np.sqrt(squared.min(axis=1)), rtol=1e-15)
        given = ggk.SelfOrganizingMap(som.rows, som.cols, som.prototypes.copy())
        np.testing.assert_array_equal(given.best_matching_units(queries)[0], units)


class Bases(unittest.TestCase):
    def test_copy_and_shift_tables(self):
        coords, s, a, r, nxt, term = grid_world(4)
        graph = ggk.transition_graph(coords, s, nxt)
        kernels = ggk.geodesic_kernels(ggk.shortest_paths(graph, np.array([0, 5, 15], np.int32)),
                                       1.5)
        copy = ggk.copy_basis(kernels, 4)
        self.assertEqual((copy.num_states, copy.num_features), (16, 12))
        dense = kernels.toarray()
        expected = np.zeros((64, 12))
        for state in range(16):
            for action in range(4):
                expected[state * 4 + action, action * 3:(action + 1) * 3] = dense[state]
        np.testing.assert_array_equal(copy.table.toarray(), expected)
        shift = ggk.shift_basis(kernels, 4, s, a, nxt)
        shifted = np.zeros((64, 12))
        for state, action, successor in zip(s, a, nxt):
            shifted[state * 4 + action, action * 3:(action + 1) * 3] = dense[successor]
        np.testing.assert_array_equal(shift.table.toarray(), shifted)
        with self.assertRaisesRegex(ValueError, "action-block form"):
            ggk.table_basis(sp.csr_matrix(np.ones((8, 4))), 2)


class Lspi(unittest.TestCase):
    def setUp(self):
        coords, self.s, self.a, self.r, self.nxt, self.term = grid_world(6)
        graph = ggk.transition_graph(coords, self.s, self.nxt)
        centers = np.array([0, 8, 21, 35, 14, 29], dtype=np.int32)
        self.kernels = ggk.geodesic_kernels(ggk.shortest_paths(graph, centers), 2.0)
        self.samples = ggk.Samples(self.s, self.a, self.r, self.nxt, self.term)

    def test_brm_and_lstdq_equal_numpy_lspi(self):
        for solver in ("brm", "lstdq"):
            for basis in (ggk.copy_basis(self.kernels, 4),
                          ggk.shift_basis(self.kernels, 4, self.s, self.a, self.nxt)):
                with self.subTest(solver=solver, scheme=basis.scheme):
                    fit = ggk.lspi(self.samples, basis, solver=solver, gamma=0.9, ridge=1e-6)
                    self.assertTrue(fit.ok, fit.message)
                    weights, policy = numpy_lspi(basis.table, 4, self.s, self.a, self.r,
                                                 self.nxt, self.term, solver, 0.9, 1e-6)
                    np.testing.assert_allclose(fit.weights, weights, rtol=1e-9, atol=1e-12)
                    np.testing.assert_array_equal(fit.policy, policy)
                    self.assertEqual(len(fit.history["rcond"]), fit.iterations)

    def test_the_fit_is_its_greedy_policy(self):
        basis = ggk.copy_basis(self.kernels, 4)
        fit = ggk.lspi({"states": self.s, "actions": self.a, "rewards": self.r,
                        "next_states": self.nxt, "terminals": self.term}, basis, ridge=1e-6)
        dense = self.kernels.toarray()
        np.testing.assert_array_equal(fit(self.kernels), fit.policy)
        np.testing.assert_array_equal(fit(dense), fit.policy)
        self.assertEqual(fit(dense[7]), fit.policy[7])
        q = fit.q_values(dense)
        np.testing.assert_allclose(q, (basis.table @ fit.weights).reshape(36, 4), rtol=1e-13)
        with self.assertRaisesRegex(ValueError, "rows of 6 state kernels"):
            fit(np.ones(5))

    def test_same_samples_give_the_same_bits(self):
        basis = ggk.copy_basis(self.kernels, 4)
        first = ggk.lspi(self.samples, basis, ridge=1e-6)
        second = ggk.lspi(self.samples, basis, ridge=1e-6)
        np.testing.assert_array_equal(first.weights, second.weights)
        table = ggk.table_basis(basis.table, 4)  # the copy path equals the table path
        np.testing.assert_array_equal(ggk.lspi(self.samples, table, ridge=1e-6).weights,
                                      first.weights)

    def test_bad_samples_and_options_raise(self):
        basis = ggk.copy_basis(self.kernels, 4)
        with self.assertRaisesRegex(ValueError, "gamma"):
            ggk.lspi(self.samples, basis, gamma=1.0)
        with self.assertRaisesRegex(ValueError, "solver must be one of"):
            ggk.lspi(self.samples, basis, solver="td")
        bad = ggk.Samples(self.s, self.a, self.r, self.nxt + 100, self.term)
        with self.assertRaisesRegex(ValueError, "state id outside"):
            ggk.lspi(bad, basis)
        with self.assertRaisesRegex(ValueError, "one length"):
            ggk.Samples(self.s, self.a[:-1], self.r, self.nxt)
        singular = ggk.lspi(self.samples, ggk.copy_basis(sp.csr_matrix((36, 6)), 4))
        self.assertEqual(singular.status, "solver_failed")
        self.assertTrue(singular.message)


class Environments(unittest.TestCase):
    def setUp(self):
        import sys
        sys.path.insert(0, str(support.SOURCE / "tests" / "python" / "envs"))
        from ggk_test_envs import broken, mountain_car
        self.broken, self.twin = broken, mountain_car.MountainCarTwin

    def test_walks_index_their_observations_and_end_series_as_the_env_says(self):
        walks = ggk.random_walks(self.twin(max_episode_steps=15), series=4, steps_per_series=10,
                                 seed=3)
        s = walks.samples
        self.assertEqual(len(s), 40)  # 4 series of 10 steps (none ends before)
        self.assertEqual(walks.observations.shape, (44, 2))
        np.testing.assert_array_equal(s.next_states, s.states + 1)
        np.testing.assert_array_equal(s.states[:11], list(range(10)) + [11])
        truncated = ggk.random_walks(self.twin(max_episode_steps=5), series=3,
                                     steps_per_series=10, seed=3)
        self.assertEqual(len(truncated.samples), 15)  # truncated after 5 steps, not absorbing
        self.assertFalse(truncated.samples.terminals.any())
        again = ggk.random_walks(self.twin(max_episode_steps=15), series=4, steps_per_series=10,
                                 seed=3)
        np.testing.assert_array_equal(again.observations, walks.observations)
        other = ggk.random_walks(self.twin(max_episode_steps=15), series=4, steps_per_series=10,
                                 seed=3, run=1)
        self.assertFalse(np.array_equal(other.observations, walks.observations))

    def test_greedy_episodes_count_terminated_as_success(self):
        test = ggk.greedy_episodes(self.twin(max_episode_steps=200), lambda o: 2 if o[1] >= 0
                                   else 0, episodes=3, max_steps=200, seed=1)
        self.assertEqual(set(test), {"returns", "lengths", "success"})
        self.assertTrue(test["success"].all())  # pushing with the velocity climbs the hill
        np.testing.assert_array_equal(test["returns"], -test["lengths"])
        stuck = ggk.greedy_episodes(self.twin(max_episode_steps=30), lambda o: 1, episodes=2,
                                    max_steps=200, seed=1)
        self.assertFalse(stuck["success"].any())
        np.testing.assert_array_equal(stuck["lengths"], [30, 30])

    def test_environments_breaking_the_api_raise(self):
        with self.assertRaisesRegex(TypeError, "action_space.n"):
            ggk.random_walks(self.broken.BoxActions(), 1, 5, seed=0)
        with self.assertRaisesRegex(ValueError, "series 0, step 3: the observation is not finite"):
            ggk.random_walks(self.broken.NanAfter(step=4), 1, 10, seed=0)
        with self.assertRaisesRegex(RuntimeError, "broken on purpose"):
            ggk.random_walks(self.broken.RaisesAfter(step=2), 1, 10, seed=0)
        with self.assertRaisesRegex(ValueError, "the policy chose 7"):
            ggk.greedy_episodes(self.twin(), lambda o: 7, episodes=1, max_steps=5, seed=0)


class ReadmeExample(unittest.TestCase):
    def test_the_readmes_example_runs_and_prints_both_bases(self):
        import re
        import subprocess
        import sys
        text = (support.SOURCE / "README.md").read_text()
        blocks = [b for b in re.findall(r"```python\n(.*?)```", text, re.S)
                  if "ggk.random_walks" in b]
        self.assertEqual(len(blocks), 1)
        env = dict(__import__("os").environ, PYTHONPATH=str(Path(ggk.__file__).parent))
        ran = subprocess.run([sys.executable, "-c", blocks[0]], cwd=support.SOURCE, env=env,
                             capture_output=True, text=True, timeout=120)
        self.assertEqual(ran.returncode, 0, ran.stderr)
        lines = ran.stdout.splitlines()
        self.assertEqual([line.split()[0] for line in lines], ["GGK", "OGK"])
        self.assertIn("success", lines[0])


if __name__ == "__main__":
    unittest.main()
