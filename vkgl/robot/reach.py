"""The reachable workspace: at a height, the radial interval in which the effector can be held hand-down.

"Hand-down" means the effector frame's z axis points up (yaw free: the rotation
about it, like a round fingertip's, does not matter). Heights and radii here
are in the chain's root frame; `Arm.reach` converts from the world.
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.formats import reach_cache
from vkgl.robot.ik import MAX_EVALUATIONS, HandDownSolver, InverseKinematics
from vkgl.robot.optimise import slsqp
from vkgl.robot.pose_error import ANGLE_TOL, POSITION_TOL, angle_error, orientation_residual

REACH_PRECISION = 1e-3
"""m: `reach` keeps this far inside the extreme radii, and its bisections stop at this width."""

REACH_SEEDS = 4
"""Random seeds (after `home`) of each optimisation of an extreme radius in `reach`."""

REACH_AZIMUTHS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0, -135.0, -90.0, -45.0)
"""Directions (deg about the base's z axis, from its x axis) at which `reach` checks its interval by IK."""

_REACH_CACHE: dict[tuple[Any, ...], tuple[float, float]] = {}
_DISK_KEYS: dict[tuple[Any, ...], str] = {}  # per model: its key in the reach cache on disk, once loaded

_REACH_SOURCES = ("reach.py", "ik.py", "optimise.py", "pose_error.py", "kinematics.py", "ready_pose.py")
"""The modules whose code decides a reach: a change to any of them makes the kept values stale."""


def cached_reach(ik: InverseKinematics, model: tuple[Any, ...], height: float) -> tuple[float, float]:
    """`reach(ik, height)`, computed once for each `model` key (URDF, link, offset) and height: kept for the
    process, and between processes in the user's cache folder (`vkgl.formats.reach_cache`)."""
    key = (*model, height)
    if key not in _REACH_CACHE:
        disk_key = _loaded_disk_key(model)
        if key not in _REACH_CACHE:
            _REACH_CACHE[key] = reach(ik, height)
            reach_cache.store(disk_key, height, _REACH_CACHE[key])
    return _REACH_CACHE[key]


def _loaded_disk_key(model: tuple[Any, ...]) -> str:
    """`model`'s key in the reach cache on disk; the first time, what is kept under it joins the process's."""
    found = _DISK_KEYS.get(model)
    if found is None:
        found = _DISK_KEYS[model] = _disk_key(model)
        for height, interval in reach_cache.load(found).items():
            _REACH_CACHE.setdefault((*model, height), interval)
    return found


def _disk_key(model: tuple[Any, ...]) -> str:
    """A digest of everything a reach depends on: the URDF's bytes, the effector link and offset, the code."""
    digest = hashlib.sha256()
    urdf, *rest = model
    try:
        digest.update(Path(urdf).read_bytes())
    except OSError:
        digest.update(str(urdf).encode())
    for part in rest:
        digest.update(part if isinstance(part, bytes) else repr(part).encode())
    here = Path(__file__).resolve().parent
    for name in _REACH_SOURCES:
        digest.update((here / name).read_bytes())
    return digest.hexdigest()


_AT_HEIGHT: dict[tuple[Any, ...], tuple[float, float]] = {}


def reach_at(ik: InverseKinematics, model: tuple[Any, ...], base_z: float, height: float) -> tuple[float, float]:
    """`cached_reach` at the world `height` above a base at `base_z` (rounded to the mm), remembered per exact
    height: the planner asks about the same few heights thousands of times, and rounding costs more than a look-up."""
    key = (*model, base_z, height)
    found = _AT_HEIGHT.get(key)
    if found is None:
        if len(_AT_HEIGHT) >= 65536:
            _AT_HEIGHT.clear()
        found = _AT_HEIGHT[key] = cached_reach(ik, model, round(height - base_z, 3))
    return found


def clear_reach_cache() -> None:
    """Forget every reach computed so far in this process (for benchmarks that time the first computation;
    with the cache on disk off, `VKGL_CACHE_DIR=off`, they are computed again)."""
    _REACH_CACHE.clear()
    _AT_HEIGHT.clear()
    _DISK_KEYS.clear()


def reach(ik: InverseKinematics, height: float) -> tuple[float, float]:
    """(r_min, r_max) hand-down at root-frame `height`: extreme radii by optimisation, checked by IK all around.

    The extreme radii come from constrained optimisations (each moved
    REACH_PRECISION inward); at every azimuth of REACH_AZIMUTHS_DEG IK must
    reach both ends, else the interval is cut to the one found by bisection
    along that azimuth. (0.0, 0.0) means nowhere at that height.
    """
    inner, outer = extreme_radius(ik, height, largest=False), extreme_radius(ik, height, largest=True)
    if inner is None or outer is None:
        return (0.0, 0.0)
    interval: tuple[float, float] | None = (inner[0] + REACH_PRECISION, outer[0] - REACH_PRECISION)
    solved: tuple[np.ndarray, np.ndarray] | None = None  # the IK solutions at both ends, at the last azimuth
    for azimuth in (math.radians(a) for a in REACH_AZIMUTHS_DEG):
        if interval is None or interval[0] >= interval[1]:
            return (0.0, 0.0)
        interval, solved = _confirmed_interval(ik, height, azimuth, interval, (inner[1], outer[1]), solved)
    return (0.0, 0.0) if interval is None else interval


def extreme_radius(ik: InverseKinematics, height: float, *, largest: bool) -> tuple[float, np.ndarray] | None:
    """The largest (smallest) distance from the root's z axis of a hand-down effector at `height`, with its joints.

    NLopt SLSQP maximises (minimises) x^2 + y^2 of the effector subject to
    its height and its z axis pointing up, from `home` and a few fixed random
    seeds; the best feasible optimum wins. None when no run is feasible.
    """
    chain = ik.chain
    sign = -1.0 if largest else 1.0
    kinematics = chain.at_last_q()  # NLopt asks the objective and both constraints at each point
    up = np.eye(3)

    def radius_squared(q: np.ndarray, grad: np.ndarray) -> float:
        pose, jac = kinematics(q)
        x, y = pose[0, 3], pose[1, 3]
        if grad.size:
            grad[:] = sign * 2.0 * (x * jac[3] + y * jac[4])
        return sign * (x * x + y * y)

    def at_height(q: np.ndarray, grad: np.ndarray) -> float:
        pose, jac = kinematics(q)
        if grad.size:
            grad[:] = jac[5]
        return float(pose[2, 3] - height)

    def upright(q: np.ndarray, grad: np.ndarray) -> float:
        pose, jac = kinematics(q)
        residual, direction = orientation_residual(pose[:3, :3], up, yaw_free=True)
        if grad.size:
            grad[:] = jac[:3].T @ direction
        # the residual is never negative: <= 0 means within 1e-10 of upright (about 1e-5 rad)
        return residual - 1e-10

    best: tuple[float, np.ndarray] | None = None
    for seed in (ik.home, *ik.random_seeds[:REACH_SEEDS]):
        q = slsqp(
            radius_squared,
            seed,
            chain.lower,
            chain.upper,
            max_evaluations=MAX_EVALUATIONS,
            xtol=1e-9,
            equalities=[(at_height, 1e-7)],
            inequalities=[(upright, 0.0)],
        )
        if q is None:
            continue
        pose = chain.pose_and_jacobian(q)[0]
        # a tenth of IK's tolerances: only clearly feasible optima may bound the interval
        if abs(pose[2, 3] - height) > POSITION_TOL / 10 or angle_error(pose, np.eye(4), True) > ANGLE_TOL / 10:
            continue
        radius = math.hypot(pose[0, 3], pose[1, 3])
        if best is None or (radius > best[0] if largest else radius < best[0]):
            best = (radius, q)
    return best


def radial_interval(ik: InverseKinematics, height: float, azimuth: float) -> tuple[float, float] | None:
    """The reachable radii (min, max) hand-down at root-frame `height` along `azimuth` (rad), or None.

    Bisection to REACH_PRECISION between a reachable radius and the chain's
    length (outward) and the axis (inward); each IK starts from the solution
    at the nearest reachable radius so far.
    """
    horizontal = ik.radius**2 - (height - ik.anchor[2]) ** 2
    if horizontal <= 0:
        return None
    limit = math.sqrt(horizontal) + math.hypot(ik.anchor[0], ik.anchor[1])
    solve = ik.hand_down_solver(height, azimuth)
    # start in the middle of the possible radii, where a reachable one is likeliest
    for radius in limit * np.array([0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8]):
        q = solve(radius, [], True)
        if q is not None:
            break
    else:
        return None
    r_max = _bisect_edge(solve, radius, q, limit)
    r_min = _bisect_edge(solve, radius, q, 0.0)
    return (r_min, r_max)


def _confirmed_interval(
    ik: InverseKinematics,
    height: float,
    azimuth: float,
    interval: tuple[float, float],
    extremes: tuple[np.ndarray, np.ndarray],
    solved: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[tuple[float, float] | None, tuple[np.ndarray, np.ndarray] | None]:
    """`interval` if IK reaches both its ends along `azimuth`, else its intersection with the bisected one there;
    and the IK solutions at both ends when it reached them (None otherwise).

    The IK of each end starts from the solution at the previous azimuth (`solved`), then from the extreme
    configuration, each turned by the first joint to face `azimuth` when the joint's limits allow. A turned
    solution usually solves at once: an arm whose first joint turns it about the vertical reaches the same
    radius at every azimuth with the same other joints.
    """
    solve = ik.hand_down_solver(height, azimuth)
    starts = [extremes] if solved is None else [solved, extremes]
    inner = [seed for pair in starts for seed in _turned_toward(ik, pair[0], azimuth)]
    outer = [seed for pair in starts for seed in _turned_toward(ik, pair[1], azimuth)]
    q_outer = solve(interval[1], outer, True)
    q_inner = None if q_outer is None else solve(interval[0], inner, True)
    if q_outer is not None and q_inner is not None:
        return interval, (q_inner, q_outer)
    here = radial_interval(ik, height, azimuth)
    if here is None or max(interval[0], here[0]) >= min(interval[1], here[1]):
        return None, None
    return (max(interval[0], here[0]), min(interval[1], here[1])), None


def _turned_toward(ik: InverseKinematics, q: np.ndarray, azimuth: float) -> list[np.ndarray]:
    """`q` with the first joint turned so that the effector faces `azimuth`, as seeds (none beyond limits)."""
    point = ik.chain.pose_and_jacobian(q)[0][:3, 3]
    turned = q.copy()
    turned[0] += (azimuth - math.atan2(point[1], point[0]) + math.pi) % (2 * math.pi) - math.pi
    return [turned] if ik.chain.lower[0] <= turned[0] <= ik.chain.upper[0] else []


def _bisect_edge(solve: HandDownSolver, inside: float, q: np.ndarray, outside: float) -> float:
    """The reachable radius closest to `outside`, by bisection from the reachable `inside` (solution `q`)."""
    if solve(outside, [q], False) is not None:
        return outside
    while abs(outside - inside) > REACH_PRECISION:
        middle = (inside + outside) / 2
        found = solve(middle, [q], False)
        if found is None:
            outside = middle
        else:
            inside, q = middle, found
    return float(inside)


__all__ = [
    "REACH_AZIMUTHS_DEG",
    "REACH_PRECISION",
    "REACH_SEEDS",
    "cached_reach",
    "clear_reach_cache",
    "extreme_radius",
    "radial_interval",
    "reach",
    "reach_at",
]
