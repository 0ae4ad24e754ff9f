"""Pushes at small offsets from a face's centre in DART: do they make repeatable arcs, and which goals can one reach?

Quasi-static pushing says a push whose line passes at offset d from a body's centre turns it about a centre of
rotation on the other side, at r ~ c^2 / d (c a length of the body's support), so small offsets make wide arcs that
slide and turn at once. This measures it with exploration's own pusher (`vkgl.sim.explore.run_trial`: the
fingertip aimed along the face's inward normal every control period, force-limited to the declared 1 N beyond the
table's friction): the -x face of the stdlib Block and of generated types
(tests/support/task_makers/generated_tasks.py, a cube
among them) pushed 15 cm at offsets 0.3 to 2 cm along the face.

Printed, per body:

1. per push: the pivot (body frame at the start) from the pose after 5 and after 15 cm of travel (how steady the
   arc is), r * d (constant if r ~ c^2 / d), the turn per cm of travel; a second seed's turn (repeatability);
2. a model fitted on the pushes at FIT offsets, r(d) = a / d + b and the pivot's position along the push its mean,
   checked on the HELD offsets: the pose predicted after 10 cm of the centre's travel against DART's (cm, deg);
3. which heading goals of `bench/physical/bench_heading.py` (slide 10 to 15 cm along the push and turn 10 to 20 deg) one
   such arc could reach: the least distance from the goal over every offset and every turn within the goal's
   heading tolerance. An arc's chord leans from the push by about half its turn, so a goal straight ahead is
   missed sideways by about L sin(turn / 2);
4. with --execute: each of those goals solved with one arc only (the model's member for it written as a point
   affordance) and carried out by the Panda arm in DART: depth and clean.

    PYTHONPATH=$PWD .venv/bin/python bench/infer/bench_arc_push.py [--bodies Block,CubeM] [--seeds 0,1] [--execute]

Seeded (the start gap's jitter), single process; ~10 s of CPU a push for the light bodies, more for the crates.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path[:0] = [str(Path(__file__).resolve().parents[2] / "tests" / "support")]

from task_makers import generated_tasks  # noqa: E402

import vkgl  # noqa: E402
from vkgl.lang.ir.nodes import Body  # noqa: E402
from vkgl.sim.explore import G, run_trial  # noqa: E402
from vkgl.sim.fingertip import NO_LOAD_SPEED  # noqa: E402
from vkgl.sim.policy import TrialSpec, plan_trials  # noqa: E402

FIT = (0.005, 0.01, 0.02)  # m: offsets the model is fitted on
HELD = (0.003, 0.0075, 0.015)  # m: offsets it is checked on
TRAVEL = 0.15  # m of the centre's travel pushed
CHECK_TRAVEL = 0.10  # m: where the held-out prediction is compared
GOALS = ((0.10, -10.0), (0.12, 15.0), (0.15, -20.0), (0.13, 12.0))  # bench_heading.py's goals
OBLIQUE = ((0.0025, 8.0), (0.005, 8.0), (0.005, -8.0), (0.0, 8.0))  # (m, deg): pushes at an angle to the normal
ANGLE_LIMIT = 12.0  # deg from the face's normal a member may push: well inside the pad's friction cone (26.6 deg)
PUSH = 1.0  # N beyond the table's friction, as the bodies' `explore` blocks push


def body_of(name: str, slide_steps: int = 1) -> Body:
    """The compiled body type `name` (the stdlib Block or a generated type, its long pushes at `slide_steps` points
    per face)."""
    kind = replace(generated_tasks.TYPES[name], slide_steps=slide_steps)
    program = vkgl.compile("stdlib/bodies/block.vkg") if kind.stdlib else vkgl.compile_source(kind.source())
    return next(b for b in program.bodies.values() if b.name == name)


def push(
    body: Body, offset: float, seed: int, angle: float = 0.0, duration: float | None = None, face: float = -1.0
) -> np.ndarray:
    """(n, 3) planar poses (x, y, yaw) of `body` pushed on its -x face (`face` 1: its +x face) at `offset` along y
    until TRAVEL (or for `duration` s), the push `angle` (rad) from the face's inward normal towards +y (0:
    exploration's `force normal`)."""
    half = float(body.shape.size.array()[0]) / 2.0  # type: ignore[union-attr]
    limit = PUSH + 0.5 * body.mass.value * G  # friction 0.5, the generated bodies' and the Block's
    if duration is None:
        duration = (TRAVEL + 0.01) / (NO_LOAD_SPEED * PUSH / limit) + 0.5  # the drive's speed against friction
    spec = TrialSpec(
        0,
        body,
        "arc",
        "push",
        np.array([face * half, offset, 0.0]),
        np.array([-face * math.cos(angle), math.sin(angle), 0]),
        PUSH,
        duration,
        np.array([0, 1.0, 0]),
    )
    result = run_trial(spec, seed)
    if not result.ok:
        raise RuntimeError(f"{body.name} at {offset} m: {result.reason}")
    poses = np.array([[T[0, 3], T[1, 3], math.atan2(T[1, 0], T[0, 0])] for T in result.T_ow])
    poses -= poses[0]
    return poses


def travelled(poses: np.ndarray) -> np.ndarray:
    return np.linalg.norm(poses[:, :2], axis=1)


def at_travel(poses: np.ndarray, distance: float) -> np.ndarray:
    """The first pose whose centre is `distance` from the start (the last one if it never gets there)."""
    index = min(int(np.searchsorted(travelled(poses), distance)), len(poses) - 1)
    return poses[index]


def pivot(end: np.ndarray) -> np.ndarray:
    """The centre of the rotation that takes the start (0, 0, 0) to `end` (x, y, yaw)."""
    turn = end[2]
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    return np.linalg.solve(np.eye(2) - rotation, end[:2])


def arc_end(pivot_xy: np.ndarray, turn: float) -> np.ndarray:
    """The pose of a body turned by `turn` (rad) about `pivot_xy` from (0, 0, 0)."""
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    return np.append(pivot_xy + rotation @ -pivot_xy, turn)


class ArcModel:
    """r(d) = a / d + b across the push, the pivot's position along the push a constant (pushed at +d: clockwise)."""

    def __init__(self, offsets: list[float], pivots: list[np.ndarray], half: float) -> None:
        d = np.array(offsets)
        radii = np.array([-p[1] for p in pivots])
        design = np.column_stack([1.0 / d, np.ones_like(d)])
        (self.a, self.b), *_ = np.linalg.lstsq(design, radii, rcond=None)
        self.along = float(np.mean([p[0] for p in pivots]))
        self.half = half

    def pivot(self, offset: float) -> np.ndarray:
        """The pivot of a normal push at `offset` (> 0) from the face's centre."""
        return np.array([self.along, -(self.a / offset + self.b)])

    def oblique_pivot(self, contact: np.ndarray, angle: float) -> np.ndarray:
        """The pivot of a push at `contact` (x, y) along `angle` (rad from +x): the normal push's pivot for the
        force line's moment arm, turned with the push (a guess: the support's friction is isotropic)."""
        direction = np.array([math.cos(angle), math.sin(angle)])
        arm = float(contact[0] * direction[1] - contact[1] * direction[0])  # > 0: counter-clockwise
        local = np.array([self.along, math.copysign(self.a / abs(arm) + self.b, arm)])
        rotation = np.array([[direction[0], -direction[1]], [direction[1], direction[0]]])
        return rotation @ local

    def pose_after(self, offset: float, distance: float) -> np.ndarray:
        """The predicted pose once the centre is `distance` from its start (chord length)."""
        centre = self.pivot(offset)
        radius = float(np.linalg.norm(centre))
        turn = -2.0 * math.asin(min(1.0, distance / (2.0 * radius)))
        return arc_end(centre, turn)


def best_arc(model: ArcModel, dx: float, dyaw_deg: float, angles: np.ndarray) -> tuple[float, float, float]:
    """(least distance in m from the goal (dx, 0, dyaw), offset in m, push angle in deg) of one arc that turns the
    body by exactly `dyaw`, over offsets from -3 to 3 cm along the -x face and push `angles` (deg)."""
    goal = np.array([dx, 0.0])
    half = model.half
    best = (math.inf, 0.0, 0.0)
    for offset in np.linspace(-0.03, 0.03, 241):
        for angle in angles:
            contact = np.array([-half, float(offset)])
            arm = float(contact[0] * math.sin(math.radians(angle)) - contact[1] * math.cos(math.radians(angle)))
            if abs(arm) < 1e-4 or math.copysign(1.0, arm) != math.copysign(1.0, dyaw_deg):
                continue  # a turn the other way round (or none)
            centre = model.oblique_pivot(contact, math.radians(float(angle)))
            miss = float(np.linalg.norm(arc_end(centre, math.radians(dyaw_deg))[:2] - goal))
            if miss < best[0]:
                best = (miss, float(offset), float(angle))
    return best


def _pose(pose: np.ndarray) -> str:
    return f"({100 * pose[0]:5.2f},{100 * pose[1]:+5.2f}) {math.degrees(pose[2]):+6.2f}d"


def oblique_check(body: Body, model: ArcModel, seed: int) -> None:
    """Pushes at an angle to the face's normal: DART's pose after 12 cm against the turned model's."""
    print(f"  {'offset':>7} {'angle':>6} {'DART after 12 cm':>24} {'model':>24}")
    for offset, angle in OBLIQUE:
        seen = at_travel(push(body, offset, seed, math.radians(angle)), 0.12)
        contact = np.array([-model.half, offset])
        centre = model.oblique_pivot(contact, math.radians(angle))
        radius = float(np.linalg.norm(centre))
        turn = math.copysign(2.0 * math.asin(min(1.0, float(np.linalg.norm(seen[:2])) / (2.0 * radius))), seen[2])
        predicted = arc_end(centre, turn)
        print(f"  {100 * offset:5.2f}cm {angle:+5.0f}d {_pose(seen):>24} {_pose(predicted):>24}", flush=True)


def _one_arc(folder: Path, name: str, arc: tuple[float, float, np.ndarray], goal: tuple[float, float], within: str):
    """Solve bench_heading.py's task for `goal` (dx m, dyaw deg) with one affordance, `arc` = (contact's offset on
    the -x face in m, the action's yaw in deg, pivot (x, y) m), and carry the plan out: (plan, report or None)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "physical"))
    import bench_heading

    kind = generated_tasks.TYPES[name]
    body_use = "use stdlib.bodies.block" if kind.stdlib else 'use "body.vkg"'
    if not kind.stdlib:
        (folder / "body.vkg").write_text(kind.source(), encoding="utf-8")
    offset, yaw, centre = arc
    half = float(kind.size[0]) / 2.0
    axis = "(0, 0, 1)" if goal[1] > 0 else "(0, 0, -1)"
    (folder / "arcs.vkg").write_text(
        f"{body_use}\n\naffordances {name} {{\n    affordance arc {{\n"
        f"        action fixed at ({-100 * half:.2f}, {100 * offset:.2f}, 0) cm yaw {yaw:g}deg\n"
        f"        motion revolute about ({100 * centre[0]:.2f}, {100 * centre[1]:.2f}, 0) cm axis {axis} "
        "range 0 to 30deg\n    }\n}\n",
        encoding="utf-8",
    )
    text = bench_heading.task_text(name, 'use "arcs.vkg"\n', *goal).replace("within 1 cm, 3deg", within)
    (folder / "task.vkg").write_text(text, encoding="utf-8")
    program = vkgl.compile(folder / "task.vkg")
    plan = vkgl.solve(program, "turn_and_slide")
    report = vkgl.execute(program, "turn_and_slide", plan) if plan.status == "solved" else None
    return plan, report


def carry_out(name: str, model: ArcModel) -> list[tuple[int | None, bool]]:
    """Each goal solved with one arc only, (depth or None, reached in DART) per goal.

    The arc is the model's best member for the goal (`best_arc`, the push within ANGLE_LIMIT of the normal) written
    as a point affordance: the fingertip's pad flat on the face at the member's contact (yaw 0: the arm's pad is a
    2 cm capsule, which a yawed action would put on the face by its end) and the turn about the member's pivot.
    The task is bench_heading.py's, the body alone at (0.45, 0) m; `vkgl.solve` plans it, `vkgl.execute` carries it
    out with the Panda arm in DART.
    """
    out: list[tuple[int | None, bool]] = []
    with tempfile.TemporaryDirectory() as tmp:
        for dx, dyaw in GOALS:
            _, offset, angle = best_arc(model, dx, dyaw, np.linspace(-ANGLE_LIMIT, ANGLE_LIMIT, 61))
            centre = model.oblique_pivot(np.array([-model.half, offset]), math.radians(angle))
            plan, report = _one_arc(Path(tmp), name, (offset, 0.0, centre), (dx, dyaw), "within 1 cm, 3deg")
            if report is None:
                out.append((None, False))
                print(f"  goal {100 * dx:.0f} cm {dyaw:+.0f} deg: one arc: {plan.status}", flush=True)
                continue
            out.append((int(plan.depth), report.status == "reached"))  # type: ignore[arg-type]
            print(
                f"  goal {100 * dx:.0f} cm {dyaw:+.0f} deg: one arc (contact {100 * offset:+.2f} cm, push "
                f"{angle:+.1f} deg) depth {plan.depth}, in DART {report.status}: {report.goals[0].errors()}",
                flush=True,
            )
    return out


PAD_PROBES = (
    ("the member of goal 12 cm +15 deg, its action yawed by its push", (-0.001, -6.5, np.array([0.0618, 0.4542]))),
    ("a pivot no push explored: 45 cm beside the face's centre", (0.0, 0.0, np.array([0.0, 0.45]))),
    *((f"tighter: {r} cm beside the face's centre", (0.0, 0.0, np.array([0.0, r / 100]))) for r in (35, 30, 25, 20)),
)
"""Arcs of the Block (offset m, action yaw deg, pivot m) carried out by the arm for goal 12 cm +15 deg, loosely:
what the arm's pad makes of an arc, planned against real."""


def pad_probe() -> None:
    """What the arm's pad does with arcs that are not the model's members: the Block's pose at the end of the push,
    planned and real."""
    print("\nthe arm's pad (a 2 cm capsule) on arcs of the Block, planned -> real at the push's end:")
    with tempfile.TemporaryDirectory() as tmp:
        for words, arc in PAD_PROBES:
            plan, report = _one_arc(Path(tmp), "Block", arc, (0.12, 15.0), "within 9 cm, 9deg")
            if report is None or not report.steps or not report.steps[0].deviations:
                print(f"  {words}: {plan.status}")
                continue
            deviation = report.steps[0].deviations[0]
            print(f"  {words}: {_matrix_pose(deviation.planned)} -> {_matrix_pose(deviation.real)}", flush=True)


def _matrix_pose(matrix: np.ndarray) -> str:
    return _pose(np.array([matrix[0, 3], matrix[1, 3], math.atan2(matrix[1, 0], matrix[0, 0])]))


def held_out(model: ArcModel, runs: dict[float, np.ndarray], words: str) -> int:
    """Print `model`'s errors on the pushes at HELD offsets over CHECK_TRAVEL; how many are within 1 cm and 2 deg."""
    kept = 0
    for offset in HELD:
        seen = at_travel(runs[offset], CHECK_TRAVEL)
        # the turn predicted once the centre has come as far as DART's; the place predicted at DART's turn
        turn = math.degrees(abs(seen[2] - model.pose_after(offset, float(np.linalg.norm(seen[:2])))[2]))
        miss = float(np.linalg.norm(seen[:2] - arc_end(model.pivot(offset), float(seen[2]))[:2]))
        kept += miss <= 0.01 and turn <= 2.0
        print(f"  {words}held-out {100 * offset:4.2f} cm over 10 cm: {100 * miss:.2f} cm, {turn:.2f} deg")
    return kept


def measure(name: str, seeds: list[int], execute: bool) -> tuple[int, int, list[tuple[int | None, bool]]]:
    """Print one body's pushes, its held-out check and its goals; (held-out pushes within 1 cm and 2 deg, held,
    with `execute` each goal's (depth, reached in DART) when solved with one arc)."""
    body = body_of(name)
    print(f"\n{name} ({body.mass.value:.2f} kg)")
    print(f"  {'offset':>7} {'pivot at 5 cm':>16} {'pivot at 15 cm':>16} {'r*d cm^2':>9} {'deg/cm':>7} {'seeds':>14}")
    pivots: dict[float, np.ndarray] = {}
    runs: dict[float, np.ndarray] = {}
    for offset in sorted(FIT + HELD):
        poses = push(body, offset, seeds[0])
        runs[offset] = poses
        early, late = pivot(at_travel(poses, 0.05)), pivot(at_travel(poses, TRAVEL))
        pivots[offset] = late
        per_cm = -math.degrees(at_travel(poses, TRAVEL)[2]) / (100 * TRAVEL)
        others = [-math.degrees(at_travel(push(body, offset, s), TRAVEL)[2]) for s in seeds[1:]]
        shown = " ".join(f"{t:.2f}" for t in [-math.degrees(at_travel(poses, TRAVEL)[2]), *others])
        print(
            f"  {100 * offset:5.2f}cm ({100 * early[0]:+5.1f},{100 * early[1]:+7.1f}) ({100 * late[0]:+5.1f},"
            f"{100 * late[1]:+7.1f}) {1e4 * offset * -late[1]:9.1f} {per_cm:7.2f} {shown:>14}",
            flush=True,
        )
    half = float(body.shape.size.array()[0]) / 2.0  # type: ignore[union-attr]
    model = ArcModel(list(FIT), [pivots[o] for o in FIT], half)
    print(
        f"  model: r = {1e4 * model.a:.1f} cm^2 / d + {100 * model.b:.1f} cm, pivot {100 * model.along:+.1f} cm along"
    )
    kept = held_out(model, runs, "")
    # What exploration's grid would see: the same offsets pushed as long as the body's `explore pushes` block
    # pushes (2 s for the Block, 3 s for a generated type: 6 to 7 cm)
    seconds = max(e.duration.value for e in body.explores if e.name == "pushes")  # type: ignore[attr-defined]
    short = [pivot(push(body, offset, seeds[0], duration=seconds)[-1]) for offset in FIT]
    held_out(ArcModel(list(FIT), short, half), runs, f"fitted on {seconds:g} s pushes, ")
    # ... and what the grid pushes today: its two off-centre points nearest the centre (9 points along the face)
    pushes = [t for t in plan_trials(body) if t.policy == "pushes" and t.direction[0] > 0]  # the -x face's
    grid = sorted(c for c in (float(t.contact[1]) for t in pushes) if c > 1e-6)[:2]
    nearest = [pivot(push(body, offset, seeds[0], duration=seconds)[-1]) for offset in grid]
    shown = " and ".join(f"{100 * c:.2f}" for c in grid)
    held_out(ArcModel(grid, nearest, half), runs, f"fitted on the grid's {shown} cm, ")
    oblique_check(body, model, seeds[0])
    for dx, dyaw in GOALS:
        normal = best_arc(model, dx, dyaw, np.zeros(1))
        oblique = best_arc(model, dx, dyaw, np.linspace(-ANGLE_LIMIT, ANGLE_LIMIT, 61))
        print(
            f"  goal {100 * dx:.0f} cm {dyaw:+.0f} deg, one arc at its heading: a normal push misses by "
            f"{100 * normal[0]:.2f} cm (offset {100 * normal[1]:+.2f} cm); an oblique one by {100 * oblique[0]:.2f} cm "
            f"(offset {100 * oblique[1]:+.2f} cm, {oblique[2]:+.1f} deg)"
        )
    return kept, len(HELD), carry_out(name, model) if execute else []


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="Block,CubeM,SlabN,CrateM", help="comma-separated body types")
    parser.add_argument("--seeds", default="0,1", help="comma-separated seeds (the first is measured in full)")
    parser.add_argument("--execute", action="store_true", help="solve each goal with one arc and carry it out in DART")
    args = parser.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    kept = held = 0
    carried: list[tuple[int | None, bool]] = []
    for name in args.bodies.split(","):
        k, h, c = measure(name, seeds, args.execute)
        kept, held, carried = kept + k, held + h, carried + c
    print(f"\nheld-out pushes within 1 cm and 2 deg over 10 cm: {kept} of {held}")
    if args.execute:
        pad_probe()
        depths = [d for d, _ in carried if d is not None]
        print(
            f"goals solved with one arc: {len(depths)} of {len(carried)}, clean in DART {sum(r for _, r in carried)}; "
            f"median depth {statistics.median(depths) if depths else float('nan'):g}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
