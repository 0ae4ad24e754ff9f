"""`vkgc solve --execute` on stderr: a plain line per step (and per re-solve) piped, and a live bar on a terminal.

Both ways: `ExecutionProgress` on a string stream as a pipe (`live=False`)
and as a forced terminal (`live=True`); then the command itself, its stderr
a terminal, carrying out task (a) in DART (`a_push_executed` in tests/conftest.py: run once, read here
and by tests/test_docs_samples.py; piped, `tests/cli/test_execute_cli.py`).
"""

from __future__ import annotations

import io
import re

from vkgl.cli.progress import ExecutionProgress
from vkgl.execute.progress import Progress
from vkgl.formats.execution_report import ExcludedStep, Resolve, StepReport

ESCAPE = re.compile(r"\x1b\[")
TITLE = "add Block.push_center_px on block with arm.fingertip: slide 15.0 cm"


def _run(shown: ExecutionProgress) -> None:
    """What an execution of two steps with one re-solve tells its progress display."""
    shown.progress(Progress(0, 1, 1, TITLE, "transit", 0.4))
    shown.progress(Progress(0, 1, 1, TITLE, "motion", 3.2))
    shown.step_done(StepReport(0, 1, TITLE, 6.84))
    failed = ExcludedStep(0, 1, TITLE, "the arm cannot reach the effector pose")
    shown.resolved(Resolve(1, f"step 1 ({TITLE}): no", (failed,), 1, "solved", "", (TITLE,), "new plan", 0.1))
    shown.progress(Progress(1, 1, 1, TITLE, "approach", 8.0))
    shown.step_done(StepReport(1, 1, TITLE, 12.5))


def test_piped_one_plain_line_per_step_and_per_re_solve():
    stream = io.StringIO()
    with ExecutionProgress(stream, live=False) as shown:
        _run(shown)
    lines = stream.getvalue().splitlines()
    assert lines == [
        f"executing: step 1 done at t = 6.84 s: {TITLE}",
        f"executing: re-solve 1: step 1 ({TITLE}): no; re-solve 1 excludes the failed step 1 of plan 0 `{TITLE}` and "
        f"the 1 plan tried; re-solved from the observed scene: new plan of 1 step: `{TITLE}`",
        f"executing: step 1 [replan 1] done at t = 12.50 s: {TITLE}",
    ]
    assert not ESCAPE.search(stream.getvalue())


def test_on_a_terminal_a_live_bar_under_the_same_lines():
    stream = io.StringIO()
    with ExecutionProgress(stream, live=True) as shown:
        shown.progress(Progress(0, 1, 1, TITLE, "motion", 3.2))
        shown._bar.refresh()  # draw now, not at the next tick of its thread
        drawn = stream.getvalue()
        _run(shown)
    text = stream.getvalue()
    assert ESCAPE.search(text)  # a terminal's control sequences: the bar is redrawn in place
    assert "step 1/1" in drawn and "motion" in drawn and "t = 3.2 s" in drawn
    for line in (f"executing: step 1 done at t = 6.84 s: {TITLE}", "executing: re-solve 1: step 1 ("):
        assert line in text


def test_solve_execute_on_a_terminal_shows_the_bar_and_keeps_stdout_plain(a_push_executed):
    code, out, err = a_push_executed  # `vkgc solve examples/tasks/a_push.vkg --execute`, stderr a terminal
    assert code == 0
    assert ESCAPE.search(err) and "executing: step 1 done at t = " in err
    assert "step 1/1" in err and "motion" in err  # the push lasts seconds: the bar draws it
    assert not ESCAPE.search(out) and "executing" not in out
    assert out.splitlines()[-1].startswith("reached:")
