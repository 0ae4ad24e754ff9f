"""The grip's model, where the executor's grip modules read it: it lives in `vkgl.robot.grip`, below the planner,
which estimates the same load before it plans a push with a held tool."""

from vkgl.robot.grip import (
    GRIP_FORCE,
    PAD_FRICTION,
    PAD_RADIUS,
    SLIP_ANGLE_TOLERANCE,
    SLIP_TOLERANCE,
    Grip,
    grip_for,
)

__all__ = ["GRIP_FORCE", "PAD_FRICTION", "PAD_RADIUS", "SLIP_ANGLE_TOLERANCE", "SLIP_TOLERANCE", "Grip", "grip_for"]
