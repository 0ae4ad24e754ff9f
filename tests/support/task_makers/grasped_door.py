"""The Door opened 60 deg by the learned grasp of its bar alone (the tests of grasped handles, in the planner and
in DART): examples/tasks/o_open_door.vkg's task with the Door's other affordances left out. Since the arm's other
configurations are tried at a contact, that example's plan is the fingertip hooked behind the bar instead."""

from __future__ import annotations

from pathlib import Path

import vkgl

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"

SOURCE = """use "{kitchen}"

affordances Door {{
    affordance grasp_side_px_z_p3 {{
        action grasp at (5.3, 14.1, 15) cm rpy (90, 0, 90) deg width 1 cm force 20 N
        motion revolute about (0, -20, 0) cm axis (0, 0, -1) range 0 to 90deg
    }}
}}

task o_open_door {{
    scene kitchen
    goal door open 60deg within 3deg
    search {{ max_depth 6  timeout 30 s }}
}}
"""
"""The learned grasp as stdlib/affordances/door.vkg writes it, and task o's goal."""


def grasped_door(folder: Path) -> vkgl.Program:
    """The program of task `o_open_door` with only the Door's grasp of its bar, written into `folder`."""
    path = folder / "o_open_door.vkg"
    path.write_text(SOURCE.format(kitchen=EXAMPLES / "scenes" / "kitchen.vkg"), encoding="utf-8")
    return vkgl.compile(path)
