"""The arm: its URDF loaded by DART, forward and inverse kinematics, reach."""

from vkgl.robot.arm import Arm, arm_for_scene, load_skeleton

__all__ = ["Arm", "arm_for_scene", "load_skeleton"]
