"""One body alone on the tabletop at (0.45, 0) m and goals around it: the task text and the solves, shared by the
benches that measure how goals that turn a body are reached (bench/physical/bench_heading.py,
bench/physical/bench_arc_offsets.py).

Every body is the stdlib Block and each generated type (generated_tasks.GENERATED_TYPES, their learned fixtures in
tests/bench/learned/).
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import vkgl
from task_makers import generated_tasks

START = (0.45, 0.0)
"""Where the body rests, in m, heading 0."""


def lone_task_text(body: str, affordances: str, task: str, dx: float, dy: float, dyaw: float) -> str:
    """A one-body task named `task`: `body` at `START`, its goal moved by (`dx`, `dy`) m and turned by `dyaw` deg."""
    return (
        "use stdlib.robots.panda\n"
        f"{affordances}\n"
        "scene alone {\n"
        "    table size (1.6, 1.2) m at (0.5, 0, 0) m\n"
        "    robot arm : Panda at (0, 0, 0) m\n"
        f"    it : {body} on table at ({START[0]}, {START[1]:g}) m yaw 0deg\n"
        "}\n\n"
        f"task {task} {{\n"
        "    scene alone\n"
        f"    goal it at ({START[0] + dx:.3f}, {START[1] + dy:.3f}) m yaw {dyaw:g}deg within 1 cm, 3deg\n"
        "    search { max_depth 6  timeout 20 s }\n"
        "}\n"
    )


@dataclass(frozen=True)
class LoneSolve:
    """One goal of one body, solved: the program, its plan and the solve's CPU seconds."""

    body: str
    program: vkgl.Program
    plan: vkgl.Plan
    cpu_s: float


def each_body_solved(task: str, goals: Sequence[tuple[float, float, float]]) -> Iterator[tuple[str, list[LoneSolve]]]:
    """(body name, its goals (dx, dy, dyaw) solved in turn) for every body; no solves for a body whose learning
    found no affordance. The bodies' folders last until the iteration ends."""
    names = ["Block", *(t.name for t in generated_tasks.GENERATED_TYPES)]
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            folder = Path(tmp) / name
            folder.mkdir()
            uses = generated_tasks.body_uses(name, folder)
            yield name, [] if uses is None else [_solve(name, uses, task, goal, folder) for goal in goals]


def _solve(name: str, uses: str, task: str, goal: tuple[float, float, float], folder: Path) -> LoneSolve:
    path = folder / "task.vkg"
    path.write_text(lone_task_text(name, uses, task, *goal), encoding="utf-8")
    program = vkgl.compile(path)
    start = time.process_time()
    plan = vkgl.solve(program, task)
    return LoneSolve(name, program, plan, time.process_time() - start)
