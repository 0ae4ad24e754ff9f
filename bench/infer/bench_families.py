"""Contact families on held-out contacts: predicted motion against DART's over a 10 cm push.

For the stdlib Block and three generated bodies (CubeM, SlabW, CrateM of
tests/support/task_makers/generated_tasks.py), the body's own exploration is run in DART
and inferred (`vkgl.api.explore`, `vkgl.infer.library.infer_library`); for
every affordance with a `family`, contacts that were NOT explored are chosen
inside its band (half way between explored contacts, or the band's middle), the
family's member there (`vkgl.lang.ir.families.at_offset`) predicts the motion,
and DART pushes the body there (a push trial of the exploration's kind: the
fingertip follows the face with the exploration's force, `vkgl.sim.explore.run_trial`).

The comparison is at equal push: when the contact (a point fixed in the body)
has travelled PUSH (10 cm) in DART, or at the end of the explored range of a
turn if that comes first (the `push` column says which), the predicted pose
is the member's motion by the value that moves the contact that far (a slide:
the distance; a turn: the arc length over the contact's radius about the
pivot). Errors: the body origin's position (cm) and heading (deg). Target:
within 1 cm and 2 deg.

    PYTHONPATH=$PWD .venv/bin/python bench/infer/bench_families.py [--bodies Block,CubeM,SlabW,CrateM] [--seconds 8]
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import math
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

from task_makers import generated_tasks  # noqa: E402

import vkgl  # noqa: E402
from vkgl.infer.library import infer_library  # noqa: E402
from vkgl.lang.ir.families import at_offset, offset_bounds  # noqa: E402
from vkgl.lang.ir.nodes import Affordance, PrismaticC, RevoluteC  # noqa: E402
from vkgl.plan.graphs.motions import motion_matrix  # noqa: E402
from vkgl.sim.explore import run_trial  # noqa: E402
from vkgl.sim.policy import TrialSpec, plan_trials  # noqa: E402

PUSH = 0.10  # m the contact travels
GENERATED = ("CubeM", "SlabW", "CrateM")


def _body(name: str):  # type: ignore[no-untyped-def]
    """The checked Body IR of the stdlib Block or of a generated type."""
    if name == "Block":
        program = vkgl.compile(REPO / "stdlib" / "bodies" / "block.vkg")
    else:
        kind = generated_tasks.TYPES[name]
        program = vkgl.compile_source(kind.source(), f"{name}.vkg")
    return program.bodies[name]


def held_out(explored: list[float], lower: float, upper: float) -> list[float]:
    """Offsets half way between neighbouring explored offsets inside [lower, upper] (the band's middle if one)."""
    inside = sorted(
        {round(s, 6) for s in explored if lower - 1e-4 <= s <= upper + 1e-4}
    )  # bands are rounded inwards to 0.1 mm
    return [0.5 * (a + b) for a, b in itertools.pairwise(inside)] or [0.5 * (lower + upper)]


def _explored_offsets(affordance: Affordance, specs: list[TrialSpec], direction: np.ndarray) -> list[float]:
    action = affordance.action.pose  # type: ignore[union-attr]
    along = affordance.family.along.array()  # type: ignore[union-attr]
    along = along / np.linalg.norm(along)
    base = action.matrix()[:3, 3]
    out = []
    for spec in specs:
        if spec.kind == "push" and float(spec.direction @ direction) > 0.99:
            off = spec.contact - base
            if abs(float(off @ direction)) < 0.01:  # on this face
                out.append(float(off @ along))
    return out


def push_direction(affordance: Affordance) -> np.ndarray:
    """The face's inward normal the family pushes along (the action frame's x, snapped to a body axis)."""
    x = affordance.action.pose.matrix()[:3, 0]  # type: ignore[union-attr]
    k = int(np.argmax(np.abs(x)))
    d = np.zeros(3)
    d[k] = math.copysign(1.0, x[k])
    return d


def compare(body, affordance: Affordance, offset: float, contact: np.ndarray, seconds: float) -> dict:  # type: ignore[no-untyped-def]
    """Push at `contact` in DART and compare with the family member at `offset`."""
    direction = push_direction(affordance)
    template = next(s for s in plan_trials(body) if s.kind == "push")
    spec = dataclasses.replace(template, index=0, contact=contact, direction=direction, duration=seconds)
    result = run_trial(spec, seed=0)
    poses = result.T_ow
    start = poses[0]
    points = np.array([(p @ np.append(contact, 1.0))[:3] for p in poses])
    travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    member = at_offset(affordance, offset)
    motion = member.motion
    limit = PUSH
    if isinstance(motion, RevoluteC):
        axis = motion.axis.array() / np.linalg.norm(motion.axis.array())
        arm = contact - motion.center.array()
        radius = float(np.linalg.norm(arm - (arm @ axis) * axis))
        upper = motion.range.upper.value if motion.range is not None else math.pi
        limit = min(PUSH, radius * upper)
    if travelled[-1] < limit:
        return {"ok": False, "why": f"DART moved the contact only {100 * travelled[-1]:.1f} cm", "push": travelled[-1]}
    k = int(np.searchsorted(travelled, limit))
    actual = np.linalg.solve(start, poses[k])
    value = travelled[k] if isinstance(motion, PrismaticC) else travelled[k] / radius
    predicted = motion_matrix(motion, value)
    position = float(np.linalg.norm(actual[:2, 3] - predicted[:2, 3]))
    heading = math.degrees(abs(math.atan2(actual[1, 0], actual[0, 0]) - math.atan2(predicted[1, 0], predicted[0, 0])))
    turned = math.degrees(abs(math.atan2(actual[1, 0], actual[0, 0])))
    return {"ok": True, "push": float(travelled[k]), "position": position, "heading": heading, "turned": turned}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="Block," + ",".join(GENERATED))
    parser.add_argument("--seconds", type=float, default=8.0, help="DART time of each held-out push (s)")
    args = parser.parse_args(argv)
    rows, worst = [], (0.0, 0.0)
    print(f"{'body':7} {'affordance':15} {'offset cm':>9} {'push cm':>7} {'turned':>7} {'err cm':>7} {'err deg':>7}")
    for name in args.bodies.split(","):
        body = _body(name)
        trials = vkgl.explore(body, jobs=1)
        module = infer_library(trials, body_use=f"{name}.vkg", header=name).module
        specs = plan_trials(body)
        for affordance in module.decls[0].affordances:  # type: ignore[union-attr]
            if affordance.family is None:
                continue
            direction = push_direction(affordance)
            lower, upper = offset_bounds(affordance)
            along = affordance.family.along.array() / np.linalg.norm(affordance.family.along.array())
            base = affordance.action.pose.matrix()[:3, 3]  # type: ignore[union-attr]
            face = base + (_face_depth(specs, direction, base) - float(base @ direction)) * direction
            for offset in held_out(_explored_offsets(affordance, specs, direction), lower, upper):
                r = compare(body, affordance, offset, face + offset * along, args.seconds)
                rows.append((name, affordance.name, offset, r))
                if r["ok"]:
                    worst = (max(worst[0], r["position"]), max(worst[1], r["heading"]))
                    print(
                        f"{name:7} {affordance.name:15} {100 * offset:9.2f} {100 * r['push']:7.1f} "
                        f"{r['turned']:7.1f} {100 * r['position']:7.2f} {r['heading']:7.2f}",
                        flush=True,
                    )
                else:
                    print(f"{name:7} {affordance.name:15} {100 * offset:9.2f}  {r['why']}", flush=True)
    ok = [r for *_, r in rows if r["ok"]]
    print(
        f"\n{len(ok)} of {len(rows)} held-out contacts compared; "
        f"worst error {100 * worst[0]:.2f} cm, {worst[1]:.2f} deg"
    )
    within = sum(1 for r in ok if r["position"] <= 0.01 and r["heading"] <= 2.0)
    print(f"within 1 cm and 2 deg: {within} of {len(ok)}")
    return 0


def _face_depth(specs: list[TrialSpec], direction: np.ndarray, base: np.ndarray) -> float:
    """Where the explored contacts of this face lie along the push (their contact points are on the surface)."""
    depths = [float(s.contact @ direction) for s in specs if s.kind == "push" and float(s.direction @ direction) > 0.99]
    return float(np.median(depths)) if depths else float(base @ direction)


if __name__ == "__main__":
    raise SystemExit(main())
