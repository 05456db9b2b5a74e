"""Lagoudakis & Parr's chain walk as sims/chain computes it (JMLR 4, 2003, sec.
9.1): states 0 .. n-1, action 0 left and 1 right, a move goes the intended way with
probability `success` and the other way otherwise, a move past an end stays there,
reward 1 for entering a rewarded state; no terminal state, a series truncated at
max_episode_steps. The observation is the state id as one float.

The one difference from the C++ chain: whether a move slips comes from this
object's own generator (seeded by reset), not from ggk's stream, as for any
stochastic Python environment. So every transition it makes is one the C++ chain
makes (Chain::move of the same state and action, Chain::reward of the state
entered), the slips have the C++ chain's rate, and with success = 1 the two are
the same function; tests/engine/tasks/python_env_test.cpp checks all three."""

import random

from . import Box, Discrete


class ChainTwin:
    def __init__(self, states=20, success=0.9, rewarded=(0, 19), max_episode_steps=50):
        self.n = states
        self.success = success
        self.rewarded = set(rewarded)
        self.max_episode_steps = max_episode_steps
        self.action_space = Discrete(2)
        self.observation_space = Box([0.0], [float(states - 1)])
        self.rng = random.Random(0)
        self.state = 0
        self.steps = 0

    def reset(self, seed=None, options=None):
        self.rng = random.Random(seed)
        self.state = self.rng.randrange(self.n)  # a uniform start, as the C++ chain's walks
        self.steps = 0
        return [float(self.state)], {}

    def step(self, action):
        intended = self.rng.random() < self.success
        direction = 1 if (action == 1) == intended else -1
        self.state = min(max(self.state + direction, 0), self.n - 1)
        self.steps += 1
        reward = 1.0 if self.state in self.rewarded else 0.0
        truncated = self.steps >= self.max_episode_steps
        return [float(self.state)], reward, False, truncated, {}
