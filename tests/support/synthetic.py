"""Synthetic trials with known ground truth, to measure inference (tests and bench/).

Each trial draws a motion (fixed, prismatic, revolute or free) with a random
axis and centre in the body frame, and an action (fixed or free), then adds
Gaussian noise to positions and orientations and replaces a fraction of the
samples by outliers. The ground truth comes back with the dataset.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.formats.trials import Trials

MOTIONS = ("fixed", "prismatic", "revolute", "free")
ACTIONS = ("fixed", "free")


@dataclass(frozen=True)
class Truth:
    """What generated one synthetic trial (axes and centre in the body frame at the first sample)."""

    motion: str
    action: str
    axis: np.ndarray | None = None
    center: np.ndarray | None = None


def synthetic_trials(
    seed: int,
    per_type: int,
    *,
    noise_p: float,
    noise_r: float,
    outliers: float = 0.02,
    samples: int = 100,
) -> tuple[Trials, list[Truth]]:
    """`per_type` trials of every (motion, action) pair, with noise (m, rad per component) and outliers."""
    rng = np.random.default_rng(seed)
    T_ro, T_ow, truths = [], [], []
    for motion in MOTIONS:
        for action in ACTIONS:
            for _ in range(per_type):
                ow, truth = _motion(rng, motion, samples)
                ro = _action(rng, action, samples)
                T_ow.append(_corrupt(rng, ow, noise_p, noise_r, outliers))
                T_ro.append(_corrupt(rng, ro, noise_p, noise_r, outliers))
                truths.append(Truth(motion=motion, action=action, axis=truth[0], center=truth[1]))
    n = len(truths)
    trials = Trials(
        body="Synthetic",
        t=np.tile(np.linspace(0.0, 2.0, samples), (n, 1)),
        T_ro=np.array(T_ro),
        T_ow=np.array(T_ow),
        contact=np.zeros((n, 3)),
        force=np.tile([1.0, 0.0, 0.0], (n, 1)),
        ok=np.ones(n, dtype=bool),
        reason=np.array([""] * n, dtype=object),
    )
    return trials, truths


def _progress(samples: int) -> np.ndarray:
    """Smooth 0 -> 1 (a push that accelerates and settles)."""
    s = np.linspace(0.0, 1.0, samples)
    return s * s * (3.0 - 2.0 * s)


def _random_pose(rng: np.random.Generator, spread: float) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = Rotation.random(random_state=rng).as_matrix()
    T[:3, 3] = rng.uniform(-spread, spread, 3)
    return T


def _unit(rng: np.random.Generator) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def _motion(rng: np.random.Generator, kind: str, samples: int) -> tuple[np.ndarray, tuple]:
    """Poses of the body in the world (samples, 4, 4) and (axis, centre) in the initial body frame."""
    T0 = _random_pose(rng, 0.5)
    s = _progress(samples)
    rel = np.tile(np.eye(4), (samples, 1, 1))
    truth: tuple = (None, None)
    if kind == "prismatic":
        axis = _unit(rng)
        rel[:, :3, 3] = np.outer(rng.uniform(0.10, 0.30) * s, axis)
        truth = (axis, None)
    elif kind == "revolute":
        axis = _unit(rng)
        center = rng.uniform(-0.3, 0.3, 3)
        center -= (center @ axis) * axis
        if np.linalg.norm(center) < 0.05:
            side = np.cross(axis, _unit(rng))
            center = 0.05 * side / np.linalg.norm(side)
        angle = np.deg2rad(rng.uniform(30.0, 90.0)) * s
        rot = Rotation.from_rotvec(np.outer(angle, axis)).as_matrix()
        rel[:, :3, :3] = rot
        rel[:, :3, 3] = center - rot @ center
        truth = (axis, center)
    elif kind == "free":
        rel = _free_path(rng, samples)
    return T0 @ rel, truth


def _free_path(rng: np.random.Generator, samples: int) -> np.ndarray:
    """A smooth 6-dof path: a curved translation and a rotation whose axis keeps changing."""
    s = np.linspace(0.0, 1.0, samples)[:, None]
    a, b, c = (rng.normal(size=3) * 0.15 for _ in range(3))
    pos = a * s + b * s**2 + c * np.sin(3.0 * s)
    w1, w2 = _unit(rng) * np.deg2rad(rng.uniform(30, 90)), _unit(rng) * np.deg2rad(rng.uniform(30, 90))
    rots = Rotation.from_rotvec(w1 * s) * Rotation.from_rotvec(w2 * s**2)
    T = np.tile(np.eye(4), (samples, 1, 1))
    T[:, :3, :3] = rots.as_matrix()
    T[:, :3, 3] = pos
    return T


def _action(rng: np.random.Generator, kind: str, samples: int) -> np.ndarray:
    """The effector in the body frame: a constant contact pose, or one that wanders freely."""
    T0 = np.eye(4)
    T0[:3, :3] = Rotation.from_euler("z", rng.uniform(-np.pi, np.pi)).as_matrix()
    T0[:3, 3] = rng.uniform(-0.15, 0.15, 3)
    if kind == "fixed":
        return np.tile(T0, (samples, 1, 1))
    return T0 @ _free_path(rng, samples)


def _corrupt(rng: np.random.Generator, T: np.ndarray, noise_p: float, noise_r: float, outliers: float) -> np.ndarray:
    T = T.copy()
    n = len(T)
    T[:, :3, 3] += rng.normal(scale=noise_p, size=(n, 3)) if noise_p > 0 else 0.0
    if noise_r > 0:
        T[:, :3, :3] = T[:, :3, :3] @ Rotation.from_rotvec(rng.normal(scale=noise_r, size=(n, 3))).as_matrix()
    bad = rng.random(n) < outliers
    if bad.any():
        k = int(bad.sum())
        T[bad, :3, 3] += rng.uniform(-0.2, 0.2, (k, 3))
        T[bad, :3, :3] = Rotation.random(k, random_state=rng).as_matrix()
    return T


def block_pushes(
    *, steps: int = 5, half_width: float = 0.08, samples: int = 60, noise_p: float = 5e-4, seed: int = 0
) -> Trials:
    """Pushes on the -x and +x faces of a 10 x 20 cm block, as exploration would record them.

    A push in the central third slides the block along the push (5 cm); one
    nearer an end turns it by 20 deg about a vertical axis through the far end
    of the face (y = -/+ 10 cm on the pushed side's opposite x face).
    """
    rng = np.random.default_rng(seed)
    T_ro, T_ow, contact, force = [], [], [], []
    for sign in (1.0, -1.0):  # push +x from the -x face, then -x from the +x face
        for y in np.linspace(-half_width, half_width, steps):
            c = np.array([-0.05 * sign, y, 0.0])
            effector = np.eye(4)
            effector[:3, :3] = Rotation.from_euler("z", 0.0 if sign > 0 else np.pi).as_matrix()
            effector[:3, 3] = c
            s = _progress(samples)
            rel = np.tile(np.eye(4), (samples, 1, 1))
            if abs(y) <= half_width / 3:
                rel[:, 0, 3] = 0.05 * sign * s
            else:
                pivot = np.array([0.05 * sign, -np.sign(y) * 0.10, 0.0])
                # Pushing +x left of the centre turns the block clockwise (axis -z), and so on.
                axis = np.array([0.0, 0.0, -np.sign(y) * sign])
                rot = Rotation.from_rotvec(np.outer(np.deg2rad(20.0) * s, axis)).as_matrix()
                rel[:, :3, :3] = rot
                rel[:, :3, 3] = pivot - rot @ pivot
            start = np.eye(4)
            start[:3, 3] = (0.45, 0.0, 0.025)
            T_ow.append(_corrupt(rng, start @ rel, noise_p, noise_p * 2, 0.0))
            T_ro.append(_corrupt(rng, np.tile(effector, (samples, 1, 1)), noise_p, noise_p * 2, 0.0))
            contact.append(c)
            force.append([sign, 0.0, 0.0])
    return _dataset("Block", samples, T_ro, T_ow, contact, force)


def wield_trials(*, samples: int = 50, noise_p: float = 5e-4, seed: int = 0) -> Trials:
    """A stick held at its handle and pushed along the 26 directions of a 3 x 3 x 3 grid.

    Each trial moves the stick 10 cm along its force (turning it a little about
    the force); the grasp stays fixed.
    """
    rng = np.random.default_rng(seed)
    grasp = np.eye(4)
    grasp[:3, 3] = (-0.15, 0.0, 0.0)
    directions = [np.array(d, dtype=float) for d in np.ndindex(3, 3, 3)]
    directions = [d - 1.0 for d in directions if np.any(d != 1.0)]
    T_ro, T_ow, force = [], [], []
    for d in directions:
        u = d / np.linalg.norm(d)
        s = _progress(samples)
        rel = np.tile(np.eye(4), (samples, 1, 1))
        rel[:, :3, 3] = np.outer(0.10 * s, u)
        rel[:, :3, :3] = Rotation.from_rotvec(np.outer(np.deg2rad(15.0) * s, u)).as_matrix()
        start = np.eye(4)
        start[:3, 3] = (0.3, 0.0, 0.3)
        T_ow.append(_corrupt(rng, start @ rel, noise_p, noise_p * 2, 0.0))
        T_ro.append(_corrupt(rng, np.tile(grasp, (samples, 1, 1)), noise_p, noise_p * 2, 0.0))
        force.append(u)
    return _dataset("Stick", samples, T_ro, T_ow, [grasp[:3, 3]] * len(T_ow), force)


def drawer_trials(*, samples: int = 60, noise_p: float = 5e-4, seed: int = 0) -> Trials:
    """A 30 cm deep drawer on a slide along x, its handle's bar 4 cm in front of its +x face.

    In order: a push on its back (-x face) that slides it 10 cm along +x; a
    push on its front that slides it 10 cm along -x; a pull with the fingertip
    behind the bar (contact at x = 19 cm, force +x) that slides it 10 cm along
    +x; the same pull against its open stop, which moves nothing.
    """
    rng = np.random.default_rng(seed)
    T_ro, T_ow, contact, force = [], [], [], []
    for x, direction, travel in ((-0.15, 1.0, 0.10), (0.15, -1.0, 0.10), (0.19, 1.0, 0.10), (0.19, 1.0, 0.0)):
        effector = np.eye(4)
        effector[:3, :3] = Rotation.from_euler("z", 0.0 if direction > 0 else np.pi).as_matrix()
        effector[:3, 3] = (x, 0.0, 0.0)
        rel = np.tile(np.eye(4), (samples, 1, 1))
        rel[:, 0, 3] = direction * travel * _progress(samples)
        start = np.eye(4)
        start[:3, 3] = (0.45, 0.0, 0.05)
        T_ow.append(_corrupt(rng, start @ rel, noise_p, noise_p * 2, 0.0))
        T_ro.append(_corrupt(rng, np.tile(effector, (samples, 1, 1)), noise_p, noise_p * 2, 0.0))
        contact.append([x, 0.0, 0.0])
        force.append([direction, 0.0, 0.0])
    return _dataset("Drawer", samples, T_ro, T_ow, contact, force)


def _dataset(body: str, samples: int, T_ro: list, T_ow: list, contact: list, force: list) -> Trials:
    """Equal-length, all-`ok` trials of `body` sampled over one second."""
    n = len(T_ow)
    return Trials(
        body=body,
        t=np.tile(np.linspace(0.0, 1.0, samples), (n, 1)),
        T_ro=np.array(T_ro),
        T_ow=np.array(T_ow),
        contact=np.array(contact),
        force=np.array(force),
        ok=np.ones(n, dtype=bool),
        reason=np.array([""] * n, dtype=object),
    )


@dataclass
class Score:
    """How inferred trials compare with their ground truth: type accuracy of both edges, and the median
    axis error (deg) and revolute centre error (m, distance to the true axis line) of correctly typed motions."""

    motion_accuracy: float
    action_accuracy: float
    axis_error_deg: float
    center_error: float


def score(results: list, truths: list[Truth]) -> Score:
    """Score `infer_trials` results against the `Truth` of each synthetic trial."""
    motion = float(np.mean([r.motion.type == t.motion for r, t in zip(results, truths)]))
    action = float(np.mean([r.action.type == t.action for r, t in zip(results, truths)]))
    axis_err, center_err = [], []
    for r, t in zip(results, truths):
        if t.axis is None or r.motion.type != t.motion:
            continue
        axis_err.append(np.degrees(np.arccos(np.clip(r.motion.params["axis"] @ t.axis, -1.0, 1.0))))
        if t.center is not None:
            d = r.motion.params["center"] - t.center
            center_err.append(np.linalg.norm(d - (d @ t.axis) * t.axis))
    return Score(motion, action, _median(axis_err), _median(center_err))


def _median(values: list) -> float:
    return float(np.median(values)) if values else float("nan")
