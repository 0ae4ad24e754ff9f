"""The revolute model: a rotation about a fixed axis line, p = c + Rot(a, q) d, R = Rot(a, q) R0.

Closed form first: with observed orientations, the axis is the common axis of
the rotations and the centre the one that makes positions turn with them
(linear least squares, p_t = c + Q_t d); from positions alone, an algebraic
circle in the best-fit plane. Then `refine_revolute`: a geometric circle fit
in 3-d by scipy least squares with a robust loss, tied to the orientations
when they were observed. Angles increase in the direction the motion went
(right-hand rule about the axis).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from vkgl.infer.data import EdgeData
from vkgl.infer.geom import angles_about, cross, excursion, perpendicular, weighted_pca, wrap_angle
from vkgl.infer.likelihood import ModelFit, reweighted, score_fit

_INFORMATIVE = 2.5  # a spread counts as motion when it exceeds this many noise sigmas
_REFINE_MIN_INLIERS = 0.3  # refine a circle only if its closed form explains this fraction of samples
_REFINE_MIN_ANGLE = np.deg2rad(5.0)  # ... and, from positions alone, if its arc spans this much
_JUMP_R = 5.0  # an orientation this many sigmas off the rotation axis' family is an outlier


def fit_revolute(data: EdgeData, w: np.ndarray) -> ModelFit:
    """The closed-form revolute fit; `refine_revolute` improves it by least squares."""
    rot_axis, _, _ = _rotation_axis(data, w)
    mean, vals, vecs = weighted_pca(data.p, w)
    moving = _positions_move(data, vals)
    if not moving:
        if rot_axis is not None:
            return _revolute_states(data, w, _center_from_rotations(data, w, rot_axis), rot_axis, moving)
        return _revolute_states(data, w, mean, vecs[:, 0], moving)
    if rot_axis is not None:
        # The centre that makes positions turn with the orientations (the circle
        # through the positions alone may bulge the wrong way on a short arc).
        lines = [(_center_from_rotations(data, w, rot_axis), rot_axis)]
    else:
        # Positions alone leave a choice of plane when the path is nearly straight
        # (the flattest plane is not always the arc's).
        lines = [_circle_in_plane(data.p, w, mean, normal) for normal in (vecs[:, 0], vecs[:, 1])]
    candidates = []
    for center, axis in lines:
        fit = _revolute_states(data, w, center, axis, moving)
        score_fit(fit, data)
        candidates.append(fit)
    return max(candidates, key=lambda f: f.loglik)


def refine_revolute(fit: ModelFit, data: EdgeData) -> ModelFit:
    """The revolute fit refined by robust least squares (circle + orientations); the better of the two.

    Skipped (the fit comes back as is) when the closed form is no circle at all
    or, from positions alone, a barely bent line whose curvature is not resolved.
    """
    if fit.inliers.sum() < _REFINE_MIN_INLIERS * data.n:
        return fit
    w = reweighted(fit, fit.inliers)
    rot_axis, rot_spread, rot_angles = _rotation_axis(data, w)
    _mean, vals, _vecs = weighted_pca(data.p, w)
    if not _positions_move(data, vals) or (rot_axis is None and np.ptp(fit.states) < _REFINE_MIN_ANGLE):
        return fit
    orientations = None
    if rot_axis is not None:
        axis_sigma = _axis_sigma(data, rot_spread)
        orientations = _Orientations(rot_axis, axis_sigma, data.rot_index, rot_angles, data.sigma_r)
    center, axis = fit.params["center"], fit.params["axis"]
    if rot_axis is not None and axis @ rot_axis < 0:
        axis = -axis  # the orientation angles are measured about rot_axis
    refined = _revolute_states(data, w, *_refine_circle(data.p, w, data.sigma_p, center, axis, orientations), True)
    score_fit(refined, data)
    # Least squares minimises a robust loss on the geometry; keep it only if the likelihood agrees.
    if refined.loglik >= fit.loglik:
        refined.independence = fit.independence
        return refined
    return fit


def _positions_move(data: EdgeData, pca_values: np.ndarray) -> bool:
    """Whether the positions spread beyond their measurement noise."""
    return bool(np.sqrt(max(pca_values[-1], 0.0)) > _INFORMATIVE * data.noise_p)


def _revolute_states(data: EdgeData, w: np.ndarray, center: np.ndarray, axis: np.ndarray, moving: bool) -> ModelFit:
    """States (angles) and predictions of a revolute joint with a known axis line."""
    q = data.p - center
    height = q @ axis
    q_perp = q - height[:, None] * axis
    rho = np.linalg.norm(q_perp, axis=1)
    radius = float(np.sum(w * rho) / max(np.sum(w), 1e-12))
    e1 = q_perp[0] / rho[0] if rho[0] > 1e-12 else perpendicular(axis)
    theta_pos = np.unwrap(np.arctan2(q_perp @ cross(axis, e1), q_perp @ e1))
    use_pos = moving and radius > 1e-9
    theta, R_ref = _combine_angles(data, w, axis, theta_pos if use_pos else None, radius)
    axis, theta = _orient_angles(axis, theta, w)
    h = float(np.sum(w * height) / max(np.sum(w), 1e-12))
    rot = Rotation.from_rotvec(theta[:, None] * axis)
    ref = radius * e1
    pred_p = center + h * axis + rot.apply(ref)
    pred_rot = rot * R_ref
    theta0 = theta[0]
    return ModelFit(
        type="revolute",
        params={"axis": axis, "center": center + h * axis, "radius": radius},
        states=theta - theta0,
        pred_p=pred_p,
        pred_rot=pred_rot,
        n_params=6 + 3 * data.any_rot,
        state_dof=float(data.n),
    )


def _combine_angles(
    data: EdgeData, w: np.ndarray, axis: np.ndarray, theta_pos: np.ndarray | None, radius: float
) -> tuple[np.ndarray, Rotation]:
    """Per-sample angle from positions and orientations, weighted by what each tells; and R at angle 0."""
    n = data.n
    if not data.any_rot:
        return (theta_pos if theta_pos is not None else np.zeros(n)), Rotation.identity()
    idx = data.rot_index
    rots = data.observed_rotations
    if theta_pos is not None:
        guess = theta_pos[idx]
    else:
        first = rots[0]
        guess = np.unwrap((rots * first.inv()).as_rotvec() @ axis)
    R_ref = _unrotate_mean(rots, axis, guess, w[idx])
    theta_rot = (rots * R_ref.inv()).as_rotvec() @ axis
    if theta_pos is None:
        theta = np.zeros(n)
        theta[idx] = np.unwrap(theta_rot)
        missing = np.flatnonzero(~data.has_rot)
        theta[missing] = np.interp(missing, idx, theta[idx])
        return theta, R_ref
    theta = theta_pos.copy()
    w_pos = (radius / data.sigma_p) ** 2
    w_rot = 1.0 / data.sigma_r**2
    # Bring each orientation angle next to its position angle before averaging (no 2 pi jumps).
    near = theta_pos[idx] + (theta_rot - theta_pos[idx] + np.pi) % (2 * np.pi) - np.pi
    theta[idx] = (w_pos * theta_pos[idx] + w_rot * near) / (w_pos + w_rot)
    return theta, R_ref


def _unrotate_mean(rots: Rotation, axis: np.ndarray, theta: np.ndarray, w: np.ndarray) -> Rotation:
    """The mean of Rot(axis, -theta_t) R_t: the orientation at angle 0."""
    back = Rotation.from_rotvec(-theta[:, None] * axis) * rots
    return back.mean(weights=np.maximum(w, 1e-9))


def _orient_angles(axis: np.ndarray, theta: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Axis and angles flipped if need be so that the angle grows the way the body turned."""
    if excursion(theta - theta[0], w) < 0:
        return -axis, -theta
    return axis, theta


def _circle_in_plane(
    p: np.ndarray, w: np.ndarray, mean: np.ndarray, normal: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Algebraic (Kasa) circle fit of the positions projected on the plane through `mean` normal to `normal`."""
    u = perpendicular(normal)
    v = cross(normal, u)
    q = p - mean
    x, y = q @ u, q @ v
    A = np.column_stack([x, y, np.ones_like(x)])
    b = -(x**2 + y**2)
    Aw = A * w[:, None]
    with np.errstate(all="ignore"):
        try:
            sol = np.linalg.solve(Aw.T @ A, Aw.T @ b)
        except np.linalg.LinAlgError:
            sol = np.full(3, np.inf)
    cx, cy = -sol[0] / 2.0, -sol[1] / 2.0
    if not np.all(np.isfinite([cx, cy])) or np.hypot(cx, cy) > 1e3:
        # Collinear points: a circle of very large radius through them (a prismatic-looking arc).
        _, _, vecs = weighted_pca(np.column_stack([x, y]), w)
        cx, cy = 1e3 * vecs[:, 0]
    return mean + cx * u + cy * v, normal


@dataclass(frozen=True)
class _Orientations:
    """What the observed orientations say about a revolute joint, for the circle refinement.

    `axis` and how well it is known (`axis_sigma`, rad); for the samples `index`,
    the angle about the axis (`angles`, rad, up to a constant) and its noise.
    """

    axis: np.ndarray
    axis_sigma: float
    index: np.ndarray
    angles: np.ndarray
    sigma: float


def _refine_circle(
    p: np.ndarray,
    w: np.ndarray,
    sigma: float,
    center: np.ndarray,
    axis: np.ndarray,
    orientations: _Orientations | None,
) -> tuple[np.ndarray, np.ndarray]:
    """Geometric circle fit in 3-d (centre, axis, radius, plane offset), robust loss, scipy least squares.

    Residuals per sample: distance from the circle's plane and from its rim,
    in noise sigmas, weighted by inlier probability. When orientations were
    observed, also: the tilt of the axis away from the one they show, and for
    each sample the difference between the angle along the circle and the
    angle the orientation turned (up to one constant) — which ties the centre
    to the orientations, the best evidence of where the centre is on short arcs.
    """
    u = perpendicular(axis)
    v = cross(axis, u)
    n = len(p)
    sw = np.sqrt(w) / sigma
    q0 = p - center
    q0_perp = q0 - np.outer(q0 @ axis, axis)
    rho0 = np.linalg.norm(q0_perp, axis=1)
    r0 = float(np.median(rho0))
    h0 = float(np.median(q0 @ axis))
    ori = orientations
    if ori is not None:
        k = ori.index
        # Angle noise of one sample: along the rim (sigma / radius) and of the orientation.
        sa = np.sqrt(w[k]) / np.sqrt((sigma / np.maximum(rho0[k], sigma)) ** 2 + ori.sigma**2)
        offset0 = float(np.median(wrap_angle(angles_about(q0_perp[k], axis, u) - ori.angles)))
    n_extra = 0 if ori is None else 3 + len(ori.index)

    def geometry(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        a = axis + x[2] * u + x[3] * v
        norm = float(np.linalg.norm(a))
        return center + x[0] * u + x[1] * v, a / norm, norm

    def turn(x: np.ndarray) -> np.ndarray:
        assert ori is not None
        c, a, _ = geometry(x)
        q = p[ori.index] - c
        q_perp = q - np.outer(q @ a, a)
        return wrap_angle(angles_about(q_perp, a, u) - ori.angles - x[6]) * sa

    def residuals(x: np.ndarray) -> np.ndarray:
        c, a, _ = geometry(x)
        q = p - c
        h = q @ a
        q_perp = q - h[:, None] * a
        rho = np.linalg.norm(q_perp, axis=1)
        res = [(h - x[5]) * sw, (rho - x[4]) * sw]
        if ori is not None:
            res += [(a - ori.axis) / ori.axis_sigma, turn(x)]
        return np.concatenate(res)

    def jacobian(x: np.ndarray) -> np.ndarray:
        c, a, norm = geometry(x)
        q = p - c
        h = q @ a
        q_perp = q - h[:, None] * a
        rho = np.maximum(np.linalg.norm(q_perp, axis=1), 1e-12)
        proj = np.eye(3) - np.outer(a, a)
        da = np.column_stack([proj @ u, proj @ v]) / norm  # d a / d (x2, x3)
        J = np.zeros((2 * n + n_extra, len(x)))
        J[:n, 0], J[:n, 1] = -(a @ u), -(a @ v)
        J[:n, 2:4] = q @ da
        J[:n, 5] = -1.0
        J[n : 2 * n, 0], J[n : 2 * n, 1] = -(q_perp @ u) / rho, -(q_perp @ v) / rho
        J[n : 2 * n, 2:4] = -(h / rho)[:, None] * (q @ da)
        J[n : 2 * n, 4] = -1.0
        J[: 2 * n] *= np.concatenate([sw, sw])[:, None]
        if ori is not None:
            J[2 * n : 2 * n + 3, 2:4] = da / ori.axis_sigma
            # d angle / d centre = -(a x q_perp) / rho^2; the tilt's effect by finite differences.
            k = ori.index
            tangent = cross(a, q_perp[k]) / (rho[k] ** 2)[:, None]
            rows = slice(2 * n + 3, None)
            J[rows, 0], J[rows, 1] = -(tangent @ u) * sa, -(tangent @ v) * sa
            J[rows, 6] = -sa
            # The angle is atan2(q.e2, q.e1) with e1 = unit(u - (u.a) a), e2 = a x e1:
            # tilting the axis turns that reference frame.
            q = p[k] - c
            w_ref = u - (u @ a) * a
            e1 = w_ref / np.linalg.norm(w_ref)
            e2 = cross(a, e1)
            x1, x2 = q @ e1, q @ e2
            r2 = np.maximum(x1**2 + x2**2, 1e-24)
            for col in (0, 1):
                dak = da[:, col]
                dw = -(u @ dak) * a - (u @ a) * dak
                de1 = (dw - e1 * (e1 @ dw)) / np.linalg.norm(w_ref)
                de2 = cross(dak, e1) + cross(a, de1)
                J[rows, 2 + col] = (x1 * (q @ de2) - x2 * (q @ de1)) / r2 * sa
        return J

    x0 = np.array([0.0, 0.0, 0.0, 0.0, r0, h0] + ([] if ori is None else [offset0]))
    sol = least_squares(
        residuals, x0, jac=jacobian, loss="soft_l1", f_scale=2.0, x_scale="jac", max_nfev=10, method="trf"
    )
    c, a, _ = geometry(sol.x)
    return c, a


def _axis_sigma(data: EdgeData, spread: float) -> float:
    """How well the orientations alone pin the rotation axis (radians of tilt)."""
    n_rot = max(int(data.has_rot.sum()), 1)
    return float(data.sigma_r / max(spread, data.sigma_r) / np.sqrt(n_rot))


def _rotation_axis(data: EdgeData, w: np.ndarray) -> tuple[np.ndarray | None, float, np.ndarray]:
    """The common axis of the observed rotations (None when they do not rotate measurably).

    Also how far they spread (rms angle, rad) and each observed sample's angle
    about the axis, relative to the mean orientation.
    """
    idx = data.rot_index
    if len(idx) < 3:
        return None, 0.0, np.zeros(0)
    rots = data.observed_rotations
    ww = np.maximum(w[idx], 1e-9)
    mean = rots.mean(weights=ww)
    # R_t = Rot(a, q_t) R_ref gives R_t mean^-1 = Rot(a, q_t - q_mean): rotation vectors along a.
    omega = (rots * mean.inv()).as_rotvec()
    for _ in range(2):
        C = (omega * ww[:, None]).T @ omega / ww.sum()
        vals, vecs = np.linalg.eigh(C)
        axis = vecs[:, -1]
        # Rotations off the one-axis family (outliers that passed the screen) would
        # tilt the axis towards themselves: drop them and look again.
        off = np.linalg.norm(omega - np.outer(omega @ axis, axis), axis=1)
        ww = np.where(off < _JUMP_R * data.sigma_r, ww, 1e-9)
    spread = float(np.sqrt(max(vals[-1], 0.0)))
    if spread <= _INFORMATIVE * data.noise_r:
        return None, spread, np.zeros(0)
    return axis, spread, omega @ axis


def _center_from_rotations(data: EdgeData, w: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """A point on the axis from p_t = c + Q_t d (linear in c and d) when positions barely move."""
    idx = data.rot_index
    rots = data.observed_rotations
    Q = (rots * rots[0].inv()).as_matrix()
    n = len(Q)
    A = np.zeros((3 * n, 6))
    A[:, :3] = np.tile(np.eye(3), (n, 1))
    A[:, 3:] = Q.reshape(3 * n, 3)
    sw = np.repeat(np.sqrt(np.maximum(w[idx], 1e-9)), 3)
    sol, *_ = np.linalg.lstsq(A * sw[:, None], data.p[idx].reshape(-1) * sw, rcond=None)
    c = sol[:3]
    start = data.p[0]
    return c + ((start - c) @ axis) * axis
