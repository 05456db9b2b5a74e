"""ggk_results.ACTION_NAMES names each task's action codes as the simulators do
(sims/*/: kActionNames, action_name), so that a relabelled policy cannot drift
from the C++ it reads."""

import re
import unittest

import support
from ggk_results import ACTION_NAMES

SOURCES = {
    "maze": "sims/maze/maze.cpp",
    "arm": "sims/arm/arm.cpp",
    "khepera": "sims/khepera/motion.cpp",
}


class Actions(unittest.TestCase):
    def test_names_match_the_simulators(self):
        for task, source in SOURCES.items():
            text = (support.SOURCE / source).read_text()
            # The initializer of the action-name array: {"up", "down", ...}.
            match = re.search(r"k(?:Action)?Names(?:\[[^\]]*\])?\s*=\s*\{([^}]*)\}", text)
            self.assertIsNotNone(match, f"{source}: no action-name array")
            names = tuple(re.findall(r'"([^"]*)"', match.group(1)))
            self.assertEqual(ACTION_NAMES[task], names, source)


if __name__ == "__main__":
    unittest.main()
