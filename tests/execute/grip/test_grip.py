"""A held tool is held by the fingers' friction: its slip is reported, a grip too weak for the load breaks and
fails the step (exit 5), and the closed loop grasps again.

The plans are scripted (`plan_script`) so that these tests do not depend on the
search; the physics, the grip's load and the slip are real. A weak grip is made
by lowering the fingers' force in the executor only (`_weak_grips`: the grip
`vkgl.execute.steps` holds a tool with; the planner keeps the real one) so far
that the stick's own weight, held at its end, needs more torque than the pads'
friction carries.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXAMPLES
from plan_script import scripted_plan

from vkgl.execute.closed_loop import execute
from vkgl.execute.grip import model
from vkgl.execute.grip.model import Grip, grip_for
from vkgl.execute.resolving import Attempts
from vkgl.formats.plan import PlanDocument
from vkgl.lang.compiler import compile_file
from vkgl.lang.ir.program import Program

TASK = "b_stick_push"
GRASP = "add Stick.wield stick arm.fingertip"
WEAK = 2.0  # N: the stick's weight at 15 cm needs 0.147 N m; 2 x 0.5 x 2 N over a 1 cm pad carries 0.013 N m


@pytest.fixture(scope="module")
def program() -> Program:
    return compile_file(str(EXAMPLES / "tasks" / f"{TASK}.vkg"))


def test_the_grip_carries_two_mu_f_and_its_torsional_friction():
    grip = Grip(force=70.0, friction=0.5)
    assert grip.max_force == pytest.approx(70.0)
    assert grip.max_torque == pytest.approx(70.0 * 0.01 * 2 / 3)
    # force along the closing axis (y) and torque about x and z are the fingers' own, not friction's
    assert grip.usage(np.array([0.0, 500.0, 0.0]), np.array([9.0, 0.0, 9.0])) == 0.0
    assert grip.usage(np.array([35.0, 0.0, 0.0]), np.zeros(3)) == pytest.approx(0.5)
    assert grip.usage(np.zeros(3), np.array([0.0, -grip.max_torque, 0.0])) == pytest.approx(1.0)


def test_a_fixed_action_grips_with_the_pandas_force_and_the_smaller_friction(program):
    action = next(a for a in program.affordances["Stick"] if a.name == "wield").action
    grip = grip_for(action, program.bodies["Stick"].friction)
    assert grip.force == model.GRIP_FORCE and grip.friction == pytest.approx(0.5)
    assert grip_for(action, 2.0).friction == model.PAD_FRICTION  # the pads' 1.0 when the tool's is higher


def test_a_held_sticks_slip_and_load_are_reported(program):
    plan = scripted_plan(program, TASK, [GRASP, "remove Stick.wield stick arm.fingertip"])
    report = execute(program, TASK, plan)
    release = report.steps[1]
    assert release.grip is not None and release.grip.tool == "stick" and not release.grip.broke
    assert release.grip.slip < 0.001
    # lowered onto the table, the grip carries the stick's weight 15 cm from its centre: 0.147 N m of 0.467
    assert 0.25 < release.grip.peak_load < 0.45
    assert "grip on stick: slip" in report.text()
    data = report.to_json()
    assert data["format"] == "vkg-execution/5" and data["steps"][1]["grip"]["tool"] == "stick"


def _weak_grips(monkeypatch) -> None:
    """The executor holds every tool with `WEAK` N (the planner, which estimates loads, keeps the real grip)."""
    real = grip_for
    monkeypatch.setattr("vkgl.execute.steps.grip_for", lambda action, mu: Grip(WEAK, real(action, mu).friction))


def test_a_grip_too_weak_for_the_load_breaks_and_fails_the_step(program, monkeypatch):
    _weak_grips(monkeypatch)
    plan = scripted_plan(program, TASK, [GRASP, "add Block.push_center_px block stick.tip 0.25"])
    report = execute(program, TASK, plan)
    assert report.status == "failed", report.text()
    assert "slipped" in report.reason and "the grip broke" in report.reason
    grip = report.steps[-1].grip
    assert grip is not None and grip.broke and grip.peak_load > 1.0
    assert grip.slip > model.SLIP_TOLERANCE or grip.slip_angle > model.SLIP_ANGLE_TOLERANCE


def test_replanning_grasps_the_tool_again(program, monkeypatch):
    """The first grasp is weak (a greasy handle), the re-solved plan grasps the stick again and holds it."""
    grips = [WEAK]
    real = grip_for

    def weak_first(action, friction):
        grip = real(action, friction)
        return Grip(grips.pop(), grip.friction) if grips else grip

    monkeypatch.setattr("vkgl.execute.steps.grip_for", weak_first)
    resolved: list[PlanDocument] = []

    def regrasp(observed: Program, task: str, attempts: Attempts) -> PlanDocument:
        assert attempts.failed and "slipped" in attempts.failed[0].why
        resolved.append(scripted_plan(observed, task, [GRASP]))
        return resolved[-1]

    plan = scripted_plan(program, TASK, [GRASP, "add Block.push_center_px block stick.tip 0.25"])
    report = execute(program, TASK, plan, replan=True, resolve=regrasp, max_replans=1)
    assert len(resolved) == 1 and report.resolves[0].outcome == "new plan"
    again = [s for s in report.steps if s.plan == 1]
    assert again and again[0].title.startswith("add Stick.wield")
    assert again[0].grip is not None and not again[0].grip.broke, report.text()
    assert report.status == "missed" and "gave up after 1 replan" in report.reason  # the new plan only grasps


def test_vkgc_exits_5_when_the_held_tool_slips(monkeypatch, capsys):
    from vkgl.cli import main
    from vkgl.cli.exit_codes import EXIT_NOT_REACHED

    _weak_grips(monkeypatch)
    code = main(["solve", str(EXAMPLES / "tasks" / f"{TASK}.vkg"), "--execute"])
    out = capsys.readouterr().out
    assert code == EXIT_NOT_REACHED
    failed = [line for line in out.splitlines() if line.startswith("failed:")]
    assert failed and "stick slipped" in failed[0] and "the grip broke" in failed[0]


def test_a_grasp_action_grips_with_its_stated_force_and_width():
    from vkgl.api import compile_source

    program = compile_source(
        "body Carton {\n    shape box (6, 6, 12) cm\n    mass 0.3 kg\n}\n"
        "affordances Carton {\n    affordance grasp_top_y {\n"
        "        action grasp at (0.6, 0, 3.2) cm yaw 0deg width 6 cm force 20 N\n"
        "        motion free\n    }\n}\n"
    )
    action = program.affordances["Carton"][0].action
    assert grip_for(action, None) == Grip(force=20.0, friction=0.5)
    assert action.width == pytest.approx(0.06)  # what the fingers close to (vkgl.execute.steps)


def test_the_width_across_the_grip_is_measured_on_the_tools_shape(program):
    from vkgl.execute.grip.fingers import width_across_grip
    from vkgl.lang.ir.geometry import body_mesh

    grasp = np.eye(4)
    grasp[0, 3] = -0.15  # the stick's handle
    assert width_across_grip(body_mesh(program.bodies["Stick"]), grasp) == pytest.approx(0.02)
    hook_grasp = grasp.copy()
    assert width_across_grip(body_mesh(program.bodies["Hook"]), hook_grasp) == pytest.approx(0.02)


def test_the_fingers_close_onto_the_tool_and_open_to_let_go(program):
    from vkgl.execute.grip.fingers import FINGER_CLEARANCE, TOUCH_GAP
    from vkgl.execute.replay import Replay

    plan = scripted_plan(program, TASK, [GRASP, "remove Stick.wield stick arm.fingertip"])
    replay = Replay(program, program.scenes[program.task(TASK).scene.name], plan.robot, record=False)
    fingers = replay.sim.fingers
    assert [j.getName() for j in fingers.joints] == ["panda_finger_joint1", "panda_finger_joint2"]
    assert fingers.opening == 0.0  # closed behind the fingertip pad
    where = replay.poses()["stick"]
    replay.run_step(1, plan.steps[0])
    assert fingers.opening == pytest.approx(0.01 + TOUCH_GAP, abs=1e-4)  # half the stick's 2 cm, both sides
    assert np.abs(replay.poses()["stick"] - where).max() < 1e-4  # the pads closed without shoving it
    replay.run_step(2, plan.steps[1])
    assert fingers.opening == pytest.approx(0.01 + FINGER_CLEARANCE, abs=1e-4)
    assert replay.holding() is None


class _StillHand:
    """Just what `GripWatch` asks of the arm: a world, an effector pose, a grip that can break."""

    def __init__(self, world, pose):
        self.world, self.pose, self.broke = world, pose, False

    def effector_pose(self):
        return self.pose

    def break_grip(self):
        self.broke = True


def test_a_handle_loads_the_grip_with_what_its_joint_needs():
    """The stdlib Drawer sliding open at 0.1 m/s on its joint (damping 4 N s/m, friction 1.5 N) needs 1.9 N
    along its slide at the hand: what its handle's grip must carry (its weight is the joint's)."""
    from vkgl.execute.grip.watch import GripWatch
    from vkgl.sim import world as sim_world

    program = compile_file(str(EXAMPLES / "tasks" / "g_open_drawer.vkg"))
    world = sim_world.new_world()
    skeleton, node = sim_world.add_body(world, "drawer", program.bodies["Drawer"], np.eye(4))
    hand = np.eye(4)
    hand[:3, 3] = node.getWorldTransform().translation() + [0.2, 0.0, 0.05]
    watch = GripWatch(_StillHand(world, hand))
    watch.hold("drawer", node, Grip(force=1.0, friction=0.5), jointed=True)  # carries 1 N in the pads' plane
    skeleton.setVelocity(0, 0.1)
    for _ in range(2):
        world.step(False)
        skeleton.setVelocity(0, 0.1)  # held at a steady speed, as the hand would
        watch.after_physics_step(world)
    watch.after_period(0.002)
    assert watch.report is not None and watch.report.peak_load == pytest.approx(1.9, abs=0.05)  # of 2 x 0.5 x 1 N
    assert watch.arm.broke and "a load of 1.9 N, 0.00 N m" in watch.report.broke


def test_the_watch_finds_a_bodys_contacts_by_its_shapes_ids(program):
    """Two blocks of one type resting on the table: each block's shape ids pick out exactly the contacts whose
    shape node is one of its own (as their names did), never its twin's."""
    from vkgl.execute.grip.watch import shape_ids
    from vkgl.sim import world as sim_world

    world = sim_world.new_world()
    sim_world.add_table(world)
    nodes = {}
    for name, x in (("one", 0.0), ("two", 0.3)):
        pose = np.eye(4)
        pose[:3, 3] = [x, 0.0, 0.024]  # 1 mm into the table: touching from the first step
        nodes[name] = sim_world.add_body(world, name, program.bodies["Block"], pose)[1]
    world.step(False)
    contacts = world.getLastCollisionResult().getContacts()
    ids = {name: shape_ids(node) for name, node in nodes.items()}
    assert ids["one"] and not ids["one"] & ids["two"]
    for name, node in nodes.items():
        names = {node.getShapeNode(i).getName() for i in range(node.getNumShapeNodes())}
        sides = [obj for c in contacts for obj in (c.collisionObject1, c.collisionObject2)]
        by_id = [obj.getShape().getID() in ids[name] for obj in sides]
        assert by_id == [obj.getShapeFrame().getName() in names for obj in sides]
        assert any(by_id)  # the block touches the table
