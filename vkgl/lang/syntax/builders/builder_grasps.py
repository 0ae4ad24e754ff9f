"""The builder's rules for grasps: `action grasp at POSE width W force F`, evidence (with its `slip`), `explore grasps`.

`GraspBuilder` holds the methods of these rules of grammar/vkg.lark; the
`Builder` (vkgl/lang/syntax/builder.py) derives from it. Units are checked
here (a width is a length, a force a force); whether a value makes sense (a
width the hand can open to, a grasp only as an action) is the checker's
question (vkgl/lang/checks/grasps.py).
"""

from __future__ import annotations

from typing import Any

from lark import Token

from vkgl.lang.ir import nodes as ir
from vkgl.lang.syntax.builders.builder_tasks import TaskBuilder
from vkgl.lang.syntax.values import Item, new_node


class GraspBuilder(TaskBuilder):
    """The IR of grasp actions and `explore grasps` policies; one method per grammar rule, as in `Builder`."""

    def grasp_at(self, meta: Any, children: list[Any]) -> ir.GraspC:
        pose, width, force = children
        width_q = self.to_quantity(width, "length")
        force_q = self.to_quantity(force, "force")
        return new_node(
            ir.GraspC,
            pose=self.to_pose(pose),
            width=width_q.value,
            force=force_q.value,
            width_unit=width_q.unit,
            force_unit=force_q.unit,
            span=self.span(meta),
        )

    def evidence(self, meta: Any, children: list[Any]) -> Item:
        trials, loglik, posterior, *slip = children
        evidence = new_node(
            ir.Evidence,
            trials=self.integer(trials, "`trials`"),
            loglik=self.number(loglik),
            posterior=self.number(posterior),
            slip=slip[0].value if slip else None,
            slip_unit=slip[0].unit if slip else "mm",
            span=self.span(meta),
        )
        return Item("evidence", evidence, self.span(meta))

    def evidence_slip(self, meta: Any, children: list[Any]) -> ir.Quantity:
        return self.to_quantity(children[0], "length")

    def explore_grasps(self, meta: Any, children: list[Any]) -> Item:
        fields = self.single(children, "explore `grasps`", {}, self.span(meta))
        approach = fields.get("approach")
        trials = fields.get("trials")
        policy = new_node(
            ir.GraspPolicy,
            approaches=None if approach is None else [str(t) for t in approach],
            approach_spans=[] if approach is None else [self.tspan(t) for t in approach],
            max_width=fields.get("max_width"),
            force=fields.get("force"),
            lift=fields.get("lift"),
            slip=fields.get("slip"),
            trials=None if trials is None else self.integer(trials, "`trials`"),
            trials_span=None if trials is None else trials.span,
            span=self.span(meta),
        )
        return Item("grasps", policy, self.span(meta))

    def grasp_approach(self, meta: Any, children: list[Token]) -> Item:
        return Item("approach", list(children), self.span(meta))

    def grasp_max_width(self, meta: Any, children: list[Any]) -> Item:
        return Item("max_width", self.to_quantity(children[0], "length"), self.span(meta))

    def grasp_force(self, meta: Any, children: list[Any]) -> Item:
        return Item("force", self.to_quantity(children[0], "force"), self.span(meta))

    def grasp_lift(self, meta: Any, children: list[Any]) -> Item:
        return Item("lift", self.to_quantity(children[0], "length"), self.span(meta))

    def grasp_slip(self, meta: Any, children: list[Any]) -> Item:
        return Item("slip", self.to_quantity(children[0], "length"), self.span(meta))

    def grasp_trials(self, meta: Any, children: list[Any]) -> Item:
        return Item("trials", children[0], self.span(meta))
