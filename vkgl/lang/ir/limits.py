"""The plausible ranges of physical values and counts (E209, E210): one table, stated in docs/language.md.

A value outside its range is almost surely a wrong unit or a typo (`mass 500 kg`
for a block, `duration 1e308 s`), and far-out values break the simulator and
the planner in ways that are hard to trace. Ranges are inclusive, in SI units.
Values at or below zero keep their own codes (E401, E402, E403, E411); these
limits catch what is positive but absurd.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Limit:
    """An inclusive range of SI values; `shown` says it in words for messages ("from 1 g to 10000 kg")."""

    low: float
    high: float
    shown: str

    def holds(self, value: float) -> bool:
        """True inside the range (NaN, the mark of a value already reported, counts as inside)."""
        return not (value < self.low or value > self.high)


MASS = Limit(1e-3, 1e4, "from 1 g to 10000 kg")
SIZE = Limit(1e-3, 10.0, "from 1 mm to 10 m")
MESH_SCALE = Limit(1e-4, 1e4, "from 0.0001 to 10000")
FRICTION = Limit(0.0, 10.0, "from 0 to 10")
FORCE = Limit(1e-3, 1e3, "from 0.001 N to 1000 N")
DURATION = Limit(1e-3, 600.0, "from 1 ms to 600 s")
TIMEOUT = Limit(1e-3, 3600.0, "from 1 ms to 3600 s")  # the CLI's --timeout range (vkgl/cli/arguments.py)

MAX_DEPTH_LIMIT = 12
"""Graphs in a sequence at most, as the CLI's `--max-depth` (vkgl/cli/arguments.py MAX_DEPTH_LIMIT)."""

STEPS = Limit(1, 100, "from 1 to 100")
GRID = Limit(1, 15, "from 1 to 15")
MAX_DEPTH = Limit(1, MAX_DEPTH_LIMIT, f"from 1 to {MAX_DEPTH_LIMIT}")
TRIALS = Limit(0, 1_000_000, "from 0 to 1000000")
GRASP_TRIALS = Limit(1, 20, "from 1 to 20")

COUNTS = {"`steps`": STEPS, "a grid size": GRID, "`max_depth`": MAX_DEPTH, "`trials`": TRIALS}
"""The limit of each count, by the name the builder gives it in messages."""

MAX_COUNT_DIGITS = 15
"""A count written with more digits is reported without being converted (Python refuses > 4300 digits)."""

# A physical joint's dynamics (`damping`, `friction`): 0 means none. The highs are far above any drawer
# slide or door hinge (tens of N*s/m, a few N*m*s/rad) yet keep DART's implicit damping and friction sane.
LINEAR_DAMPING = Limit(0.0, 1e4, "from 0 to 10000 N*s/m")
ANGULAR_DAMPING = Limit(0.0, 1e3, "from 0 to 1000 N*m*s/rad")
JOINT_FORCE = Limit(0.0, 1e3, "from 0 to 1000 N")
JOINT_TORQUE = Limit(0.0, 1e3, "from 0 to 1000 N*m")
