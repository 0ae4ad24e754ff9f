"""What `vkgc solve` says when there is no plan: infeasible goals (exit 2) and timeouts (exit 3), and input errors."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.api import solve
from vkgl.cli import main
from vkgl.errors import InputError
from vkgl.lang.compiler import compile_file

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "tabletop.vkg"

HEADER = f'''use "{SCENES}"
use stdlib.affordances.block
use stdlib.affordances.stick
use stdlib.affordances.hook
use stdlib.tools
'''


# tabletop_mid on a table 40 cm longer: goals near x = 1.3 m are on it (`vkgc check` rejects goals off the
# table, E423) but out of every effector's reach.
WIDE_MID = """
scene wide_mid {
    table size (2.0, 1.2) m at (0.7, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.7, 0) m yaw 0deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
    hook : Hook on table at (0.3, 0.4) m yaw 0deg
}
"""


def task_file(tmp_path: Path, body: str, name: str = "t") -> str:
    path = tmp_path / f"{name}.vkg"
    path.write_text(HEADER + body, encoding="utf-8")
    return str(path)


def test_goal_off_the_table_is_infeasible_at_once_and_says_why(tmp_path):
    # `vkgc check` rejects such a goal in a file (E423); a goal set through the API reaches the planner
    path = task_file(tmp_path, "task off { scene tabletop  goal block at (0.6, 0.0) m within 1 cm }\n")
    program = compile_file(path).with_goal("off", "block", at=(2.0, 0.0), within=(0.01, 0.05))
    plan = solve(program)
    assert plan.status == "infeasible"
    assert "off the table" in plan.reason and "block" in plan.reason
    assert plan.stats["graphs_expanded"] == 0  # decided before any search (how fast: bench/, not a timed test)


def test_goal_beyond_the_sticks_reach_is_infeasible_and_names_the_reach(tmp_path):
    path = task_file(
        tmp_path,
        "task far { scene tabletop_mid  goal block at (1.25, 0.0) m yaw 0deg within 1 cm, 3 deg"
        "  search { max_depth 6  timeout 20 s } }\n",
    )
    plan = solve(path)
    assert plan.status == "infeasible"
    assert "reach" in plan.reason and "no sequence of at most 6 graphs" in plan.reason
    assert plan.stats["graphs_expanded"] == 0  # the bound proves it before any graph is expanded
    out = plan.to_json()
    assert out["status"] == "infeasible" and out["depth"] is None and out["steps"] == [] and out["reason"]


def test_a_short_timeout_on_a_deep_search_stops_in_about_that_time(tmp_path):
    # far and turned: only the stick held by its end can end the block there, after many graphs if at all, so the
    # search runs through sequences of up to 9 graphs (at (1.25, 0.3) m no tool held any way can: "no plan" at once)
    path = task_file(
        tmp_path,
        WIDE_MID + "task deep { scene wide_mid  goal block at (1.15, 0.3) m yaw 40deg within 1 cm, 3 deg"
        "  search { max_depth 9  timeout 1 s } }\n",
    )
    started = time.perf_counter()
    plan = solve(path)
    elapsed = time.perf_counter() - started
    assert plan.status == "timeout", plan.reason
    assert "timeout of 1 s" in plan.reason
    # The deadline is the wall clock: stopping takes a little past it (the sequence being checked ends first),
    # more on a loaded machine; 9 levels of this search would take minutes.
    assert elapsed < 4.0


def test_command_line_exit_codes(tmp_path, capsys):
    ok = task_file(
        tmp_path, "task ok { scene tabletop  goal block at (0.55, 0.0) m yaw 0deg within 1 cm, 3 deg }\n", "ok"
    )
    off = task_file(tmp_path, "task off { scene tabletop  goal block at (2.0, 0.0) m within 1 cm }\n", "off")
    deep = task_file(
        tmp_path,
        WIDE_MID + "task deep { scene wide_mid  goal block at (1.15, 0.3) m yaw 40deg within 1 cm, 3 deg"
        "  search { max_depth 9  timeout 60 s } }\n",
        "deep",
    )
    out_json, out_png = tmp_path / "plan.json", tmp_path / "plan.png"
    assert main(["solve", ok, "--json", str(out_json), "--plot", str(out_png)]) == 0
    assert out_json.read_text().startswith("{") and out_png.stat().st_size > 10_000
    assert main(["solve", off]) == 1  # E423 at `check`: the goal is off the table
    assert main(["solve", deep, "--timeout", "0.5"]) == 3
    assert main(["solve", deep, "--max-depth", "3"]) == 2
    assert main(["solve", str(tmp_path / "missing.vkg")]) == 1
    captured = capsys.readouterr()
    assert "error[E423]: the goal puts `block` off the table" in captured.out + captured.err


def test_task_naming_a_body_the_scene_lacks_is_an_input_error(compiled):
    program = compiled("a_push")
    with pytest.raises(InputError, match="no task `nope`"):
        solve(program, "nope")
    with pytest.raises(InputError, match="max_depth must be at least 1"):
        solve(program, max_depth=0)


def test_max_depth_bounds_the_graphs_of_a_plan(compiled):
    program = compiled("b_stick_push")
    short = solve(program, max_depth=2)
    assert short.status == "infeasible" and "at most 2 graphs" in short.reason
    assert solve(program, max_depth=3).depth == 3


def test_a_goal_past_a_joint_limit_says_the_numbers() -> None:
    import vkgl

    source = (
        "use stdlib.robots.panda\nuse stdlib.bodies.drawer\nuse stdlib.affordances.drawer\n"
        "scene kitchen { table size (1.6, 1.2) m at (0.5, 0, 0) m  robot arm : Panda at (0, 0, 0) m\n"
        "  drawer : Drawer on table at (0.45, 0) m yaw 0deg }\n"
        "task too_far { scene kitchen  goal drawer at (0.85, 0) m within 1 cm  search { max_depth 3 } }\n"
    )
    plan = vkgl.solve(vkgl.compile_source(source, "kitchen.vkg", base_dir=Path(__file__).parent))
    assert plan.status == "infeasible"
    assert "the goal needs it at 40.0 cm on its prismatic joint, past its upper limit of 30.0 cm" in plan.reason
    assert "--max-depth" not in plan.reason  # no longer sequence passes a joint's limit
