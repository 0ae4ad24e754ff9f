"""Where a running execution is, for a live display: the plan, the step, its phase and the simulated time.

    execute(program, task, plan, on_progress=lambda p: print(p.text()))

`execute(..., on_progress=f)` calls `f(Progress(...))` while the world runs:
when a step begins, whenever the arm's phase changes (the world's label, as
the animation shows it: `step 2 transit`, `step 2 approach`, `step 2
motion`, `step 2 retreat`, ...) and at least every `PERIOD` of simulated time
in between; and once with the phase "re-solving" before each re-solve. The
callback runs in the simulation's thread: it must be quick.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

PERIOD = 0.1
"""s of simulated time between two reports of the same phase."""


@dataclass(frozen=True)
class Progress:
    """Where the execution is: `plan` (0 = the plan given, 1.. = re-solves), `step` of `steps` (0: between steps),
    the step's `title` (between steps: what the arm does, e.g. "putting things down to re-solve"), the arm's
    `phase` ("transit", "approach", "motion", "retreat", "settle", "release", "re-solving", ...) and the
    simulated time (s)."""

    plan: int
    step: int
    steps: int
    title: str
    phase: str
    sim_time: float

    def text(self) -> str:
        """`step 2/3 [replan 1] add Block.push_center_px on block with arm.fingertip: motion, t = 8.3 s`."""
        origin = "" if self.plan == 0 else f" [replan {self.plan}]"
        where = f"step {self.step}/{self.steps}{origin} {self.title}" if self.step else f"{self.title}{origin}"
        return f"{where}: {self.phase or 'starting'}, t = {self.sim_time:.1f} s"


class ProgressFeed:
    """Turns the world's ticks (`SceneWorld.on_advance`) into `Progress` reports for one callback."""

    def __init__(
        self, callback: Callable[[Progress], None] | None, label: Callable[[], str], time: Callable[[], float]
    ) -> None:
        """`label()` and `time()` read the world's label (`step 2 motion`) and simulated time."""
        self.callback = callback
        self._label, self._time = label, time
        self.plan, self.step, self.steps, self.title = 0, 0, 0, ""
        self._last: tuple[str, float] | None = None

    def begin(self, plan: int, step: int, steps: int, title: str) -> None:
        """A step (or, with step 0, the work between steps) begins: report it at once."""
        self.plan, self.step, self.steps, self.title = plan, step, steps, title
        self._last = None
        self.tick()

    def phase(self, phase: str) -> None:
        """Report a phase that is not the world's (e.g. "re-solving", while the planner runs)."""
        self._emit(phase)

    def tick(self) -> None:
        """The world advanced: report when the phase changed or `PERIOD` went by since the last report."""
        if self.callback is None:
            return
        label = self._label()
        prefix = f"step {self.step} "
        if self.step:  # "" until the step moves the arm: the label is still the one before ("start", "step 1 settle")
            phase = label[len(prefix) :] if label.startswith(prefix) else ""
        else:
            phase = label.rpartition(" ")[2]  # "replan retreat", "end settle"
        last = self._last
        if last is not None and last[0] == phase and self._time() - last[1] < PERIOD:
            return
        self._emit(phase)

    def _emit(self, phase: str) -> None:
        if self.callback is None:
            return
        now = self._time()
        self._last = (phase, now)
        self.callback(Progress(self.plan, self.step, self.steps, self.title, phase, now))


__all__ = ["PERIOD", "Progress", "ProgressFeed"]
