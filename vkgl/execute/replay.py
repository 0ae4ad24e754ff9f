"""Carry out the steps of a `vkg-plan/8` plan in a DART world of the task's scene.

`Replay` is the façade the closed loop (`vkgl.execute.closed_loop`) drives:
one simulated world of the scene (`scene_world.SceneWorld`: table, bodies,
arm), the arm's moves in it (`arm_moves.ArmMoves`: effector paths, travel
through free space, contact motions solved beforehand) and the step kinds
(`steps.StepKinds`: push, let go, grasp, release). Each plan step becomes an
effector path (`vkgl.execute.effector_path`) that the arm follows; the bodies
move only through contact and friction with the fingertip or a held tool —
their poses are never set after the start.

The plan comes as a `vkgl.formats.plan.PlanDocument`; nothing here reads JSON.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from vkgl.execute.arm_moves import ArmMoves
from vkgl.execute.scene_world import SceneWorld
from vkgl.execute.steps import StepKinds
from vkgl.execute.world_arm import ArmStuck
from vkgl.formats.execution_report import Frames, GripReport
from vkgl.formats.plan import PlanRobot, PlanStepRecord
from vkgl.lang.ir.nodes import Body, Scene
from vkgl.lang.ir.program import Program


class Replay:
    """A DART world of one task's scene, in which plan steps are carried out one after another."""

    def __init__(self, program: Program, scene: Scene, robot: PlanRobot, *, record: bool) -> None:
        """Build the world of `scene` with the plan's `robot` in it; with `record`, keep frames for `animate`."""
        self.sim = SceneWorld(program, scene, robot, record=record)
        self.moves = ArmMoves(self.sim)
        self.kinds = StepKinds(self.sim, self.moves)

    # ------------------------------------------------------------ observation

    @property
    def time(self) -> float:
        """Simulated time since the start (s)."""
        return self.sim.time

    @property
    def label(self) -> str:
        """What the arm is doing now, as the animation labels it (`step 2 motion`, `replan retreat`)."""
        return self.sim.label

    def watch(self, on_advance: Callable[[], None] | None) -> None:
        """Call `on_advance()` after every control period the world runs (None: stop)."""
        self.sim.on_advance = on_advance

    @property
    def frames(self) -> Frames | None:
        """The recorded frames (None unless recording)."""
        return self.sim.frames

    @property
    def types(self) -> dict[str, Body]:
        """The body type of every scene body, by body name."""
        return self.sim.types

    def poses(self) -> dict[str, np.ndarray]:
        """The real world poses of every scene body now."""
        return self.sim.poses()

    def holding(self) -> str | None:
        """The name of the tool in the hand, if any."""
        return self.sim.holding()

    def grip_report(self) -> GripReport | None:
        """The grip on the tool held during the step just carried out (slip, load), None if no tool was held."""
        report = self.sim.grip.report
        return None if report is None else dataclasses.replace(report)

    def openings(self) -> dict[str, float]:
        """The coordinate of every body's physical joint now (m or rad, 0 where the scene places the body)."""
        return self.sim.openings()

    def opening_at(self, name: str, pose: np.ndarray) -> float:
        """The coordinate of body `name`'s physical joint at world `pose` (a planned pose)."""
        return self.sim.opening_at(name, pose)

    def joint_type(self, name: str) -> str | None:
        """ "prismatic" or "revolute" for a body on a physical joint, else None."""
        joint = self.sim.types[name].joint
        return None if joint is None else joint.type

    # ------------------------------------------------------------ acting

    def run_step(self, index: int, step: PlanStepRecord) -> None:
        """Carry out step `index` (from 1) of a plan. Raises ArmStuck if the arm cannot follow the path."""
        self.kinds.run_step(index, step)

    def let_go(self, label: str = "end") -> None:
        """Break contact: back off against the push direction, then lift. Nothing if not in contact."""
        self.kinds.let_go(label)

    def put_down(self, label: str) -> None:
        """Lower the held tool onto the table and let go of it; then lift the empty hand."""
        self.kinds.put_down(label)

    def settle(self, seconds: float, label: str = "settle") -> None:
        """Let the world run with the arm still."""
        self.kinds.settle(seconds, label)


__all__ = ["ArmStuck", "Replay"]
