"""The builder's rule for a family of contacts: `family along DIR from LO to HI UNIT [drift VEC] [arc ...] [sigma Q]`.

The unit after the upper bound also applies to a lower bound written without
one (as a motion's `range 0 to 24 cm`). `sigma` is a length (the spread of a
turn's pivot) or an angle (the spread of a slide's direction): which one the
motion wants is the checker's question (vkgl/lang/checks/families.py), as are
the band, the direction and the drift.
"""

from __future__ import annotations

from typing import Any

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import dimension_of
from vkgl.lang.syntax.values import INVALID, Item, RawQ, RawVec, ValueReader, new_node


class FamilyBuilder(ValueReader):
    """The IR of `family` lines; one method per grammar rule, as in `Builder`."""

    def family(self, meta: Any, children: list[Any]) -> Item:
        along, lower, upper, *rest = children
        high = self.to_quantity(upper, "length")
        if lower.unit:
            low = self.to_quantity(lower, "length")
        elif high.value == high.value:  # `-4 to 4 cm`: the upper bound's unit is the lower's too
            low = self.to_quantity(RawQ(lower.text, upper.unit, lower.span, lower.written), "length")
        else:  # the upper bound's unit was reported; one error is enough
            low = new_node(ir.Quantity, value=INVALID, unit=high.unit, span=lower.span)
        fields = dict(rest)
        family = new_node(
            ir.Family,
            along=self.to_vector(along, "number", (3,), "a family's direction"),
            lower=low,
            upper=high,
            drift=fields.get("drift"),
            arc=fields.get("arc"),
            sigma=fields.get("sigma"),
            span=self.span(meta),
        )
        return Item("family", family, self.span(meta))

    def family_drift(self, meta: Any, children: list[RawVec]) -> tuple[str, ir.Vector]:
        return "drift", self.to_vector(children[0], "number", (3,), "a family's drift")

    def family_arc(self, meta: Any, children: list[RawQ]) -> tuple[str, ir.Arc]:
        lever, bias, ahead, *beyond = (self.to_quantity(raw, "length") for raw in children)
        return "arc", new_node(
            ir.Arc, lever=lever, bias=bias, ahead=ahead, beyond=beyond[0] if beyond else None, span=self.span(meta)
        )

    def family_sigma(self, meta: Any, children: list[RawQ]) -> tuple[str, ir.Quantity]:
        raw = children[0]
        dimension = "angle" if raw.unit and dimension_of(raw.unit) == "angle" else "length"
        return "sigma", self.to_quantity(raw, dimension, note="a turn's sigma is a length, a slide's an angle")
