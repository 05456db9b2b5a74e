"""Lagoudakis & Parr's inverted pendulum, operation for operation as ggk's
sims/pendulum (RK4, 10 substeps of dt / 10), without noise by default: the
twin of the C++ task with `noise = 0`."""

import math
import random

from . import Box, Discrete


class PendulumTwin:
    def __init__(self, noise=0.0, start_perturbation=0.1, max_episode_steps=None):
        self.m, self.big_m, self.l, self.g = 2.0, 8.0, 0.5, 9.8
        self.force, self.noise, self.dt, self.substeps = 50.0, noise, 0.1, 10
        self.start_perturbation = start_perturbation
        self.max_episode_steps = max_episode_steps
        self.steps = 0
        self.action_space = Discrete(3)
        self.observation_space = Box([-math.pi / 2, -10.0], [math.pi / 2, 10.0])
        self.rng = random.Random(0)
        self.state = (0.0, 0.0)

    def acceleration(self, angle, velocity, u):
        alpha = 1.0 / (self.m + self.big_m)
        m, l, c = self.m, self.l, math.cos(angle)
        return ((self.g * math.sin(angle) - alpha * m * l * velocity * velocity *
                 math.sin(2.0 * angle) / 2.0 - alpha * c * u) /
                (4.0 * l / 3.0 - alpha * m * l * c * c))

    def reset(self, seed=None, options=None):
        self.rng = random.Random(seed)
        p = self.start_perturbation
        self.state = (self.rng.uniform(-p, p), self.rng.uniform(-p, p))
        self.steps = 0
        return list(self.state), {}

    def step(self, action):
        u = (action - 1) * self.force
        if self.noise > 0:
            u += self.rng.uniform(-self.noise, self.noise)
        a, w = self.state
        h = self.dt / self.substeps
        for _ in range(self.substeps):
            k1a, k1w = w, self.acceleration(a, w, u)
            k2a, k2w = w + h / 2.0 * k1w, self.acceleration(a + h / 2.0 * k1a, w + h / 2.0 * k1w, u)
            k3a, k3w = w + h / 2.0 * k2w, self.acceleration(a + h / 2.0 * k2a, w + h / 2.0 * k2w, u)
            k4a, k4w = w + h * k3w, self.acceleration(a + h * k3a, w + h * k3w, u)
            a, w = (a + h / 6.0 * (k1a + 2.0 * k2a + 2.0 * k3a + k4a),
                    w + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w))
        self.state = (a, w)
        fell = abs(a) >= math.pi / 2.0
        self.steps += 1
        truncated = (self.max_episode_steps is not None and self.steps >= self.max_episode_steps
                     and not fell)
        return [a, w], (-1.0 if fell else 0.0), fell, truncated, {}
