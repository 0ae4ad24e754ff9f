"""A way into a contact beyond the three rules, planned and carried out in DART: from the side along a handle's bar.

The stdlib Hook catches the Drawer's handle bar at its overhang (`Drawer.pull_px_left`), its 16 cm
cross-piece behind the bar and its shaft 12 cm aside, beyond the drawer's side. Here a ledge (a 10 x 3.9 x
1 cm board on a stiff slide, so it stays where it is) reaches over where the shaft lies at the contact, 7 mm
above it: the hook cannot come down there (from above, and 30 deg below the push, are blocked by the ledge),
nor back along its pull (the cross-piece would go into the drawer's front), nor through the cone about the
pull. It slides in from the side, along the bar, at the contact's height: the ledge stops 3 mm short of
where the shaft is 3 cm aside. Execution follows the plan's approach segment and leaves the contact at the
end as the planner checked it: back out the way it came, then up.

A hook pull of a 24 cm wide crate is not an approach problem: with its tip at the middle of the far face,
the hook's shaft (12 cm aside) lies 1 cm inside the crate at the contact itself, so the planner says so at
once instead of trying ways in.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from task_makers import generated_tasks

import vkgl
from vkgl.execute.steps import StepKinds

SOURCE = """
use stdlib.robots.panda
use stdlib.bodies.drawer
use stdlib.bodies.hook
use stdlib.furniture.drawer_cabinet
use stdlib.affordances.drawer
use stdlib.affordances.hook
use stdlib.tools

body Ledge {{
    shape box (10, {width}, 1) cm
    mass 1 kg
    friction 0.5
    joint prismatic axis (1, 0, 0) limits (0, 1) cm damping 1000 N*s/m friction 100 N
}}

scene kitchen_ledge {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    cabinet : DrawerCabinet on table at (1.1, 0.15) m yaw 180deg
    drawer : Drawer at (1.1, 0.15, 0.073) m yaw 180deg
    hook : Hook on table at (0.3, 0.4) m yaw 0deg
    ledge : Ledge at (0.85, {y}, 0.095) m yaw 0deg
}}

task hook_drawer_ledge {{
    scene kitchen_ledge
    goal drawer open 15 cm within 1 cm
    search {{ max_depth 3  timeout 60 s }}
}}
"""

LEDGE = {"width": 3.9, "y": -0.0725}
"""Over the shaft at the contact (y -0.065 to -0.085 m), clear of it 3 cm aside (from -0.095 m)."""

WIDE_LEDGE = {"width": 8.0, "y": -0.093}
"""Over the shaft at the contact and 3 cm aside as well: no way in is clear."""


def ledge_task(tmp_path: Path, ledge: dict[str, float]) -> Path:
    path = tmp_path / "ledge.vkg"
    path.write_text(SOURCE.format(**ledge), encoding="utf-8")
    return path


def test_the_hook_comes_in_from_the_side_of_the_bar_and_opens_the_drawer_in_physics(tmp_path, monkeypatch):
    program = vkgl.compile(ledge_task(tmp_path, LEDGE))
    plan = vkgl.solve(program, "hook_drawer_ledge")
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Hook.wield", "Drawer.pull_px_left"]
    pull = plan.steps[1]
    approach = pull.path[-1]
    assert approach.phase == "approach"
    fk = plan.problem.arm.fk
    way = fk(approach.joints[-1])[:3, 3] - fk(approach.joints[-2])[:3, 3]
    way /= np.linalg.norm(way)
    # level, across the pull (world -x): along the bar, from beyond the shaft's side
    assert abs(way[2]) < 0.05 and abs(way[0]) < 0.05 and way[1] > 0.99

    leaving: list[tuple[str, np.ndarray | None]] = []
    let_go = StepKinds.let_go

    def spy(self: StepKinds, label: str = "end") -> None:
        if self.push_direction is not None:
            leaving.append(self.leaving)
        let_go(self, label)

    monkeypatch.setattr(StepKinds, "let_go", spy)
    report = vkgl.execute(program, "hook_drawer_ledge", plan)
    assert report.status == "reached", report.to_dict()
    # the contact was left back out along the bar (the way it came, -y), as the planner checked
    assert leaving and leaving[0][0] == "reverse"
    assert leaving[0][1] is not None and leaving[0][1][1] > 0.99
    start = plan.steps[0].poses_start["ledge"]
    assert np.linalg.norm(report.final["ledge"][:3, 3] - start[:3, 3]) < 0.002  # the hook never pushed the ledge


def test_the_reason_says_which_ways_in_were_tried(tmp_path):
    program = vkgl.compile(ledge_task(tmp_path, WIDE_LEDGE))
    plan = vkgl.solve(program, "hook_drawer_ledge")
    assert plan.status != "solved"
    assert (
        "Drawer.pull_px_left on drawer with hook.tip: slide 15.0 cm): no straight approach into the contact "
        "(tried 31 approaches: along the push, from above, 30 deg below the push, 16 in a 40 deg cone about the "
        "push, 6 from the side along the bar (level, higher and lower), 4 with a shorter stand-off (1.5 cm), "
        "2 with a longer stand-off (6 cm); closest: " in plan.reason
    )
    assert "would overlap ledge by" in plan.reason


def _wide_pull(tmp_path, body: str):
    """`body` pulled by the middle of its far face from 1.0 m to 0.82 m, solved at depth 3 at most."""
    target = generated_tasks.Placement("target", body, 1.0, 0.0, 0.0)
    tools = tuple(generated_tasks.Placement(n, t.name, x, y, a) for n, t, x, y, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("wide", 0, 0, (target, *tools), (0.82, 0.0, 0.0), "far-pull", False, 0.18)
    task = generated_tasks.write_task(spec, tmp_path / body, generated_tasks.fixture_library())
    return vkgl.solve(vkgl.compile(task), "wide", max_depth=3)


def test_a_hook_pull_of_a_wide_crate_rolls_the_hook_over_its_top(tmp_path):
    """A 30 cm wide crate: the shaft is 4 cm inside it at the centre, and no contact along the face leaves the
    cross-piece over its centre line with the shaft clear (`tool_faces`); the hook rolled 35 deg about the pull and
    lifted 4.5 cm passes its shaft over the crate's top (`vkgl.plan.problem.over`)."""
    plan = _wide_pull(tmp_path, "CrateM")
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Hook.wield", "CrateM.push_center_nx/over+35deg+4.50cm"]


def test_a_24_cm_crate_is_pulled_straight_from_off_its_centre(tmp_path):
    """A 24 cm wide crate: at the centre the shaft is 1 cm inside it; 2 cm toward the shaft's side it is clear."""
    plan = _wide_pull(tmp_path, "CrateT")
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Hook.wield", "CrateT.push_center_nx@+2.00cm/straight"]
