"""Bodies for the exploration tests.

`stdlib_body(name)` parses stdlib/bodies/NAME.vkg when the front end exists, and
otherwise returns the same body written by hand here (`HANDMADE`); a test checks
that the two agree once both exist. `with_policy` shrinks a body's grid for fast
tests. The handmade bodies carry spans into a made-up file, so that error
messages can be checked for file:line:col without the parser.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any

from vkgl.lang.ir.nodes import (
    Body,
    BoxShape,
    ContactSpec,
    Explore,
    ForceSpec,
    Frame,
    Joint,
    Pose,
    Quantity,
    Ref,
    ShapePart,
    Span,
    UnionShape,
    Vector,
)

STDLIB = Path(__file__).resolve().parents[2] / "stdlib"

FILE = "handmade.vkg"


def span(line: int, col: int = 5, length: int = 10) -> Span:
    """A span on one line of the made-up file."""
    return Span(file=FILE, line=line, col=col, end_line=line, end_col=col + length)


def q(value: float, unit: str = "", line: int = 1) -> Quantity:
    return Quantity(value=value, unit=unit, span=span(line))


def v(*values: float, unit: str = "") -> Vector:
    return Vector(values=tuple(float(x) for x in values), unit=unit)


def push_policy(faces: list[str], steps: int, force: float, duration: float, line: int = 10) -> Explore:
    return Explore(
        name="pushes",
        contacts=ContactSpec(faces=faces, steps=steps, span=span(line + 1)),
        force=ForceSpec(mode="normal", magnitude=q(force, "N", line + 2), span=span(line + 2)),
        duration=q(duration, "s", line + 3),
        span=span(line),
    )


def block(steps: int = 9, faces: list[str] | None = None, duration: float = 2.0, slides: bool = False) -> Body:
    """The Block; with `slides`, also its long centre pushes (the stdlib's second explore block, 2 x 17 s)."""
    explores = [push_policy(faces or ["+x", "-x"], steps, 1.0, duration)]
    if slides:
        explores.append(push_policy(["+x", "-x"], 1, 1.0, 17.0, line=20).model_copy(update={"name": "slides"}))
    return Body(
        name="Block",
        shape=BoxShape(size=v(0.10, 0.20, 0.05, unit="cm")),
        mass=q(0.5, "kg"),
        friction=0.5,
        frames=[Frame(name="com", pose=Pose(position=v(0, 0, 0, unit="cm")))],
        explores=explores,
        name_span=span(7, 6, 5),
        span=span(7, 1, 30),
    )


def hook_policy(frames: str | list[str], force: float, duration: float, line: int = 20) -> Explore:
    """`explore pull { contacts at FRAME[, FRAME]  force normal F  duration D }`: the fingertip behind a handle."""
    names = [frames] if isinstance(frames, str) else frames
    refs = [Ref(name=name, span=span(line + 1, 21, len(name))) for name in names]
    return Explore(
        name="pull",
        contacts=ContactSpec(frames=refs, span=span(line + 1)),
        force=ForceSpec(mode="normal", magnitude=q(force, "N", line + 2), span=span(line + 2)),
        duration=q(duration, "s", line + 3),
        span=span(line),
    )


def part(size: tuple[float, float, float], at: tuple[float, float, float]) -> ShapePart:
    """A box of a union, in cm."""
    return ShapePart(
        shape=BoxShape(size=v(*(round(x / 100, 12) for x in size), unit="cm")),  # as the parser reads "22.4 cm"
        pose=Pose(position=v(*(round(x / 100, 12) for x in at), unit="cm")),
    )


def drawer(steps: int = 1, limits: tuple[float, float] = (0.0, 0.30), duration: float = 10.0) -> Body:
    """The Drawer: a box with a bar handle in front of its +x face, closed by pushes and opened by pulls behind
    the bar's middle and its overhang; its slide damped and rubbing."""
    return Body(
        name="Drawer",
        shape=UnionShape(
            parts=[
                part((30, 40, 10), (0, 0, 0)),
                part((4, 1, 1), (17, -6.4, 0)),
                part((4, 1, 1), (17, 6.4, 0)),
                part((1, 22.4, 1), (19.5, 0, 0)),
            ]
        ),
        mass=q(2.0, "kg"),
        friction=0.5,
        frames=[
            Frame(name="handle", pose=Pose(position=v(0.19, 0, 0, unit="cm"))),
            Frame(name="bar_end", pose=Pose(position=v(0.19, 0.105, 0, unit="cm"))),
        ],
        joint=Joint(
            type="prismatic",
            axis=v(1, 0, 0),
            lower=q(limits[0], "cm"),
            upper=q(limits[1], "cm"),
            damping=q(4.0, "N*s/m"),
            friction=q(1.5, "N"),
        ),
        explores=[push_policy(["+x"], steps, 1.0, duration), hook_policy(["handle", "bar_end"], 1.0, duration)],
        name_span=span(7, 6, 6),
        span=span(7, 1, 30),
    )


def door(steps: int = 1, duration: float = 12.0) -> Body:
    """The Door: a plate hinged at its -y edge, a bar handle on its +x face; pushes close it, a pull opens it."""
    return Body(
        name="Door",
        shape=UnionShape(
            parts=[
                part((2, 40, 50), (0, 0, 0)),
                part((4, 1, 1), (3, 9.5, 15)),
                part((4, 1, 1), (3, 17.5, 15)),
                part((1, 10, 1), (5.5, 13.5, 15)),
            ]
        ),
        mass=q(3.0, "kg"),
        friction=0.5,
        frames=[Frame(name="handle", pose=Pose(position=v(0.05, 0.135, 0.15, unit="cm")))],
        joint=Joint(
            type="revolute",
            axis=v(0, 0, -1),
            through=v(0, -0.20, 0, unit="cm"),
            lower=q(0.0, "deg"),
            upper=q(math.pi / 2, "deg"),
            damping=q(0.3, "N*m*s/rad"),
            friction=q(0.2, "N*m"),
        ),
        explores=[push_policy(["+x"], steps, 1.0, duration), hook_policy("handle", 1.0, duration)],
        name_span=span(7, 6, 4),
        span=span(7, 1, 30),
    )


def stick(grid: tuple[int, int, int] = (3, 3, 3), duration: float = 1.0, grasp: str = "handle") -> Body:
    return Body(
        name="Stick",
        shape=BoxShape(size=v(0.40, 0.02, 0.02, unit="cm")),
        mass=q(0.1, "kg"),
        frames=[
            Frame(name="handle", pose=Pose(position=v(-0.15, 0, 0, unit="cm"))),
            Frame(name="tip", pose=Pose(position=v(0.20, 0, 0, unit="cm"))),
        ],
        explores=[
            Explore(
                name="wield",
                grasp=Ref(name=grasp, span=span(11, 9, len(grasp))),
                force=ForceSpec(mode="directions", grid=grid, magnitude=q(1.0, "N", 12), span=span(12)),
                duration=q(duration, "s", 13),
                span=span(10),
            )
        ],
        name_span=span(7, 6, 5),
        span=span(7, 1, 30),
    )


HANDMADE = {"Block": functools.partial(block, slides=True), "Drawer": drawer, "Door": door, "Stick": stick}


def stdlib_body(name: str) -> Body:
    """The stdlib body `name`, compiled from its file (the silent fallback to a handmade twin is gone)."""
    from vkgl.lang.compiler import compile_file

    return compile_file(str(STDLIB / "bodies" / f"{name.lower()}.vkg")).bodies[name]


def with_policy(body: Body, **changes: Any) -> Body:
    """`body` with its first explore block changed: faces=, steps=, duration=, grid=, magnitude=."""
    policy = body.explores[0]
    update: dict[str, Any] = {}
    if "faces" in changes or "steps" in changes:
        assert policy.contacts is not None
        update["contacts"] = policy.contacts.model_copy(
            update={k: changes[k] for k in ("faces", "steps") if k in changes}
        )
    if "duration" in changes:
        assert policy.duration is not None
        update["duration"] = policy.duration.model_copy(update={"value": changes["duration"]})
    if "grid" in changes or "magnitude" in changes:
        assert policy.force is not None
        force: dict[str, Any] = {}
        if "grid" in changes:
            force["grid"] = changes["grid"]
        if "magnitude" in changes:
            force["magnitude"] = policy.force.magnitude.model_copy(update={"value": changes["magnitude"]})
        update["force"] = policy.force.model_copy(update=force)
    return body.model_copy(update={"explores": [policy.model_copy(update=update)]})


def with_durations(body: Body, seconds: float) -> Body:
    """`body` with every explore block lasting `seconds`."""
    explores = [
        e.model_copy(update={"duration": e.duration.model_copy(update={"value": seconds})}) for e in body.explores
    ]
    return body.model_copy(update={"explores": explores})


def with_joint_limits(body: Body, lower: float, upper: float) -> Body:
    """`body` with its joint's limits changed (SI)."""
    assert body.joint is not None
    joint = body.joint.model_copy(
        update={
            "lower": body.joint.lower.model_copy(update={"value": lower}),
            "upper": body.joint.upper.model_copy(update={"value": upper}),
        }
    )
    return body.model_copy(update={"joint": joint})
