"""A contact's arm configurations (`vkgl.plan.arm.contact_chains`): the arm's other configurations are tried when
the plan's and home's cannot carry the motion, so that no plan needs a step that moves nothing to seed them."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
from task_makers.generated_tasks import TEST_SOLVE_TIMEOUT_S, fixture_library, task_spec, write_task

import vkgl
from vkgl.plan.arm.contact_chains import CLASH_PARTS, ContactChains, between
from vkgl.plan.arm.straight_moves import ArmState, Overlap, StraightMoves
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.problem.problem import build_problem

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


def test_gen1_024_is_one_arc_push_without_a_0_cm_push_before_it(tmp_path: Path) -> None:
    # the arc's chain from home broke off (a joint jump near the stretched elbow, the hand leaned back 30 deg) and
    # the hand upright hit the slab with a finger in every configuration; the search then found the same arc
    # after a 0 cm push on the other face and its release, whose configuration seeded IK at the arc's contact
    spec = task_spec(1, 24)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    steps = plan.to_json()["steps"]
    assert [(s["op"], s["affordance"]) for s in steps] == [("add", "SlabW.push_center_nx@-2.90cm")]
    assert all(s["value"] > 0.01 for s in steps if s["op"] == "add")  # every push moves its body


def test_only_the_links_beyond_the_arms_last_joint_and_a_held_tool_move_with_the_hand() -> None:
    program = vkgl.compile(EXAMPLES / "tasks" / "a_push.vkg")
    problem = build_problem(program, program.task("a_push"))
    chains = ContactChains(problem, StraightMoves(problem, GeometryCheck(problem)))
    for part in ("panda_leftfinger", "panda_hand", "panda_link7", "fingertip"):
        assert chains._rigid_with_hand(Overlap(f"the arm's {part} would overlap block by 0.2 cm", 0.002, link=part))
    assert chains._rigid_with_hand(Overlap("hook would overlap block by 0.3 cm", 0.003))  # a held tool
    for part in ("panda_link6", "panda_link4"):  # another elbow or wrist position may pass clear
        assert not chains._rigid_with_hand(Overlap(f"the arm's {part} would overlap block", 0.002, link=part))


def test_the_plans_and_homes_configurations_come_first_as_before(tmp_path: Path) -> None:
    # a contact whose chain from the plan's configuration carries the motion is given that chain first
    program = vkgl.compile(EXAMPLES / "tasks" / "a_push.vkg")
    plan = vkgl.solve(program)
    assert plan.status == "solved" and plan.problem is not None
    step = plan.steps[0]
    problem = plan.problem
    chains = ContactChains(problem, StraightMoves(problem, GeometryCheck(problem)))
    first = next(chains.solve(step, ArmState(problem.arm.home.copy()), "step 1"))
    assert isinstance(first, np.ndarray) and np.allclose(first, step.contact)


def test_gen3_018_pushes_the_cube_before_the_crate_aside_with_the_hand_turned(tmp_path: Path) -> None:
    # a CubeS 1.8 cm before the face of the CrateM to be pushed 34 cm, on its way, turned 60 deg to it: pushed aside
    # with the pad along its face, the 20 cm wide hand overlaps the crate by 3.1 cm at the contact, leaned or rolled
    # as it may be (before: a timeout at 20 CPU-s); turned about its axis, the pad's end pushes and the hand's width
    # lies along the push, clear of the crate
    spec = task_spec(3, 18)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, max_depth=4, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    # (the contacts may be raised on their faces, `/over+0deg+...`: the same pushes, the hand higher)
    assert [(s.op, s.affordance.split("/")[0]) for s in plan.steps] == [
        ("add", "CubeS.push_center_px"),
        ("remove", "CubeS.push_center_px"),
        ("add", "CrateM.push_center_px"),
    ]
    assert plan.problem is not None
    first = plan.steps[0]
    hand = plan.problem.arm.fk(first.contact[0])
    push = (first.poses_start[first.body] @ plan.problem.action(first.body, first.affordance.partition(".")[2]))[:3, 0]
    assert abs(float(hand[:3, 1] @ push)) > np.sin(np.radians(25.0))  # the pad's axis no longer across the push
    last = plan.steps[2]
    crate = plan.problem.arm.fk(last.contact[0])
    crate_action = plan.problem.action(last.body, last.affordance.partition(".")[2])
    crate_push = (last.poses_start[last.body] @ crate_action)[:3, 0]
    assert abs(float(crate[:3, 1] @ crate_push)) < 0.1  # where nothing stands beside, the pad lies along the face


def test_gen3_000_pulls_past_a_cube_beside_the_way_with_the_hand_rolled(tmp_path: Path) -> None:
    # the fingertip pulls a CubeS 15 cm back past another CubeS 6 cm beside its way: upright, a finger meets the
    # pulled cube; leaned back 30 deg, the 20 cm wide hand meets the one beside by 0.1 cm; rolled 20 deg about
    # the pull's direction its side rises over it (before: a 5-graph plan clearing that cube first, 20 CPU-s)
    spec = task_spec(3, 0)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, max_depth=2, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["CubeS.push_center_nx"]
    assert plan.problem is not None
    hand = plan.problem.arm.fk(plan.steps[0].contact[0])
    pad_axis = hand[:3, 1]  # the pad lies along the effector frame's y: upright or leaned back, level
    assert abs(pad_axis[2]) > np.sin(np.radians(15.0))


def test_a_contact_exactly_a_whole_number_of_spacings_long_gets_the_same_chain_on_any_cpu() -> None:
    """15 cm is 15 spacings whether a CPU computes it as 0.15 or 0.15000000000000002 m (the drawer's golden plan
    had 17 configurations on one machine, 16 on another); a millimetre more is one more spacing."""
    from vkgl.plan.arm.contact_chains import CHAIN_SPACING, chain_count

    assert chain_count(0.15) == chain_count(0.15 * (1 + 4e-16)) == chain_count(0.15 * (1 - 4e-16)) == 16
    assert chain_count(0.151) == 17
    assert chain_count(0.0) == 2 and chain_count(CHAIN_SPACING / 2) == 2


class _RecordingMoves:
    """Straight moves whose overlap check records every configuration asked and clashes at one of them."""

    def __init__(self, clash_at: np.ndarray | None = None) -> None:
        self.asked: list[np.ndarray] = []
        self.clash_at = clash_at

    def grasps(self, step: object) -> bool:
        return False

    def first_overlap(self, joints: np.ndarray, *args: object) -> Overlap | None:
        self.asked.append(joints[0].copy())
        if self.clash_at is not None and np.allclose(joints[0], self.clash_at):
            return Overlap("the arm's panda_hand would overlap clutter by 0.1 cm", 0.001, frozenset({"clutter"}))
        return None


def _still_step() -> SimpleNamespace:
    pose = np.eye(4)
    return SimpleNamespace(body="block", poses_start={"block": pose}, poses_end={"block": pose})


def test_the_arm_is_checked_between_a_chains_configurations_too() -> None:
    # a hand clear at two configurations 1 cm apart may pass through a body between them (gen15_028: 0.8 mm deep)
    chain = np.array([[0.0] * 7, [0.4] * 7, [1.2] * 7])
    joints, fractions = between(chain)
    assert len(joints) == 2 * (CLASH_PARTS - 1)
    assert np.all((fractions > 0) & (fractions < 1)) and not np.isin(fractions, [0.0, 0.5, 1.0]).any()
    assert np.allclose(joints[:, 0], np.interp(fractions, [0.0, 0.5, 1.0], chain[:, 0]))  # as the executor follows
    program = vkgl.compile(EXAMPLES / "tasks" / "a_push.vkg")
    problem = build_problem(program, program.task("a_push"))
    clear = _RecordingMoves()
    state = ArmState(problem.arm.home.copy())
    assert ContactChains(problem, clear)._contact_clash(_still_step(), state, chain) is None  # type: ignore[arg-type]
    assert len(clear.asked) == len(chain) + len(joints)  # the chain's own first, then those between
    clipping = _RecordingMoves(clash_at=joints[-1])
    clash = ContactChains(problem, clipping)._contact_clash(_still_step(), state, chain)  # type: ignore[arg-type]
    assert clash is not None and clash.words.startswith(f"{fractions[-1]:.0%} along the contact's motion")
    one = ContactChains(problem, _RecordingMoves())._contact_clash(_still_step(), state, chain[:1])  # type: ignore[arg-type]
    assert one is None  # a single configuration (the turned hand's first check) has nothing between
