"""Benchmark: what one DART step of plan execution costs, at DART's solver tolerance and at a looser one.

    python bench/sim/bench_step.py [TASK ...]      (default: the example tasks a, c, d, g, h)

Solves each example task (examples/tasks/TASK.vkg) and carries its plan out twice, open loop: once with the
friction-cone solver stopping its sweeps at DART's residual (1e-5, what every world uses) and once at `LOOSER`
(tried for `vkgl.sim.world.EXECUTION_SOLVER_TOLERANCE`, not taken: docs/execution.md). Prints one Markdown table:
the physics steps, the CPU seconds of the whole execution (`time.process_time`: IK, the grip's watch and the rest
included), the CPU per step all in, and how far every body ends from where it ends at DART's tolerance (the largest
over the scene's bodies, position and heading), with the goals' errors at both (docs/execution.md, "The contact
solver's tolerance").
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
TASKS = ("a_push", "c_hook_pull", "d_rotate_push", "g_open_drawer", "h_close_door")
DART_TOLERANCE = 1e-5  # DART's default: every world's
LOOSER = 1e-4  # the stop tried for execution


def _yaw(pose: np.ndarray) -> float:
    return math.atan2(pose[1, 0], pose[0, 0])


def execute_at(program, task: str, plan, tolerance: float) -> tuple[object, float, int]:
    """The execution report of `plan` carried out with the solver stopping at `tolerance`, its CPU seconds, and the
    number of physics steps it took."""
    import vkgl
    from vkgl.execute import scene_world
    from vkgl.sim import world as sim_world

    steps = [0]
    advance = scene_world.SceneWorld.advance

    def counted(self, n: int) -> None:
        steps[0] += n
        advance(self, n)

    saved = sim_world.EXECUTION_SOLVER_TOLERANCE
    sim_world.EXECUTION_SOLVER_TOLERANCE = tolerance  # read by SceneWorld when it builds its world
    scene_world.SceneWorld.advance = counted  # type: ignore[method-assign]
    try:
        started = time.process_time()
        report = vkgl.execute(program, task, plan)
        return report, time.process_time() - started, steps[0]
    finally:
        sim_world.EXECUTION_SOLVER_TOLERANCE = saved
        scene_world.SceneWorld.advance = advance  # type: ignore[method-assign]


def _goal_errors(report) -> str:
    return ", ".join(f"{g.position_error * 1000:.2f}" for g in report.goals if g.position_error is not None) or "-"


def main(tasks: list[str]) -> None:
    import vkgl

    print(
        f"| task | steps | CPU s at {DART_TOLERANCE:g} | at {LOOSER:g} | ms per step "
        "| bodies moved by (largest) | goal errors, mm (before; after) | status |"
    )
    print("|---|---:|---:|---:|---|---|---|---|")
    for task in tasks:
        program = vkgl.compile(str(REPO / "examples" / "tasks" / f"{task}.vkg"))
        plan = vkgl.solve(program, task)
        before, cpu_before, steps = execute_at(program, task, plan, DART_TOLERANCE)
        after, cpu_after, steps_after = execute_at(program, task, plan, LOOSER)
        moved = max(np.linalg.norm(after.final[b][:3, 3] - before.final[b][:3, 3]) for b in before.final)
        turned = max(
            abs((math.degrees(_yaw(after.final[b]) - _yaw(before.final[b])) + 180) % 360 - 180) for b in before.final
        )
        print(
            f"| {task} | {steps} ({steps_after}) | {cpu_before:.2f} | {cpu_after:.2f} "
            f"| {1000 * cpu_before / steps:.3f} -> {1000 * cpu_after / steps_after:.3f} "
            f"| {moved * 1000:.3f} mm, {turned:.4f} deg | {_goal_errors(before)}; {_goal_errors(after)} "
            f"| {before.status}, {after.status} |",
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:] or list(TASKS))
