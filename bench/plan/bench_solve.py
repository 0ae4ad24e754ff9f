"""Benchmark: `vkgc solve` on the paper's six tasks, beside the paper's Table 1, and scaling with extra tools.

    python bench/plan/bench_solve.py [--repeat N]

Prints two Markdown tables:

1. per task: the paper's depth and time, our depth, the solve time measured
   in-process (search + task-space checks + IK; compiling the task file is
   reported apart), graphs expanded, task-space checks, NLopt task-space runs,
   joint-space checks and IK calls. "first" is the first solve in a fresh
   process (it also loads the arm from its URDF and computes its reach at the
   heights the plan needs, both cached for the process afterwards); "warm" is
   the median of `--repeat` later solves.
2. scaling: the time of tasks b and e when 1, 2, 4 and 8 extra tools (sticks
   and hooks) lie on the table (each one a new effector for the search).

Targets (issue 5): each task < 0.5 s, the six together < 2 s. Issue 12 (collision checks on): 8 extra
bodies cost less than 3x the bare scene, and the exhaustive search of the unreachable goal among 11 bodies
answers in under 2 s. The first solves in fresh processes, as `vkgc solve` meets them:
bench/plan/bench_first_solve.py.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TASKS = ["a_push", "b_stick_push", "c_hook_pull", "d_rotate_push", "e_rotate_stick_push", "f_rotate_hook_pull"]
PAPER = {
    "a_push": (2, 1.328),
    "b_stick_push": (3, 1.250),
    "c_hook_pull": (3, 0.854),
    "d_rotate_push": (4, 1.623),
    "e_rotate_stick_push": (5, 7.106),
    "f_rotate_hook_pull": (5, 3.066),
}
EXTRA_SPOTS = [  # clear of the scene's bodies, of each other, of the robot's base and of the table's edges
    (0.10, 0.57, "Stick"),
    (0.10, -0.57, "Hook"),
    (0.60, 0.57, "Stick"),
    (0.60, -0.57, "Hook"),
    (0.00, 0.30, "Stick"),
    (0.00, -0.30, "Hook"),
    (1.05, 0.45, "Stick"),
    (1.05, -0.45, "Hook"),
]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="warm solves per task (median reported)")
    args = parser.parse_args()
    sys.path.insert(0, str(REPO))
    import vkgl.plan.solve  # noqa: F401 - Python's imports (trimesh, DART, NLopt: ~0.7 s) are not the first solve's
    from vkgl.api import solve
    from vkgl.lang.compiler import compile_file

    programs, compile_times = {}, {}
    for name in TASKS:
        started = time.perf_counter()
        programs[name] = compile_file(str(REPO / "examples" / "tasks" / f"{name}.vkg"))
        compile_times[name] = time.perf_counter() - started
    print("## The paper's six tasks\n")
    print(
        "| task | paper depth | paper time (s) | depth | first (s) | warm (s) | compile (s) | graphs expanded "
        "| task-space checks | NLopt runs | joint-space checks | IK calls | effectors |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    total_first = total_warm = 0.0
    for name in TASKS:
        started = time.perf_counter()
        plan = solve(programs[name])
        first = time.perf_counter() - started
        warm = statistics.median(_timed(solve, programs[name]) for _ in range(args.repeat))
        total_first += first
        total_warm += warm
        effectors = sorted({s.effector for s in plan.steps if s.op == "add"})
        stats, details = plan.stats, plan.details
        print(
            f"| {name} | {PAPER[name][0]} | {PAPER[name][1]:.3f} | {plan.depth} | {first:.3f} | {warm:.3f} | "
            f"{compile_times[name]:.3f} | {stats['graphs_expanded']} | {stats['task_space_checks']} | "
            f"{details['optimisations']} | {stats['joint_space_checks']} | {details['ik_calls']} | "
            f"{', '.join(effectors)} |"
        )
    print(
        f"| total | | {sum(t for _, t in PAPER.values()):.3f} | | {total_first:.3f} | {total_warm:.3f} | | | | | | | |"
    )
    print("\n## Time against extra tools on the table (warm, median)\n")
    print("| task | extra tools | bodies | depth | time (s) | CPU (s) | graphs expanded | task-space checks |")
    print("|---|---|---|---|---|---|---|---|")
    cases = {
        "b_stick_push": programs["b_stick_push"],
        "e_rotate_stick_push": programs["e_rotate_stick_push"],
        "unreachable goal (exhaustive)": _with_far_goal(programs["b_stick_push"]),
    }
    for name, base in cases.items():
        for extra in (0, 1, 2, 4, 8):
            program = (_with_extra_tools(base, extra), base.task().name)
            solve(*program)
            plan = solve(*program)
            cpu_times = [_cpu_timed(solve, program) for _ in range(max(1, args.repeat // 2))]
            n_bodies = len(program[0].scenes[base.task().scene.name].bodies)
            wall = statistics.median(t for t, _ in cpu_times)
            cpu = statistics.median(c for _, c in cpu_times)
            print(
                f"| {name} | {extra} | {n_bodies} | {plan.depth or plan.status} | {wall:.3f} | {cpu:.3f} | "
                f"{plan.stats['graphs_expanded']} | {plan.stats['task_space_checks']} |"
            )
    return 0


def _timed(solve, program) -> float:  # type: ignore[no-untyped-def]
    started = time.perf_counter()
    solve(*program) if isinstance(program, tuple) else solve(program)
    return time.perf_counter() - started


def _cpu_timed(solve, program) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """(wall, CPU) seconds of one solve: on a shared machine the CPU time is the steadier one."""
    wall, cpu = time.perf_counter(), time.process_time()
    solve(*program)
    return time.perf_counter() - wall, time.process_time() - cpu


def _with_far_goal(program):  # type: ignore[no-untyped-def]
    """Task b with its goal beyond the stick's reach: the search must try every sequence up to max_depth."""
    import dataclasses

    from vkgl.lang.ir.nodes import Vector

    task = program.task()
    goal = task.goals[0].model_copy(update={"position": Vector(values=(1.25, 0.0), unit="m")})
    far = task.model_copy(update={"goals": [goal]})
    return dataclasses.replace(program, tasks={**program.tasks, task.name: far})


def _with_extra_tools(program, count: int):  # type: ignore[no-untyped-def]
    """A copy of `program` whose task scene has `count` more tools lying on the table."""
    import dataclasses

    from vkgl.lang.ir.nodes import Placement, Pose, Quantity, Ref, SceneBody, Vector

    scene = program.scenes[program.task().scene.name]
    extra = [
        SceneBody(
            name=f"{kind.lower()}{i}",
            type=Ref(name=kind),
            placement=Placement(
                on_table=True, pose=Pose(position=Vector(values=(x, y), unit="m"), yaw=Quantity(value=0.0, unit="deg"))
            ),
        )
        for i, (x, y, kind) in enumerate(EXTRA_SPOTS[:count])
    ]
    grown = scene.model_copy(update={"bodies": [*scene.bodies, *extra]})
    return dataclasses.replace(program, scenes={**program.scenes, scene.name: grown})


if __name__ == "__main__":
    sys.exit(main())
