"""Environments that break the Gymnasium API, one way each, for the tests of
python_env's refusals and failures."""

import math

from . import Box, Discrete
from .mountain_car import MountainCarTwin


class NoStep:
    action_space = Discrete(2)

    def reset(self, seed=None, options=None):
        return [0.0], {}


class BoxActions(MountainCarTwin):
    def __init__(self):
        super().__init__()
        self.action_space = Box([-1.0], [1.0])


class ImageObservation(MountainCarTwin):
    class Image:
        shape = (2, 2)

        def __iter__(self):
            return iter([[0.0, 0.0], [0.0, 0.0]])

    def reset(self, seed=None, options=None):
        return ImageObservation.Image(), {}


class NanAfter(MountainCarTwin):
    """A NaN observation at the given step of every episode."""

    def __init__(self, step=3):
        super().__init__()
        self.bad_step = step

    def step(self, action):
        observation, reward, terminated, truncated, info = super().step(action)
        if self.steps == self.bad_step:
            observation[1] = math.nan
        return observation, reward, terminated, truncated, info


class RaisesAfter(MountainCarTwin):
    """step raises at the given step of every episode of the objects made after
    the first `spared` of this process: with spared = 2 and one run in one
    process, the job reader's object and the walks' are spared and every fit's
    test raises (python_env makes an object for each)."""

    made = 0

    def __init__(self, step=3, spared=0):
        super().__init__()
        self.bad_step = step
        self.raises = RaisesAfter.made >= spared
        RaisesAfter.made += 1

    def step(self, action):
        result = super().step(action)
        if self.raises and self.steps == self.bad_step:
            raise RuntimeError(f"broken on purpose at step {self.steps}")
        return result


def raising_factory():
    raise ValueError("this factory always fails")
