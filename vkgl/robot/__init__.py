"""The arm: its URDF loaded by DART, forward and inverse kinematics, reach.

Modules, one job each: `urdf` (loading with DART), `frames` (the effector
frame convention), `kinematics` (the chain's FK and Jacobian), `pose_error`
(residuals and tolerances), `optimise` (the NLopt SLSQP set-up), `ready_pose`
(`Arm.home`), `ik` (inverse kinematics), `reach` (the reachable workspace) and
`arm` (the `Arm` placed at a base pose, and how to build one).
"""

from vkgl.robot.arm import Arm, arm_for_scene, clear_caches
from vkgl.robot.frames import rx_pi
from vkgl.robot.pose_error import ANGLE_TOL, POSITION_TOL
from vkgl.robot.urdf import load_skeleton

__all__ = ["ANGLE_TOL", "POSITION_TOL", "Arm", "arm_for_scene", "clear_caches", "load_skeleton", "rx_pi"]
