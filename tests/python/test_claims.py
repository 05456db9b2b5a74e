"""results/claims.py on any files: recognised by task and rotation step, not by
name (the quick reproduction's out/quick/arm.h5 and khepera.h5), its numbers
those of ggk_results.paired, two files for one role refused."""

import shutil
import subprocess
import sys
import unittest

import support
from support import Scratch, run_ggk

support.require("h5py", "pandas", "xarray")
import ggk_results  # noqa: E402

CLAIMS = support.SOURCE / "results" / "claims.py"


def claims(*arguments):
    return subprocess.run([sys.executable, str(CLAIMS), *map(str, arguments)],
                          capture_output=True, text=True)


class Claims(Scratch):
    def setUp(self):
        super().setUp()
        quick = self.dir / "quick"
        quick.mkdir()
        for job, name in (("arm-quick", "arm"), ("khepera-quick", "khepera")):
            made = run_ggk("run", support.SOURCE / f"jobs/{job}.toml", "-q", "-o",
                           quick / f"{name}.h5")
            self.assertEqual(made.returncode, 0, made.stderr)
        self.quick = quick

    def test_reads_the_quick_files_of_a_folder(self):
        result = claims("--results", self.quick)
        self.assertEqual(result.returncode, 0, result.stderr)
        table = result.stdout
        self.assertIn("| Arm: success vs kernels (Fig. 3) |", table)
        self.assertIn("| Khepera: exploration vs kernels (Fig. 6), BRM,", table)
        self.assertNotIn("missing", table)
        # The Khepera row's numbers are paired()'s: the worst point's difference.
        frame = ggk_results.open_results(self.quick / "khepera.h5").summary()
        points = ggk_results.paired(frame[frame.solver == "brm"], "mean_return")
        best = points.loc[points.difference.idxmax()]
        self.assertIn(f"best for GGK: {int(best.kernels)} kernels {best.a:.3g} vs {best.b:.3g} "
                      f"({best.difference:+.3g} ± {best.high - best.difference:.2g})", table)
        # success from A is 0/1 per run: Newcombe's interval, printed as bounds.
        arm_row = next(line for line in table.splitlines() if "Fig. 3" in line)
        self.assertIn("95 % CI", arm_row)

    def test_takes_a_file_list_and_says_what_is_missing(self):
        result = claims(self.quick / "khepera.h5")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("(results/arm-paper.h5 missing: ggk run jobs/arm-paper.toml)", result.stdout)
        self.assertIn("Khepera: exploration vs kernels", result.stdout)

    def test_refuses_two_files_for_one_role(self):
        shutil.copy(self.quick / "arm.h5", self.quick / "arm-again.h5")
        result = claims("--results", self.quick)
        self.assertEqual(result.returncode, 2)
        self.assertIn("arm-again.h5", result.stderr)
        self.assertIn("both hold arm results", result.stderr)
        # The paper's file name wins over any other file for its role.
        shutil.copy(self.quick / "arm.h5", self.quick / "arm-paper.h5")
        self.assertEqual(claims("--results", self.quick).returncode, 0)

    def test_rows_of_the_third_basis(self):
        # No "pvf" fits: no PVF rows.
        self.assertNotIn("PVF", claims("--results", self.quick).stdout)
        made = run_ggk("run", support.SOURCE / "jobs/arm-quick.toml", "-q", "--overwrite",
                       "--set", 'sweep.basis=["ggk","ogk","pvf"]', "-o", self.quick / "arm.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        result = claims("--results", self.quick)
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = {line.split(" | ")[0]: line for line in result.stdout.splitlines()}
        frame = ggk_results.open_results(self.quick / "arm.h5").summary()
        for a, b in (("ggk", "pvf"), ("pvf", "ogk")):
            row = rows[f"| Arm: {a.upper()} vs {b.upper()} (BRM; ggk's third basis, "
                       "proto-value functions)"]
            # paired()'s numbers, a - b by run.
            points = ggk_results.paired(frame[frame.solver == "brm"], "success_from_A",
                                        a=a, b=b)
            best = points.loc[points.difference.idxmax()]
            self.assertIn(f"best for {a.upper()}: {int(best.kernels)} kernels "
                          f"{100 * best.a:.3g} % vs {100 * best.b:.3g} %", row)
            self.assertRegex(row, rf"\| {a.upper()} (ahead|partly ahead|not ahead) \|$")

    def test_rows_of_a_maze_file(self):
        # No maze file: no maze row (the maze is not one of the paper's claims).
        self.assertNotIn("Maze", claims("--results", self.quick).stdout)
        made = run_ggk("run", support.SOURCE / "jobs/maze.toml", "-q", "--set", "runs=4",
                       "--set", "sweep.kernels=[8,24]", "-o", self.quick / "maze-small.h5")
        self.assertEqual(made.returncode, 0, made.stderr)
        result = claims("--results", self.quick)
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = {line.split(" | ")[0]: line for line in result.stdout.splitlines()}
        frame = ggk_results.open_results(self.quick / "maze-small.h5").summary()
        for solver in ("brm", "lstdq"):
            row = rows[f"| Maze: success vs kernels, {solver.upper()} (ggk's addition: the GGK "
                       "papers' artificial task, the four-rooms map of jobs/maze.toml)"]
            points = ggk_results.paired(frame[frame.solver == solver], "success_rate")
            best = points.loc[points.difference.idxmax()]
            self.assertIn(f"best for GGK: {int(best.kernels)} kernels "
                          f"{100 * best.a:.3g} % vs {100 * best.b:.3g} %", row)
            for a, b in (("ggk", "pvf"), ("pvf", "ogk")):
                self.assertIn(f"| Maze: {a.upper()} vs {b.upper()} ({solver.upper()}; ggk's "
                              "third basis, proto-value functions)", rows)
        # A second maze file is a second file for one role; maze.h5 is the paper's name.
        shutil.copy(self.quick / "maze-small.h5", self.quick / "maze-again.h5")
        refused = claims("--results", self.quick)
        self.assertEqual(refused.returncode, 2)
        self.assertIn("both hold maze results", refused.stderr)
        shutil.copy(self.quick / "maze-small.h5", self.quick / "maze.h5")
        self.assertEqual(claims("--results", self.quick).returncode, 0)


if __name__ == "__main__":
    unittest.main()
