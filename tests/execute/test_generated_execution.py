"""Generated tasks whose first plans failed in physics, carried out in DART (bench/bench_physical.py's tasks).

The generated bodies' affordances are the fixtures of tests/bench/learned (`tests/bench/test_generated_plans.py`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from generated_tasks import fixture_library, task_spec, write_task

import vkgl


def test_the_hand_does_not_sweep_a_bystander_while_it_pushes(tmp_path: Path) -> None:
    # gen1_028: a cube pushed out of the way lies 12 cm beside the target cube. The hand, leaned back 30 deg behind
    # the fingertip, cleared the target where the push started and ended but swept through it halfway, and shoved
    # it 15 cm: the planner now checks the arm along the whole contact, and the plan takes the stick instead
    spec = task_spec(1, 28)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name)
    assert plan.status == "solved", plan.reason
    report = vkgl.execute(program, spec.name, plan)
    assert report.status == "reached", report.reason
    for name in ("target", "clutter1", "clutter2"):  # every body where the plan leaves it
        off = np.linalg.norm(report.final[name][:2, 3] - plan.final[name][:2, 3])
        assert off < 0.01, f"{name} is {off * 100:.1f} cm from where the plan leaves it"
