"""The mountain car of Gymnasium's MountainCar-v0, operation for operation in its
order (so the bits of ggk's sims/mountain_car): tests/engine/tasks replays this
twin's samples through the C++ simulator."""

import math
import random

from . import Box, Discrete


class MountainCarTwin:
    def __init__(self, max_episode_steps=200):
        self.force = 0.001
        self.gravity = 0.0025
        self.max_speed = 0.07
        self.min_position = -1.2
        self.max_position = 0.6
        self.goal_position = 0.5
        self.goal_velocity = 0.0
        self.max_episode_steps = max_episode_steps
        self.action_space = Discrete(3)
        self.observation_space = Box([self.min_position, -self.max_speed],
                                     [self.max_position, self.max_speed])
        self.state = (0.0, 0.0)
        self.steps = 0

    def reset(self, seed=None, options=None):
        rng = random.Random(seed)
        self.state = (rng.uniform(-0.6, -0.4), 0.0)  # Gymnasium's reset distribution
        self.steps = 0
        return list(self.state), {}

    def step(self, action):
        position, velocity = self.state
        velocity += (action - 1) * self.force + math.cos(3 * position) * (-self.gravity)
        velocity = min(max(velocity, -self.max_speed), self.max_speed)
        position += velocity
        position = min(max(position, self.min_position), self.max_position)
        if position == self.min_position and velocity < 0:
            velocity = 0.0
        terminated = bool(position >= self.goal_position and velocity >= self.goal_velocity)
        self.state = (position, velocity)
        self.steps += 1
        truncated = self.steps >= self.max_episode_steps and not terminated
        return [position, velocity], -1.0, terminated, truncated, {}
