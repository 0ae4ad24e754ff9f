"""What `vkgc solve --execute` shows on stderr while the plan runs in DART (stdout keeps the report).

Piped or on a terminal, one plain line per step as it ends and one per re-solve:

    executing: step 1 done at t = 6.84 s: add Block.push_center_px on block with arm.fingertip: slide 15.0 cm
    executing: re-solve 1: step 1 (...): the arm cannot reach ...; re-solve 1 excludes the failed step 1 of ...

On a terminal, under those lines, a live bar (`rich.progress`): the step being
carried out, the arm's phase (transit, approach, motion, retreat, ...), the
simulated time, the steps of the plan done, the wall time and the step's
title (cut to the terminal's width). The bar is cleared when the execution
ends; nothing of it reaches a pipe or a log file, nor stdout.
"""

from __future__ import annotations

from types import TracebackType
from typing import TYPE_CHECKING, Any, TextIO

if TYPE_CHECKING:
    from vkgl.execute.progress import Progress
    from vkgl.formats.execution_report import Resolve, StepReport

OTHER_COLUMNS = 60
"""Characters the bar's columns before the step's title take (the title gets the rest of the line)."""


class ExecutionProgress:
    """Progress of one execution on `stream`: lines always, and with `live` a bar under them.

    A context manager: the bar runs between `__enter__` and `__exit__`. Pass
    `step_done`, `resolved` and `progress` to `vkgl.execute` as `on_step`,
    `on_resolve` and `on_progress`.
    """

    def __init__(self, stream: TextIO, *, live: bool) -> None:
        """`live`: draw the bar (for a terminal); otherwise only the lines."""
        self.stream = stream
        self.live = live
        self._bar: Any = None
        self._task: Any = None
        self._plan = -1

    def __enter__(self) -> ExecutionProgress:
        if self.live:
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, SpinnerColumn, TextColumn, TimeElapsedColumn
            from rich.progress import Progress as Bar
            from rich.table import Column

            console = Console(file=self.stream, force_terminal=True)
            title = Column(no_wrap=True, overflow="ellipsis", max_width=max(10, console.width - OTHER_COLUMNS))
            self._bar = Bar(
                SpinnerColumn(),
                TextColumn("{task.fields[where]}", table_column=Column(no_wrap=True)),
                TextColumn("[bold]{task.fields[phase]}", table_column=Column(no_wrap=True, min_width=8)),
                TextColumn("t = {task.fields[sim]:.1f} s", table_column=Column(no_wrap=True, min_width=10)),
                BarColumn(bar_width=10),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                TextColumn("{task.description}", table_column=title),
                console=console,
                transient=True,
                redirect_stdout=False,
                redirect_stderr=False,
            )
            self._task = self._bar.add_task("", total=None, where="executing", phase="", sim=0.0)
            self._bar.start()
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None

    # ------------------------------------------------------------ what the execution tells

    def step_done(self, step: StepReport) -> None:
        """A step ended: its line (and the bar counts it)."""
        origin = "" if step.plan == 0 else f" [replan {step.plan}]"
        self._line(f"executing: step {step.index}{origin} done at t = {step.end_time:.2f} s: {step.title}")
        if self._bar is not None:
            self._bar.update(self._task, completed=step.index, sim=step.end_time)

    def resolved(self, record: Resolve) -> None:
        """The loop re-solved: what triggered it, what it excluded, what it found."""
        self._line(f"executing: re-solve {record.number}: {record.text()}")

    def progress(self, where: Progress) -> None:
        """Where the execution is now: the bar follows (nothing without a bar)."""
        if self._bar is None:
            return
        origin = "" if where.plan == 0 else f" [replan {where.plan}]"
        text = f"step {where.step}/{where.steps}{origin}" if where.step else f"between steps{origin}"
        update: dict[str, Any] = {"where": text, "description": where.title, "phase": where.phase}
        update["sim"] = where.sim_time
        if where.plan != self._plan:  # a new plan: count its steps
            self._plan = where.plan
            update.update(total=where.steps, completed=max(where.step - 1, 0))
        self._bar.update(self._task, **update)

    def _line(self, text: str) -> None:
        if self._bar is not None:
            self._bar.console.print(text, markup=False, highlight=False, soft_wrap=True)
        else:
            print(text, file=self.stream, flush=True)


__all__ = ["ExecutionProgress"]
