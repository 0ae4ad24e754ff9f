"""Semantic checks of grasps: `grasp at POSE width W force F` only as an action, with a width the hand can open
to and a positive force; `slip` in evidence 0 or more; a body's `explore grasps` policy (E460-E462, E411, E209).

NaN marks a value already reported by the builder (a wrong unit): every comparison with it is false, so it
gets no second error here.
"""

from __future__ import annotations

from vkgl.lang.checks.context import CheckContext, shown
from vkgl.lang.checks.ranges import check_count, check_quantity
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import limits
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.grasps import GRASP_APPROACHES, HAND_OPENING, NO_APPROACH

_OPENING_CM = f"{HAND_OPENING * 100:g} cm"


def check_grasp_affordance(affordance: ir.Affordance, ctx: CheckContext) -> None:
    """A grasp is an action (never a motion) with a sound width and force; a slip in the evidence is >= 0."""
    if isinstance(affordance.motion, ir.GraspC):
        ctx.error(
            codes.GRASP_NOT_ACTION,
            f"affordance `{affordance.name}`: a grasp says how the fingers hold the body, so it is an `action`, "
            "not a `motion`",
            ctx.narrow(affordance.motion.span, r"(grasp)\b"),
            "write `action grasp at ...` and say how the held body moves: `motion free` (carried in the hand) "
            "or its joint's `prismatic along ...` / `revolute about ...`",
        )
    if isinstance(affordance.action, ir.GraspC):
        _check_grasp(affordance.action, ctx)
    evidence = affordance.evidence
    if evidence is not None and evidence.slip is not None and evidence.slip < 0:
        slip = _length(evidence.slip, evidence.slip_unit)
        ctx.error(
            codes.NON_POSITIVE_VALUE,
            f"a slip is how far the body moved in the hand: 0 or more, got {slip}",
            ctx.narrow(evidence.span, r"slip\s+(\S+)"),
        )


def _check_grasp(grasp: ir.GraspC, ctx: CheckContext) -> None:
    # model_construct: the values are typed already; validating would build Quantity's validator (and scan the
    # installed packages for pydantic plugins), a tenth of a `vkgc check` whose scene has a grasp.
    width = ir.Quantity.model_construct(value=grasp.width, unit=grasp.width_unit)
    if grasp.width <= 0 or grasp.width > HAND_OPENING:
        _width_error(width, "a grasp's width", ctx.narrow(grasp.span, r"width\s+(\S+)"), ctx)
    force_span = ctx.narrow(grasp.span, r"force\s+(\S+)")
    force = ir.Quantity.model_construct(value=grasp.force, unit=grasp.force_unit, span=force_span)
    if grasp.force <= 0:
        ctx.error(
            codes.NON_POSITIVE_VALUE,
            f"a grasp's force is how hard the fingers close: it must be positive, got {shown(force)}",
            force.span,
        )
    check_quantity(force, "a grasp's force", limits.FORCE, ctx)


def _width_error(width: ir.Quantity, what: str, span: ir.Span | None, ctx: CheckContext) -> None:
    if width.value <= 0:
        problem = "it must be positive"
    else:
        problem = f"the hand opens at most {_OPENING_CM} (4 cm per finger)"
    ctx.error(
        codes.GRASP_WIDTH_OUT_OF_HAND,
        f"{what} is an opening across the finger pads: {problem}, got {shown(width)}",
        span,
        f"a body wider than {_OPENING_CM} cannot be held there: grasp it across a narrower part"
        if width.value > 0
        else "",
    )


def check_grasp_policy(policy: ir.GraspPolicy, ctx: CheckContext) -> None:
    """`explore grasps`: known approaches (`none` alone), a max width the hand opens to, positive values."""
    if policy.approaches is not None:
        _check_approaches(policy, ctx)
    if policy.max_width is not None and (policy.max_width.value <= 0 or policy.max_width.value > HAND_OPENING):
        _width_error(policy.max_width, "`max_width`", policy.max_width.span, ctx)
    for word, q, limit in (
        ("force", policy.force, limits.FORCE),
        ("lift", policy.lift, limits.SIZE),
        ("slip", policy.slip, limits.SIZE),
    ):
        if q is not None and q.value <= 0:
            ctx.error(
                codes.NON_POSITIVE_VALUE, f"`{word}` in `explore grasps` must be positive, got {shown(q)}", q.span
            )
        check_quantity(q, f"`{word}` in `explore grasps`", limit, ctx)
    if policy.trials is not None and policy.trials < 1:
        ctx.error(codes.NON_POSITIVE_VALUE, f"`trials` must be at least 1, got {policy.trials}", policy.trials_span)
    span = ctx.narrow(policy.trials_span, r"trials\s+(\S+)")
    check_count(policy.trials, "`trials` in `explore grasps`", limits.GRASP_TRIALS, span, ctx)


def _check_approaches(policy: ir.GraspPolicy, ctx: CheckContext) -> None:
    words = policy.approaches or []
    spans: list[ir.Span | None] = list(policy.approach_spans) or [policy.span] * len(words)
    known = ", ".join(f"`{a}`" for a in GRASP_APPROACHES)
    for word, span in zip(words, spans, strict=False):
        if word not in (*GRASP_APPROACHES, NO_APPROACH):
            ctx.error(
                codes.UNKNOWN_APPROACH,
                f"unknown grasp approach `{word}`",
                span,
                f"approaches are {known}, or `{NO_APPROACH}` alone for no grasps",
            )
    if NO_APPROACH in words and len(words) > 1:
        ctx.error(
            codes.UNKNOWN_APPROACH,
            f"`approach {NO_APPROACH}` learns no grasps: it cannot be listed with other approaches",
            spans[words.index(NO_APPROACH)],
            f"write `approach {NO_APPROACH}` alone, or leave it out",
        )


def _length(value: float, unit: str) -> str:
    return shown(ir.Quantity(value=value, unit=unit))
