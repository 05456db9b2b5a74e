"""What the Python tests share: ggk_results from this checkout (python/), the ggk
binary (GGK, set by ctest) and job files written into a scratch folder."""

import importlib.util
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

SOURCE = Path(os.environ.get("GGK_SOURCE_DIR", Path(__file__).resolve().parents[2]))
sys.path.insert(0, str(SOURCE / "python"))


def require(*modules):
    """Skips the calling test module when a Debian package it needs is missing."""
    for name in modules:
        # find_spec, not import: importing setuptools after pip breaks distutils.
        if importlib.util.find_spec(name) is None:
            raise unittest.SkipTest(f"no module {name} (Debian: scripts/install-deps.sh)")


def ggk():
    """The ggk binary ctest gives (GGK), or build/ggk of this checkout."""
    binary = os.environ.get("GGK", str(SOURCE / "build" / "ggk"))
    if not Path(binary).exists():
        raise unittest.SkipTest(f"no ggk binary at {binary}")
    return binary


def run_ggk(*arguments):
    """Runs ggk; returns the CompletedProcess (stdout, stderr as text)."""
    return subprocess.run([ggk(), *map(str, arguments)], capture_output=True, text=True,
                          check=False)


class Scratch(unittest.TestCase):
    """A test case with a scratch folder, removed afterwards."""

    def setUp(self):
        self._scratch = tempfile.TemporaryDirectory(prefix="ggk-python-")
        self.dir = Path(self._scratch.name)

    def tearDown(self):
        self._scratch.cleanup()


def maze_job(path, runs, kernels=(4, 8), solvers=("brm",), sigmas=(10.0,)):
    """A small maze job (the four-rooms map) at `path`."""
    quote = lambda values: ", ".join(f'"{v}"' if isinstance(v, str) else repr(v) for v in values)
    path.write_text(f"""name = "python-test"
task = "maze"
runs = {runs}
seed = 17
[sweep]
basis = ["ggk", "ogk"]
kernels = [{quote(kernels)}]
sigma = [{quote(sigmas)}]
solver = [{quote(solvers)}]
[maze]
map_file = "{SOURCE / 'jobs/maps/four-rooms.txt'}"
series = 20
steps_per_series = 150
""")
    return path


def ggk_module():
    """The compiled module `ggk` (GGK_MODULE_DIR, set by ctest, or build/python of this
    checkout); skips the calling test module when it was not built."""
    folder = os.environ.get("GGK_MODULE_DIR", str(SOURCE / "build" / "python"))
    if not folder:  # ctest's build has no module (GGK_WITH_PYTHON=OFF)
        raise unittest.SkipTest("ggk built without Python (GGK_WITH_PYTHON=OFF): no module ggk")
    if not any(Path(folder).glob("ggk*.so")):
        raise unittest.SkipTest(f"no module ggk in {folder} (a build with GGK_WITH_PYTHON)")
    sys.path.insert(0, folder)
    import ggk
    return ggk
