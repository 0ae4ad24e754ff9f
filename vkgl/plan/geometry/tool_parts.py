"""A tool's parts beside its contact: at a contact only the part that carries the tool's frame may touch the body.

A tool acts on a body through its frame (`Hook.tip`, `Stick.tip`), which lies
on one part of the tool's shape (the Hook's cross-piece). That part may sit in
the body's face as deep as its own thickness (`GeometryCheck._tool_through`);
the tool's other parts (the Hook's shaft, 12 cm beside its tip) must stand
clear of the body by `BESIDE_CLEARANCE`. The tool and the body move together
through the contact (the hand carries the tool along the body's planned
motion), so the contact's start decides: a shaft against the body's side
is there from the transit's end (the approach's stand-off, beside the face
it goes to) through the whole motion.

Why: gen8_027 of the physical bench pulled a Block along an arc whose member
puts the contact 1.05 cm toward the Hook's shaft, which then lay 0.5 mm inside
the Block's side. The thickness test let it pass, and so did the transit, which
checks the body a transit leads to with its exact shape and the 1 mm tolerance
of a touch (`HELD_TRANSIT_CLEARANCE`); in DART the shaft touched the Block at
the end of the transit and execution stopped. The straight pulls off the
centre (`vkgl.plan.graphs.tool_faces`) already kept the shaft this far outside
the body's width; arcs (a family's members, learned for a point) did not.

A mesh body is not grown (`vkgl.motion.collision`): against one, a part
beside the contact must only not overlap it by more than the 1 mm tolerance.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from vkgl.lang.ir.geometry import JOINT_LIFT
from vkgl.lang.ir.nodes import UnionShape
from vkgl.motion.collision import TOUCH_TOL, CollisionScene, Contact
from vkgl.plan.problem.over import PART_CLEARANCE, tool_parts
from vkgl.plan.problem.problem import EffectorSpec, Problem

BESIDE_CLEARANCE = PART_CLEARANCE
"""m: how far a tool's parts beside its contact stay from the body it acts on (the same room as a straight pull
off the centre leaves the Hook's shaft, `vkgl.plan.problem.over.PART_CLEARANCE`)."""

ON_PART = 1e-3
"""m: a tool frame this close to a part's box lies on that part."""


class BesideParts:
    """The tool parts beside each tool effector's contact, checked against the bodies it acts on (a small
    collision scene per effector and body, built when first asked)."""

    def __init__(self, problem: Problem) -> None:
        """Checks for `problem`'s tools."""
        self.problem = problem
        self._scenes: dict[tuple[str, str], tuple[CollisionScene, list[tuple[str, np.ndarray]]] | None] = {}

    def overlap(self, effector: EffectorSpec, body: str, poses: Mapping[str, np.ndarray]) -> Contact | None:
        """The deepest overlap of a part of `effector`'s tool beside its contact with `body` grown by
        `BESIDE_CLEARANCE` (named as the tool and the body), the bodies at `poses`; None when they stand clear or
        the tool has no part beside the contact."""
        assert effector.tool is not None, "only a tool has parts beside its contact"
        key = (effector.name, body)
        if key not in self._scenes:
            self._scenes[key] = self._built(effector, body)
        found = self._scenes[key]
        if found is None:
            return None
        scene, parts = found
        scene.place({body: poses[body]})
        tool = poses[effector.tool]
        contacts = [c for part, at in parts for c in scene.against(part, tool @ at, [body])]
        deepest = max(contacts, key=lambda c: c.depth, default=None)
        if deepest is None:
            return None
        return Contact(effector.tool, body, deepest.depth, deepest.point)

    def _built(self, effector: EffectorSpec, body: str) -> tuple[CollisionScene, list[tuple[str, np.ndarray]]] | None:
        """A collision scene of the tool's parts beside the contact (each its own body, exact) and `body` grown by
        the clearance, with those parts' names and poses in the tool's frame; None without such parts."""
        assert effector.tool is not None
        shape = self.problem.bodies[effector.tool].type.shape
        if not isinstance(shape, UnionShape):
            return None
        origin = effector.frame[:3, 3]
        on = [
            bool(np.all(v.min(axis=0) - ON_PART <= origin) and np.all(origin <= v.max(axis=0) + ON_PART))
            for v in tool_parts(shape)
        ]
        if not any(on):
            return None  # a frame off every part: no part to tell the contact by
        # each part a body of its own, placed where it sits in the tool (its own shape: no IR node is made)
        beside = {
            f"{effector.tool}#beside{i}": (part.shape, part.pose.matrix())
            for i, (part, touching) in enumerate(zip(shape.parts, on, strict=True))
            if not touching
        }
        if not beside:
            return None
        acted_on = self.problem.bodies[body]
        # grown by the clearance and the tolerance: a part that touches the grown body is closer than the clearance
        scene = CollisionScene(
            {body: acted_on.type.shape, **{name: part for name, (part, _) in beside.items()}},
            margin=BESIDE_CLEARANCE + TOUCH_TOL,
            exact=beside,
            lifts={body: JOINT_LIFT} if acted_on.joint_limits is not None else None,
        )
        return scene, [(name, at) for name, (_, at) in beside.items()]
