"""A scene body where it starts, the table and the robots' bases, as the scene checks see them; and how their
messages write lengths and positions."""

from __future__ import annotations

from typing import NamedTuple

from vkgl.lang.checks.geometry.rigid import Rigid, Vec3
from vkgl.lang.checks.geometry.solids import Piece
from vkgl.lang.ir import nodes as ir

TOUCH = 0.001
"""m: bodies may interpenetrate this much at the start (contact, rounding of written positions)."""
JOINT_GAP = 0.0005
"""m: a body on a joint stays this clear of other bodies where it hangs (in DART a drawer touching its
cabinet's top dragged the cabinet 20 cm; 1 mm under it, the cabinet stayed put)."""


class Table(NamedTuple):
    """The table's rectangle (x and y from `low` to `high`) and the height of its top."""

    low: tuple[float, float]
    high: tuple[float, float]
    top: float


class Placed(NamedTuple):
    """A scene body where it starts: its world pose, convex pieces and axis-aligned bounds."""

    scene_body: ir.SceneBody
    body: ir.Body
    pose: Rigid
    pieces: list[Piece]
    low: Vec3
    high: Vec3

    @property
    def name(self) -> str:
        """The scene body's name."""
        return self.scene_body.name


class Base(NamedTuple):
    """A robot's base in a scene."""

    name: str
    pieces: list[Piece]


def cm(metres: float) -> str:
    return f"{metres * 100:.1f} cm"


def m(metres: float) -> str:
    """A coordinate in metres to the millimetre, without trailing zeros: `1.35`, `-0.3`, `2`."""
    if abs(metres) >= 1e6:
        return f"{metres:.4g}"
    text = f"{metres:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def where(scene_body: ir.SceneBody) -> ir.Span | None:
    return scene_body.span or scene_body.placement.span
