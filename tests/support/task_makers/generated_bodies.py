"""The body types of the generated tasks (`generated_tasks`): six boxes nobody tuned for, the stdlib Block, and
the tools; each writes its own `body` declaration and knows the key of its learned affordances."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

LEARNED_MODULES = "+families+arcs"
"""What inference writes into modules beyond its report (part of the cache key): `family` lines, their `arc`s."""
SLIDE_SECONDS = 17  # s of the generated bodies' `explore slides` trials: the stdlib Block's (it slides 49 cm)
TWO_FACES = ("+x", "-x")
"""The faces the stdlib Block is explored on, and the generated bodies by default: a blocker slides along x only."""
FOUR_FACES = ("+x", "-x", "+y", "-y")
"""Every side face, as a user exploring a cube or a crate pushes it: a blocker can also be pushed sideways."""


@dataclass(frozen=True)
class BodyType:
    """A box body (or a stdlib body): its name, kind, size (m, x y z) and density (kg/m^3)."""

    name: str
    kind: str
    size: tuple[float, float, float]
    density: float = 500.0
    stdlib: bool = False
    parts: tuple[tuple[float, float, float, float], ...] = ()  # (cx, cy, sx, sy) boxes of a union, body frame
    long_slides: bool = True  # explored with the long `slides` pushes too; False: the short push grid only
    slide_steps: int = 1  # points per face of the long `slides` pushes: 1, the centre; 5 adds pulls off it
    faces: tuple[str, ...] = TWO_FACES  # the side faces both explore blocks push on (`FOUR_FACES`: all four)

    @property
    def mass(self) -> float:
        """kg, from the density (rounded to grams)."""
        return round(self.density * self.size[0] * self.size[1] * self.size[2], 3)

    @property
    def size_class(self) -> str:
        """`low` (height up to 6 cm), `mid` (up to 15 cm) or `tall`."""
        height = self.size[2]
        return "low" if height <= 0.06 + 1e-9 else "mid" if height <= 0.15 + 1e-9 else "tall"

    def rects(self) -> tuple[tuple[float, float, float, float], ...]:
        """The footprint as (cx, cy, sx, sy) rectangles in the body frame."""
        return self.parts or ((0.0, 0.0, self.size[0], self.size[1]),)

    def source(self) -> str:
        """The `body` declaration (generated types only)."""
        x, y, z = (num(v * 100) for v in self.size)
        faces = ", ".join(self.faces)
        return (
            f"body {self.name} {{\n"
            f"    shape box ({x}, {y}, {z}) cm\n"
            f"    mass {num(self.mass)} kg\n"
            f"    friction 0.5\n"
            f"    explore pushes {{\n"
            f"        contacts on faces {faces} steps 9\n"
            f"        force normal 1 N\n"
            f"        duration 3 s\n"
            f"    }}\n"
            + (
                f"    explore slides {{\n"
                f"        contacts on faces {faces} steps {self.slide_steps}\n"
                f"        force normal 1 N\n"
                f"        duration {num(SLIDE_SECONDS)} s\n"
                f"    }}\n"
                if self.long_slides
                else ""
            )
            + "}\n"
        )

    def source_hash(self) -> str:
        """The key of the learned-affordance cache: a hash of the body's source, of what inference writes and of
        the physics it was explored in.

        `INFER_REPORT_FORMAT` changes with what inference writes (version 2:
        `range ... open`), `INFERENCE_REVISION` with what it makes of the same
        trials, `LEARNED_MODULES` with what it writes into modules only (`family` lines), and
        `PHYSICS_REVISION` with what the DART worlds simulate (revision 2: the friction cone), so a cache
        learned by an older inference or under other physics is not reused.
        """
        from vkgl.formats.infer_report import INFER_REPORT_FORMAT
        from vkgl.infer.library import INFERENCE_REVISION
        from vkgl.sim.world import PHYSICS_REVISION

        key = f"{self.source()}{INFER_REPORT_FORMAT}{LEARNED_MODULES} inference {INFERENCE_REVISION}{PHYSICS_REVISION}"
        return hashlib.sha256(key.encode()).hexdigest()[:16]


GENERATED_TYPES = (
    BodyType("CubeS", "cube", (0.08, 0.08, 0.08)),
    BodyType("CubeM", "cube", (0.12, 0.12, 0.12)),
    BodyType("SlabN", "slab", (0.12, 0.24, 0.05)),
    BodyType("SlabW", "slab", (0.16, 0.30, 0.06)),
    BodyType("CrateM", "crate", (0.20, 0.30, 0.18), density=150.0),
    BodyType("CrateT", "crate", (0.16, 0.24, 0.25), density=150.0),
)
BLOCK = BodyType("Block", "block", (0.10, 0.20, 0.05), stdlib=True)
STICK = BodyType("Stick", "stick", (0.40, 0.02, 0.02), stdlib=True)
HOOK = BodyType(
    "Hook", "hook", (0.40, 0.16, 0.02), stdlib=True, parts=((0.0, 0.0, 0.40, 0.02), (0.19, 0.07, 0.02, 0.16))
)
MOVABLE_TYPES = (*GENERATED_TYPES, BLOCK)
TYPES = {t.name: t for t in (*MOVABLE_TYPES, STICK, HOOK)}
TOOLS = (("stick", STICK, 0.3, -0.4, 0.0), ("hook", HOOK, 0.3, 0.4, 0.0))


def num(value: float) -> str:
    """A number as the files write it: no trailing zeros."""
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text
