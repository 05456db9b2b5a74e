"""ggk_results.adaptive_cells (the Python twin of engine/store/adaptive_state.hpp)
against `ggk info --adaptive --csv` on jobs/ci-adaptive.toml run by the binary:
the same cells, states, runs and confidence-sequence bounds (to 1e-12), a study
grown by --resume that the twin reads partway, and one whose cells stop on
their own (its later runs hold the open cells' fits alone)."""

import io
import re
import shutil

import support

support.require("numpy", "pandas", "h5py")
import h5py  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ggk_results import adaptive_cells, adaptive_rule  # noqa: E402


class AdaptiveCells(support.Scratch):
    def setUp(self):
        super().setUp()
        (self.dir / "maps").mkdir()
        shutil.copy(support.SOURCE / "jobs" / "maps" / "four-rooms.txt", self.dir / "maps")
        self.job = self.dir / "ci-adaptive.toml"
        shutil.copy(support.SOURCE / "jobs" / "ci-adaptive.toml", self.job)

    def run_job(self, output, *options):
        done = support.run_ggk("run", self.job, "-q", "-o", output, *options)
        self.assertEqual(done.returncode, 0, done.stderr)

    def assert_twins_agree(self, output):
        done = support.run_ggk("info", "--adaptive", "--csv", output)
        self.assertEqual(done.returncode, 0, done.stderr)
        ours = pd.read_csv(io.StringIO(done.stdout))
        theirs = adaptive_cells(output)
        self.assertEqual(len(ours), len(theirs))
        for column in ("compare", "metric", "state"):
            self.assertEqual(ours[column].astype(str).tolist(), theirs[column].astype(str).tolist())
        self.assertEqual(ours["runs"].tolist(), theirs["runs"].tolist())
        for column in ("kernels", "maze.slip", "difference", "cs_low", "cs_high"):
            np.testing.assert_allclose(ours[column].astype(float), theirs[column].astype(float),
                                       rtol=0, atol=1e-12, err_msg=column)
        return theirs

    def test_the_twin_reads_the_engines_cells(self):
        output = self.dir / "a.h5"
        self.run_job(output)
        cells = self.assert_twins_agree(output)
        self.assertTrue(cells.attrs["done"])
        self.assertEqual(set(cells["state"]), {"+"})
        self.assertLess(sum(cells.attrs["runs_wanted"]), 120)
        self.assertEqual(adaptive_rule(output)["compare"], ["basis=ggk,ogk"])

    def test_another_rule_replayed_on_the_files_runs(self):
        output = self.dir / "r.h5"
        self.run_job(output)
        own = adaptive_cells(output)
        same = adaptive_cells(output, rule={})
        pd.testing.assert_frame_equal(own, same)
        # Each cell at 95 % instead of 97.5 %: decided no later than under Bonferroni.
        looser = adaptive_cells(output, rule={"correction": "none"})
        self.assertTrue((looser["runs"].to_numpy() <= own["runs"].to_numpy()).all())
        self.assertEqual(looser.attrs["cell_level"], 0.95)

    def test_a_capped_study_and_its_growth(self):
        output = self.dir / "g.h5"
        self.run_job(output, "--set", "runs=10")
        capped = self.assert_twins_agree(output)
        self.assertIn("capped", set(capped["state"]))
        self.assertEqual(capped.attrs["runs_wanted"], [10, 10])
        self.run_job(output, "--resume")
        self.assert_twins_agree(output)

    def test_a_shard_judges_its_configurations_at_the_studys_level(self):
        self.run_job(self.dir / "w.h5")
        self.run_job(self.dir / "s.h5", "--shard", "1/2")
        shard = self.assert_twins_agree(self.dir / "s.shard-1-of-2.h5")
        whole = adaptive_cells(self.dir / "w.h5")
        self.assertEqual(len(shard), 1)
        self.assertEqual(shard.attrs["cell_level"], whole.attrs["cell_level"])  # 2 cells
        self.assertEqual(shard.attrs["runs_wanted"][0], 0)  # shard 0's configuration
        self.assertEqual(shard.attrs["runs_wanted"][1], whole.attrs["runs_wanted"][1])
        self.assertEqual(shard["cs_low"].tolist(), whole["cs_low"].tolist()[1:])

    def test_each_cell_stops_on_its_own(self):
        # Kernels 2 and 8: kernels 2's cells decide first, the later runs hold
        # kernels 8's fits alone; the twin replays the same looks on them.
        output = self.dir / "k.h5"
        self.run_job(output, "--set", "sweep.kernels=[2, 8]")
        cells = self.assert_twins_agree(output)
        self.assertTrue(cells.attrs["done"])
        runs = {int(float(k)): n for k, n in cells.groupby("kernels")["runs"].max().items()}
        self.assertLess(runs[2], runs[8])
        info = support.run_ggk("info", "--adaptive", output).stdout
        held = re.search(r"holding (\d+) of their (\d+) fits", info)
        self.assertIsNotNone(held, info)
        self.assertEqual((cells.attrs["fits_wanted"], cells.attrs["fits_whole"]),
                         (int(held.group(1)), int(held.group(2))))
        self.assertLess(cells.attrs["fits_wanted"], cells.attrs["fits_whole"])
        with h5py.File(output, "r") as f:
            last = sorted(r for r in f["maze/config_000"] if r.startswith("run_"))[-1]
            self.assertEqual(len(f[f"maze/config_000/{last}/fit_metrics"]), 2)


if __name__ == "__main__":
    import unittest
    unittest.main()
