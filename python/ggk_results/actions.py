"""The action codes of each task's files (policy, unit_policy, samples/actions,
the action rows of weights) and their names, as the simulators define them:
sims/maze/maze.hpp, sims/arm/arm.hpp, sims/khepera/motion.hpp
(tests/python/test_actions.py checks this table against those sources)."""

ACTION_NAMES = {
    "maze": ("up", "down", "left", "right"),
    "arm": ("shoulder+", "shoulder-", "elbow+", "elbow-"),
    "khepera": ("forward", "left", "right", "backward"),
}


def action_names(task, count=None):
    """The names of a task's actions 0, 1, ...; `count` actions named "0", "1",
    ... for a task this table does not know."""
    names = ACTION_NAMES.get(task)
    if names is None or (count is not None and count != len(names)):
        return tuple(str(a) for a in range(count or 0))
    return names
