"""The shared NLopt SLSQP set-up."""

from __future__ import annotations

import numpy as np

from vkgl.robot.optimise import Objective, slsqp


def squared_distance_to(point: np.ndarray) -> Objective:
    """The squared distance to `point`, as an NLopt objective."""

    def f(q: np.ndarray, grad: np.ndarray) -> float:
        if grad.size:
            grad[:] = 2.0 * (q - point)
        return float((q - point) @ (q - point))

    return f


def test_slsqp_minimises_within_the_bounds() -> None:
    lower, upper = np.array([-1.0, -1.0]), np.array([1.0, 0.5])
    q = slsqp(squared_distance_to(np.array([0.3, 2.0])), np.zeros(2), lower, upper, max_evaluations=100, xtol=1e-10)
    assert q is not None
    np.testing.assert_allclose(q, [0.3, 0.5], atol=1e-6)


def test_slsqp_honours_equality_and_inequality_constraints() -> None:
    def on_circle(q: np.ndarray, grad: np.ndarray) -> float:  # |q| = 1
        if grad.size:
            grad[:] = 2.0 * q
        return float(q @ q - 1.0)

    def narrow(q: np.ndarray, grad: np.ndarray) -> float:  # |x| <= 0.2
        if grad.size:
            grad[:] = [2.0 * q[0], 0.0]
        return float(q[0] ** 2 - 0.04)

    bounds = -5.0 * np.ones(2), 5.0 * np.ones(2)
    towards = squared_distance_to(np.array([1.0, 1.0]))
    q = slsqp(towards, np.array([0.5, 0.5]), *bounds, max_evaluations=200, xtol=1e-9, equalities=[(on_circle, 1e-9)])
    assert q is not None
    np.testing.assert_allclose(q, [0.5**0.5, 0.5**0.5], atol=1e-6)
    q = slsqp(
        towards,
        np.array([0.5, 0.5]),
        *bounds,
        max_evaluations=200,
        xtol=1e-9,
        equalities=[(on_circle, 1e-9)],
        inequalities=[(narrow, 0.0)],
    )
    assert q is not None
    np.testing.assert_allclose(q, [0.2, 0.96**0.5], atol=1e-6)


def test_slsqp_says_none_when_nlopt_fails() -> None:
    def broken(q: np.ndarray, grad: np.ndarray) -> float:
        raise ValueError("no value here")

    assert slsqp(broken, np.zeros(2), -np.ones(2), np.ones(2), max_evaluations=10, xtol=1e-6) is None
