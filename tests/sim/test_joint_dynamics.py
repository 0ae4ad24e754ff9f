"""A physical joint's `damping` and `friction` in DART: the same push moves a damped or rubbing joint less.

The drawer hangs on its slide (no table contact), so its motion under a
constant push has a closed form to compare with: x = a t^2 / 2 free,
a = (F - f) / m with Coulomb friction f (none when F <= f), and
x = v (t - tau (1 - exp(-t / tau))) with v = F / c, tau = m / c under damping c
(m: the stdlib Drawer's mass, 2 kg).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from sim_bodies import q, stdlib_body, v, with_durations, with_joint_limits

from vkgl.errors import InputError
from vkgl.lang.ir.nodes import Body, Joint
from vkgl.sim import world as sim_world
from vkgl.sim.explore import explore

PUSH = 1.0  # N along the slide
SECONDS = 0.3
MASS = 2.0  # kg, the stdlib Drawer's


def drawer(damping: float | None = None, friction: float | None = None) -> Body:
    """The stdlib Drawer (2 kg) on a long slide, with the given damping (N*s/m) and Coulomb friction (N)."""
    body = with_joint_limits(stdlib_body("Drawer"), 0.0, 2.0)
    assert body.joint is not None and body.mass.value == MASS
    joint = body.joint.model_copy(
        update={
            "damping": q(damping, "N*s/m") if damping is not None else None,
            "friction": q(friction, "N") if friction is not None else None,
        }
    )
    return body.model_copy(update={"joint": joint})


def pushed(body: Body, force: np.ndarray, offset: np.ndarray, seconds: float = SECONDS) -> tuple[float, float]:
    """The joint's position (m or rad) after `seconds` of `force` (world) at `offset` (body frame), and its speed."""
    world = sim_world.new_world()
    skeleton, node = sim_world.add_body(world, "body", body, np.eye(4))
    for _ in range(round(seconds / world.getTimeStep())):
        node.addExtForce(force, offset, False, True)  # DART clears external forces after every step
        world.step()
    joint = skeleton.getJoint(0)
    return float(joint.getPosition(0)), float(joint.getVelocity(0))


def slide(body: Body, force: float = PUSH) -> float:
    return pushed(body, np.array([force, 0.0, 0.0]), np.zeros(3))[0]


def test_the_joint_carries_the_declared_coefficients() -> None:
    skeleton, _ = sim_world.add_body(sim_world.new_world(), "d", drawer(damping=5.0, friction=2.0), np.eye(4))
    joint = skeleton.getJoint(0)
    assert joint.getDampingCoefficient(0) == 5.0 and joint.getCoulombFriction(0) == 2.0
    free, _ = sim_world.add_body(sim_world.new_world(), "d", drawer(), np.eye(4))
    assert free.getJoint(0).getDampingCoefficient(0) == 0.0 and free.getJoint(0).getCoulombFriction(0) == 0.0


def test_an_undamped_slide_accelerates_as_newton_says() -> None:
    assert slide(drawer()) == pytest.approx(0.5 * PUSH / MASS * SECONDS**2, rel=0.02)


def test_a_damped_slide_moves_less_under_the_same_push_and_as_the_damping_says() -> None:
    free, damped = slide(drawer()), slide(drawer(damping=20.0))
    assert damped < 0.5 * free
    speed, tau = PUSH / 20.0, MASS / 20.0
    assert damped == pytest.approx(speed * (SECONDS - tau * (1 - math.exp(-SECONDS / tau))), rel=0.05)
    assert slide(drawer(damping=5.0)) > damped  # more damping, less motion


def test_coulomb_friction_holds_a_slide_against_a_weaker_push_and_slows_a_stronger_one() -> None:
    assert abs(slide(drawer(friction=2.0), force=1.0)) < 1e-5
    rubbed = slide(drawer(friction=0.5), force=1.0)
    assert rubbed == pytest.approx(0.5 * (1.0 - 0.5) / MASS * SECONDS**2, rel=0.05)


def test_a_damped_hinge_turns_less_under_the_same_push() -> None:
    stdlib = stdlib_body("Door")
    assert stdlib.joint is not None
    door = stdlib.model_copy(update={"joint": stdlib.joint.model_copy(update={"damping": None, "friction": None})})
    damped = door.model_copy(update={"joint": door.joint.model_copy(update={"damping": q(2.0, "N*m*s/rad")})})
    push, at = np.array([1.0, 0.0, 0.0]), np.array([-0.01, 0.15, 0.0])  # on the inside, 35 cm from the hinge
    free_angle, _ = pushed(door, push, at)
    damped_angle, _ = pushed(damped, push, at)
    assert free_angle > 0.05  # it opens (positive about its axis, -z: it swings out toward +x)
    assert 0.0 < damped_angle < 0.5 * free_angle


def test_a_negative_coefficient_that_escaped_the_checker_is_an_input_error() -> None:
    bad = drawer().model_copy(
        update={"joint": Joint(type="prismatic", axis=v(1, 0, 0), lower=q(0.0), upper=q(0.3), damping=q(-1.0))}
    )
    with pytest.raises(InputError, match=r"handmade\.vkg:1:5: the damping of Drawer.s joint must be zero or positive"):
        sim_world.add_body(sim_world.new_world(), "d", bad, np.eye(4))


def test_exploration_pushes_a_damped_drawer_open_less_far() -> None:
    """The exploration world is built by the same `add_body`: the fingertip's 1 N pull meets the damping."""
    opened = []
    for damping in (None, 30.0):
        body = drawer(damping=damping)
        pull = with_durations(body.model_copy(update={"explores": body.explores[1:]}), 1.0)  # hooked behind the bar
        trials = explore(pull, jobs=1)
        pulled_open = 0  # from the closed end (then from the open end, against the stop)
        assert trials.force[pulled_open, 0] == 1.0
        x = trials.T_ow[pulled_open, : trials.samples(pulled_open), 0, 3]
        opened.append(float(x[-1] - x[0]))
    free, damped = opened
    assert free > 0.05 and 0.0 < damped < 0.5 * free, opened


def test_the_fingertips_force_limit_covers_a_joints_friction_as_the_tables_for_a_lying_body() -> None:
    """`force normal F` is the push beyond friction: a slide's friction force, a hinge's torque over the lever."""
    from vkgl.sim.explore import push_force_limit

    assert push_force_limit(drawer(), 1.0) == 1.0  # no friction: F
    assert push_force_limit(drawer(friction=1.5), 1.0, np.array([0.19, 0.0, 0.0])) == pytest.approx(2.5)
    door = stdlib_body("Door")  # 0.2 N*m at its hinge, through (0, -20, 0) cm about z
    assert door.joint is not None and door.joint.friction is not None and door.joint.friction.value == 0.2
    assert push_force_limit(door, 1.0, np.array([0.01, 0.0, 0.0])) == pytest.approx(1.0 + 0.2 / np.hypot(0.01, 0.2))
    assert push_force_limit(door, 1.0, np.array([0.05, 0.135, 0.15])) == pytest.approx(
        1.0 + 0.2 / np.hypot(0.05, 0.335)
    )
    assert push_force_limit(door, 1.0, np.array([0.0, -0.2, 0.3])) == pytest.approx(1.0 + 0.2 / 0.01)  # on the axis
    block = stdlib_body("Block")
    assert push_force_limit(block, 1.0) == pytest.approx(1.0 + 0.5 * 0.5 * 9.81)


def test_exploration_pulls_a_rubbing_drawer_open_with_the_push_beyond_its_friction() -> None:
    """A 3 N slide friction would hold a fingertip limited to the declared 1 N; beyond it, the drawer opens."""
    body = drawer(friction=3.0)
    pull = with_durations(body.model_copy(update={"explores": body.explores[1:]}), 1.0)
    trials = explore(pull, jobs=1)
    x = trials.T_ow[0, : trials.samples(0), 0, 3]
    assert float(x[-1] - x[0]) > 0.02
