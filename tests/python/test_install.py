"""python/ installs as the package ggk_results into a fresh venv that sees
Debian's packages (--system-site-packages), with --no-deps and without a
package index, and the installed package reads a results file."""

import os
import shutil
import subprocess
import sys
import unittest

import support
from support import Scratch, maze_job, run_ggk


class Install(Scratch):
    def test_installs_into_a_fresh_venv_without_an_index(self):
        support.require("pip", "setuptools", "xarray")
        # A copy: pip builds in the source folder (build/, *.egg-info).
        source = self.dir / "python"
        shutil.copytree(support.SOURCE / "python", source,
                        ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
        venv = self.dir / "venv"
        subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip",
                        str(venv)], check=True)
        python = venv / "bin" / "python"
        env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
        installed = subprocess.run(
            [str(python), "-m", "pip", "install", "--no-deps", "--no-build-isolation",
             "--no-index", str(source)], capture_output=True, text=True, env=env)
        self.assertEqual(installed.returncode, 0, installed.stdout + installed.stderr)

        results = self.dir / "r.h5"
        made = run_ggk("run", maze_job(self.dir / "job.toml", runs=2), "-q", "-o", results)
        self.assertEqual(made.returncode, 0, made.stderr)
        # Run outside the checkout, so that only the installed copy can be found.
        shutil.rmtree(source)
        script = ("import ggk_results, sys\n"
                  "r = ggk_results.open_results(sys.argv[1])\n"
                  "print(ggk_results.__file__)\n"
                  "print(len(r.summary()), r.dataset().success_rate.dims)\n")
        used = subprocess.run([str(python), "-c", script, str(results)], capture_output=True,
                              text=True, cwd=self.dir, env=dict(os.environ, PYTHONPATH=""))
        self.assertEqual(used.returncode, 0, used.stderr)
        where, rows = used.stdout.splitlines()[:2]
        self.assertTrue(where.startswith(str(venv)), where)
        self.assertTrue(rows.startswith("8 ('run', 'basis', 'kernels'"), rows)


if __name__ == "__main__":
    unittest.main()
