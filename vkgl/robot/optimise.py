"""The one NLopt set-up of vkgl: SLSQP over bounded variables, with constraints and a stopping rule.

IK, the ready pose and the extreme radii of the reach minimise a smooth
function of the joints with analytic gradients (from DART's Jacobian), and the
planner's task space (`vkgl.plan.task_space.feasible`) minimises the goal error
over a sequence's motion values under vector constraints; they differ only in
their functions and stopping rules.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

Objective = Callable[[np.ndarray, np.ndarray], float]
"""NLopt's calling convention: `f(q, grad)` returns the value and fills `grad` in place when it is not empty."""

Constraint = tuple[Objective, float]
"""A constraint function and its tolerance."""

VectorFunction = Callable[[np.ndarray, np.ndarray, np.ndarray], None]
"""NLopt's vector-constraint convention: `f(result, x, grad)` fills `result` (m) and, when not empty, `grad` (m x n)."""

VectorConstraint = tuple[VectorFunction, np.ndarray]
"""A vector constraint function (all components <= 0) and its per-component tolerances."""


def slsqp(
    objective: Objective,
    seed: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    *,
    max_evaluations: int,
    xtol: float,
    ftol: float | None = None,
    stop: float | None = None,
    equalities: Sequence[Constraint] = (),
    inequalities: Sequence[Constraint] = (),
    vector_inequalities: Sequence[VectorConstraint] = (),
    max_time: float | None = None,
) -> np.ndarray | None:
    """Minimise `objective` with NLopt's LD_SLSQP from `seed` within [lower, upper]: the optimum, or None.

    `equalities` hold at 0 and `inequalities` at <= 0, each within its
    tolerance (`vector_inequalities`: every component <= 0); `xtol` and `ftol`
    are absolute tolerances, `stop` a value at which to stop at once and
    `max_time` a limit in seconds. None means NLopt gave up with an error
    (round-off, a failed line search, a non-finite value, a forced stop);
    callers that want the best point seen so far track it in their objective.
    """
    import nlopt

    optimiser = nlopt.opt(nlopt.LD_SLSQP, len(seed))
    optimiser.set_lower_bounds(lower)
    optimiser.set_upper_bounds(upper)
    optimiser.set_min_objective(objective)
    for function, tolerance in equalities:
        optimiser.add_equality_constraint(function, tolerance)
    for function, tolerance in inequalities:
        optimiser.add_inequality_constraint(function, tolerance)
    for vector, tolerances in vector_inequalities:
        optimiser.add_inequality_mconstraint(vector, tolerances)
    # NLopt's defaults are left alone unless asked: each caller keeps its own stopping rule.
    if stop is not None:
        optimiser.set_stopval(stop)
    optimiser.set_maxeval(max_evaluations)
    if ftol is not None:
        optimiser.set_ftol_abs(ftol)
    optimiser.set_xtol_abs(xtol)
    if max_time is not None:
        optimiser.set_maxtime(max_time)
    try:
        return np.asarray(optimiser.optimize(np.array(seed, dtype=float)))
    except (nlopt.RoundoffLimited, nlopt.ForcedStop, nlopt.runtime_error, ValueError, RuntimeError):
        return None


__all__ = ["Constraint", "Objective", "VectorConstraint", "VectorFunction", "slsqp"]
