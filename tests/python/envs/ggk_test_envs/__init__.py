"""Environments with the Gymnasium API for ggk's python_env task, written for the
tests (Gymnasium is not packaged in Debian 12): twins of three C++ tasks that
compute the same dynamics operation for operation (so the same bits), and
environments that break the API on purpose.

Spaces are the minimum the API asks for: Discrete(n) has n (and start 0), Box has
low, high and shape. Randomness comes from reset's seed alone (random.Random)."""


class Discrete:
    def __init__(self, n):
        self.n = n
        self.start = 0


class Box:
    def __init__(self, low, high):
        self.low = list(low)
        self.high = list(high)
        self.shape = (len(self.low),)
