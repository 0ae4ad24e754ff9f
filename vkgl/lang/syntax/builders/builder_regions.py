"""The builder's rules for regions: `region NAME = ...` in a scene, `goal B in R` and `keep [B] out [of] R` in a task.

A region is a box, `(x0, y0) to (x1, y1) UNIT`, or a polygon, `polygon (x, y),
(x, y), ... UNIT`; the unit after the last corner also applies to corners
written without one (as a motion's `range 0 to 24 cm`). Whether the corners
make a region (not swapped, a convex polygon) is the checker's question
(vkgl/lang/checks/geometry/regions.py).
"""

from __future__ import annotations

import dataclasses
from typing import Any

from lark import Token

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.regions import KeepOut, Region
from vkgl.lang.syntax.values import Item, RawQ, RawVec, ValueReader, new_node

POSITION_TOLERANCE_NOTE = (
    "`within` gives the position's tolerance first, then the heading's: `within 1 cm, 3 deg` "
    "(a goal without a tolerance uses 1 cm and 3 deg)"
)
"""E201's note for an angle where a goal's position tolerance stands (`within 3 deg` meant for the yaw alone)."""


class RegionBuilder(ValueReader):
    """The IR of regions and region goals; one method per grammar rule, as in `Builder`."""

    def scene_region(self, meta: Any, children: list[Any]) -> Region:
        name, region = children
        return region.model_copy(update={"name": str(name), "name_span": self.tspan(name), "span": self.span(meta)})

    def region_box(self, meta: Any, children: list[RawVec]) -> Region:
        corners = self._corners(children, "a region's corner")
        return new_node(Region, kind="box", corners=corners, span=self.span(meta))

    def region_polygon(self, meta: Any, children: list[RawVec]) -> Region:
        corners = self._corners(children, "a polygon's vertex")
        return new_node(Region, kind="polygon", corners=corners, span=self.span(meta))

    def _corners(self, raws: list[RawVec], what: str) -> list[ir.Vector]:
        """Each corner as a 2-vector of lengths; the last corner's unit applies to those written without one."""
        last = raws[-1].unit
        shared = [
            r if r.unit is not None or any(c.unit for c in r.components) else dataclasses.replace(r, unit=last)
            for r in raws
        ]
        return [self.to_vector(r, "length", (2,), what) for r in shared]

    def region_inline(self, meta: Any, children: list[Region]) -> Region:
        return children[0]

    def region_name(self, meta: Any, children: list[Token]) -> ir.Ref:
        return new_node(ir.Ref, name=str(children[0]), span=self.tspan(children[0]))

    def task_keep_out(self, meta: Any, children: list[Any]) -> Item:
        return Item("keep", self._keep_out(None, children[0], meta), self.span(meta))

    def task_keep_body_out(self, meta: Any, children: list[Any]) -> Item:
        body = new_node(ir.Ref, name=str(children[0]), span=self.tspan(children[0]))
        return Item("keep", self._keep_out(body, children[1], meta), self.span(meta))

    def _keep_out(self, body: ir.Ref | None, place: Region | ir.Ref, meta: Any) -> KeepOut:
        region = place if isinstance(place, Region) else None
        ref = place if isinstance(place, ir.Ref) else None
        return new_node(KeepOut, body=body, region=region, region_ref=ref, span=self.span(meta))

    def goal_in(self, meta: Any, children: list[Any]) -> ir.Goal:
        """`B in R [yaw Q] [within L[, A]]`: the body's footprint inside region R (in place, or the scene's)."""
        body, place = children[0], children[1]
        rest = children[2:]
        yaw = self.to_quantity(rest.pop(0), "angle") if rest and isinstance(rest[0], RawQ) else None
        tolerances: list[RawQ] = rest[0] if rest else []
        return new_node(
            ir.Goal,
            body=new_node(ir.Ref, name=str(body), span=self.tspan(body)),
            region=place if isinstance(place, Region) else None,
            region_ref=place if isinstance(place, ir.Ref) else None,
            yaw=yaw,
            tol_position=self.to_quantity(tolerances[0], "length", POSITION_TOLERANCE_NOTE) if tolerances else None,
            tol_yaw=self.to_quantity(tolerances[1], "angle") if len(tolerances) > 1 else None,
            span=self.span(meta),
        )


__all__ = ["RegionBuilder"]
