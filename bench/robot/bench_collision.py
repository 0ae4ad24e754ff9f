"""Collision queries the planner needs, timed per library: DART (FCL, DART, Bullet detectors), coal, python-fcl.

Run on demand: `PYTHONPATH=. python bench/robot/bench_collision.py [--repeat N] [--tasks]`. Prints one table
(microseconds per query, lower is better) and the answers' agreement with the truth.

Queries (docs/collision.md says why these):
  (i)   pair: two bodies at given poses, "do they overlap by more than 1 mm?" (box/box,
        box/union hook, box/cylinder, box/convex mesh of 64 vertices) — a penetration query;
  (ii)  sweep: a moved block at N = 50 poses against K = 10 still bodies + the table;
  (iii) arm: the Panda's 18 URDF collision shapes at a joint configuration (forward
        kinematics included) against 10 bodies + the table.
The libraries that are not installed are skipped. The project's checker (vkgl.motion.collision,
.sweep, .arm_collision: DART's FCL behind a numpy bounding-ball cull) is timed last on the same
queries (its pair column includes that cull; its sweep column calls `hits` per pose).
Every time is the best of 5 rounds (the minimum is the cost; a shared machine only adds to it).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

REPO = Path(__file__).resolve().parents[2]
URDF = REPO / "stdlib" / "robots" / "panda.urdf"
TOL = 1e-3  # m: penetration that counts as overlap

# A shape spec: ("box", size) | ("cyl", (radius, height)) | ("convex", vertices); a body: list of (spec, pose).
Spec = tuple[str, Any]
BodyParts = list[tuple[Spec, np.ndarray]]


ROUNDS = 5
"""Each timing is the best of this many rounds: the machine may be shared, the minimum is the cost."""


def best_of(run: Callable[[], Any], count: int) -> float:
    """µs per item of `run()` (which handles `count` items): the best of ROUNDS rounds."""
    times = []
    for _ in range(ROUNDS):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times) / count * 1e6


def _pose(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler("z", yaw).as_matrix()
    m[:3, 3] = (x, y, z)
    return m


BLOCK: BodyParts = [(("box", (0.1, 0.2, 0.05)), np.eye(4))]
HOOK: BodyParts = [(("box", (0.4, 0.02, 0.02)), np.eye(4)), (("box", (0.02, 0.16, 0.02)), _pose(0.19, 0.07, 0))]
CYL: BodyParts = [(("cyl", (0.04, 0.12)), np.eye(4))]
MESH: BodyParts = [(("convex", trimesh.creation.icosphere(2, 0.05).convex_hull.vertices[:64]), np.eye(4))]
TABLE: BodyParts = [(("box", (1.6, 1.2, 0.05)), _pose(0.5, 0, -0.025))]

PAIRS = {"box/box": (BLOCK, BLOCK), "box/union": (BLOCK, HOOK), "box/cylinder": (BLOCK, CYL), "box/mesh": (BLOCK, MESH)}


def _scene() -> tuple[dict[str, BodyParts], dict[str, np.ndarray]]:
    """10 bodies on the table in front of the arm (4 blocks, 2 hooks, 2 cylinders, 2 meshes) + the table."""
    kinds = [BLOCK, BLOCK, BLOCK, BLOCK, HOOK, HOOK, CYL, CYL, MESH, MESH]
    bodies, poses = {"table": TABLE}, {"table": np.eye(4)}
    for i, kind in enumerate(kinds):
        x, y = 0.35 + 0.2 * (i % 4), -0.45 + 0.3 * (i // 4)
        bodies[f"b{i}"] = kind
        poses[f"b{i}"] = _pose(x, y, 0.06, 0.3 * i)
    return bodies, poses


def _pair_poses(rng: np.random.Generator, n: int) -> list[np.ndarray]:
    """Relative poses of the second body: random turns, offsets within 0.15 m (about a third overlap)."""
    out = []
    for _ in range(n):
        m = np.eye(4)
        m[:3, :3] = Rotation.random(random_state=rng).as_matrix()
        m[:3, 3] = rng.uniform(-0.15, 0.15, 3)
        out.append(m)
    return out


def _sweep_poses(n: int) -> list[np.ndarray]:
    return [_pose(0.2 + 0.6 * s, 0.0, 0.03, 0.5 * s) for s in np.linspace(0, 1, n)]


# ---------------------------------------------------------------- coal


class CoalBackend:
    name = "coal"

    def __init__(self) -> None:
        import coal

        self.coal = coal
        self.req = coal.CollisionRequest()
        self.req.security_margin = -TOL  # only penetration deeper than TOL is a collision
        self.res = coal.CollisionResult()
        self.tf_a, self.tf_b = coal.Transform3s(), coal.Transform3s()

    def geom(self, spec: Spec) -> Any:
        kind, data = spec
        if kind == "box":
            return self.coal.Box(*data)
        if kind == "cyl":
            return self.coal.Cylinder(*data)
        points = self.coal.StdVec_Vec3s()
        points.extend([np.asarray(v, dtype=float) for v in data])
        return self.coal.Convex.convexHull(points, False, None)

    def pair(self, a: BodyParts, b: BodyParts) -> Callable[[np.ndarray, np.ndarray], bool]:
        pa = [(self.geom(s), p) for s, p in a]
        pb = [(self.geom(s), p) for s, p in b]
        # ComputeCollision keeps raw pointers to the geometries: keep them alive with it
        fns = [(self.coal.ComputeCollision(ga, gb), la, lb, ga, gb) for ga, la in pa for gb, lb in pb]
        req, res, ta, tb = self.req, self.res, self.tf_a, self.tf_b

        def query(pose_a: np.ndarray, pose_b: np.ndarray) -> bool:
            for fn, la, lb, _, _ in fns:
                wa, wb = pose_a @ la, pose_b @ lb
                ta.setRotation(wa[:3, :3]), ta.setTranslation(wa[:3, 3])
                tb.setRotation(wb[:3, :3]), tb.setTranslation(wb[:3, 3])
                res.clear()
                if fn(ta, tb, req, res):
                    return True
            return False

        return query


# ---------------------------------------------------------------- python-fcl


class PyFclBackend:
    name = "python-fcl"

    def __init__(self) -> None:
        import fcl

        self.fcl = fcl

    def geom(self, spec: Spec) -> Any:
        kind, data = spec
        if kind == "box":
            return self.fcl.Box(*data)
        if kind == "cyl":
            return self.fcl.Cylinder(*data)
        hull = trimesh.convex.convex_hull(np.asarray(data))
        faces = np.hstack([np.full((len(hull.faces), 1), 3), hull.faces]).ravel()
        return self.fcl.Convex(hull.vertices, len(hull.faces), faces)

    def pair(self, a: BodyParts, b: BodyParts) -> Callable[[np.ndarray, np.ndarray], bool]:
        fcl = self.fcl
        objs = [
            (fcl.CollisionObject(self.geom(sa)), la, fcl.CollisionObject(self.geom(sb)), lb)
            for sa, la in a
            for sb, lb in b
        ]
        req = fcl.CollisionRequest(enable_contact=True)

        def query(pose_a: np.ndarray, pose_b: np.ndarray) -> bool:
            for oa, la, ob, lb in objs:
                wa, wb = pose_a @ la, pose_b @ lb
                oa.setTransform(fcl.Transform(wa[:3, :3], wa[:3, 3]))
                ob.setTransform(fcl.Transform(wb[:3, :3], wb[:3, 3]))
                res = fcl.CollisionResult()
                if fcl.collide(oa, ob, req, res) and max(c.penetration_depth for c in res.contacts) > TOL:
                    return True
            return False

        return query


# ---------------------------------------------------------------- DART


class DartBackend:
    def __init__(self, detector: str) -> None:
        import dartpy as dart

        self.dart = dart
        self.name = f"dart-{detector}"
        self.detector = {
            "fcl": dart.collision.FCLCollisionDetector,
            "dart": dart.collision.DARTCollisionDetector,
            "bullet": dart.collision.BulletCollisionDetector,
        }[detector]()
        if detector == "fcl":
            self.detector.setPrimitiveShapeType(dart.collision.FCLCollisionDetector.PRIMITIVE)
        self.option = dart.collision.CollisionOption()
        self.option.enableContact = True
        self.option.maxNumContacts = 4
        self.keep: list[Any] = []

    def shape(self, spec: Spec) -> Any:
        kind, data = spec
        if kind == "box":
            return self.dart.dynamics.BoxShape(np.asarray(data, dtype=float))
        if kind == "cyl":
            return self.dart.dynamics.CylinderShape(*data)
        hull = trimesh.convex.convex_hull(np.asarray(data))
        path = Path("/tmp/bench_collision_hull.stl")
        hull.export(path)
        from vkgl.lang.ir.nodes import MeshShape
        from vkgl.shapes import load_mesh_shape

        return load_mesh_shape(MeshShape(path=str(path)))

    def group(self, parts: BodyParts, tag: str) -> tuple[Any, list[tuple[Any, np.ndarray]]]:
        group = self.detector.createCollisionGroup()
        frames = []
        for i, (spec, local) in enumerate(parts):
            frame = self.dart.dynamics.SimpleFrame(self.dart.dynamics.Frame.World(), f"{tag}{i}")
            frame.setShape(self.shape(spec))
            group.addShapeFrame(frame)
            self.keep.append(frame)  # groups hold raw pointers to their frames
            frames.append((frame, local))
        return group, frames

    def still_group(self, bodies: dict[str, BodyParts], poses: dict[str, np.ndarray]) -> Any:
        """One group of all `bodies` at `poses` (their frames are kept alive by the backend)."""
        still = self.detector.createCollisionGroup()
        for name, parts in bodies.items():
            _, frames = self.group(parts, name)
            self.place(frames, poses[name])
            for frame, _ in frames:
                still.addShapeFrame(frame)
        return still

    def place(self, frames: list[tuple[Any, np.ndarray]], pose: np.ndarray) -> None:
        for frame, local in frames:
            iso = self.dart.math.Isometry3()
            iso.set_matrix(pose @ local)
            frame.setTransform(iso)

    def deep(self, result: Any) -> bool:
        return any(c.penetrationDepth > TOL for c in result.getContacts())

    def pair(self, a: BodyParts, b: BodyParts) -> Callable[[np.ndarray, np.ndarray], bool]:
        ga, fa = self.group(a, "a")
        gb, fb = self.group(b, "b")
        option, dart = self.option, self.dart

        def query(pose_a: np.ndarray, pose_b: np.ndarray) -> bool:
            self.place(fa, pose_a)
            self.place(fb, pose_b)
            result = dart.collision.CollisionResult()
            return bool(ga.collide(gb, option, result)) and self.deep(result)

        return query


# ---------------------------------------------------------------- the three queries


def time_pairs(backend: Any, repeat: int) -> dict[str, float]:
    rng = np.random.default_rng(0)
    poses = _pair_poses(rng, repeat)
    out = {}
    for label, (a, b) in PAIRS.items():
        query = backend.pair(a, b)
        out[label] = best_of(lambda q=query: [q(np.eye(4), pose) for pose in poses], len(poses))
    return out


def pair_truth(label: str, repeat: int) -> list[bool]:
    """Ground truth from coal's signed distance (EPA) < -TOL, used to check the others agree."""
    backend = CoalBackend()
    a, b = PAIRS[label]
    query = backend.pair(a, b)
    return [query(np.eye(4), p) for p in _pair_poses(np.random.default_rng(0), repeat)]


def time_sweep(backend: Any, n: int = 50, repeat: int = 20) -> float:
    """µs per sweep: a block at n poses against 10 bodies + table, every pose checked against every body."""
    bodies, poses = _scene()
    if isinstance(backend, DartBackend):
        still = backend.still_group(bodies, poses)
        moving, mframes = backend.group(BLOCK, "moving")
        option, dart = backend.option, backend.dart

        def sweep() -> int:
            hits = 0
            for pose in _SWEEP:
                backend.place(mframes, pose)
                result = dart.collision.CollisionResult()
                hits += bool(moving.collide(still, option, result)) and backend.deep(result)
            return hits
    else:
        queries = [(backend.pair(BLOCK, parts), poses[name]) for name, parts in bodies.items()]

        def sweep() -> int:
            hits = 0
            for pose in _SWEEP:
                for query, still_pose in queries:
                    hits += query(pose, still_pose)
            return hits

    _SWEEP[:] = _sweep_poses(n)
    return best_of(lambda: [sweep() for _ in range(repeat)], repeat)


_SWEEP: list[np.ndarray] = []


def _arm() -> tuple[Any, list[tuple[Any, Any, np.ndarray]]]:
    """The Panda's skeleton and its collision shape nodes as (body node, shape, pose in the body node)."""
    from vkgl.robot import load_skeleton

    skeleton = load_skeleton(URDF)
    shapes = []
    for i in range(skeleton.getNumBodyNodes()):
        node = skeleton.getBodyNode(i)
        for j in range(node.getNumShapeNodes()):
            shape_node = node.getShapeNode(j)
            if shape_node.hasCollisionAspect():
                shapes.append((node, shape_node, shape_node.getRelativeTransform().matrix()))
    return skeleton, shapes


def _arm_spec(shape_node: Any) -> Spec:
    shape = shape_node.getShape()
    if shape.getType() == "BoxShape":
        return ("box", tuple(shape.getSize()))
    return ("cyl", (shape.getRadius(), shape.getHeight()))


def arm_configurations(n: int = 60) -> list[np.ndarray]:
    """n joint configurations within the Panda's limits (fixed seed): some hit the table or a body, some are free."""
    skeleton, _ = _arm()
    lower, upper = skeleton.getPositionLowerLimits(), skeleton.getPositionUpperLimits()
    return list(np.random.default_rng(1).uniform(lower, upper, (n, len(lower))))


def arm_checker(backend: Any) -> Callable[[np.ndarray], bool]:
    """`check(q)`: whether an arm collision shape overlaps a body or the table by more than TOL (FK included)."""
    bodies, poses = _scene()
    skeleton, shapes = _arm()
    if isinstance(backend, DartBackend):
        arm_group = backend.detector.createCollisionGroup()
        for _, shape_node, _ in shapes:
            arm_group.addShapeFrame(shape_node)
        still = backend.still_group(bodies, poses)
        option, dart = backend.option, backend.dart

        def check(q: np.ndarray) -> bool:
            skeleton.setPositions(q)
            result = dart.collision.CollisionResult()
            return bool(arm_group.collide(still, option, result)) and backend.deep(result)

        return check
    nodes = sorted({id(n): n for n, _, _ in shapes}.values(), key=lambda n: n.getIndexInSkeleton())
    index = {id(n): i for i, n in enumerate(nodes)}
    links = [([(_arm_spec(s), local)], index[id(n)]) for n, s, local in shapes]
    queries = [(backend.pair(parts, body), link, poses[name]) for parts, link in links for name, body in bodies.items()]

    def check(q: np.ndarray) -> bool:
        skeleton.setPositions(q)
        frames = [n.getWorldTransform().matrix() for n in nodes]
        return any(query(frames[link], pose) for query, link, pose in queries)

    return check


def time_arm(backend: Any, qs: list[np.ndarray]) -> tuple[float, list[bool]]:
    """(µs per configuration, the answers) over `qs`."""
    check = arm_checker(backend)
    answers = [check(q) for q in qs]
    return best_of(lambda: [check(q) for q in qs], len(qs)), answers


# ---------------------------------------------------------------- the project's checker


def _ir(parts: BodyParts) -> Any:
    """The IR shape of a bench body (a mesh is written to a temporary STL)."""
    from vkgl.lang.ir.nodes import (
        BoxShape,
        CylinderShape,
        MeshShape,
        Pose,
        Quantity,
        ShapePart,
        UnionShape,
        Vector,
    )

    def one(spec: Spec) -> Any:
        kind, data = spec
        if kind == "box":
            return BoxShape(size=Vector(values=tuple(data)))
        if kind == "cyl":
            return CylinderShape(radius=Quantity(value=data[0]), height=Quantity(value=data[1]))
        path = Path("/tmp/bench_collision_hull.stl")
        trimesh.convex.convex_hull(np.asarray(data)).export(path)
        return MeshShape(path=str(path), resolved=str(path))

    if len(parts) == 1 and np.allclose(parts[0][1], np.eye(4)):
        return one(parts[0][0])
    return UnionShape(
        parts=[
            ShapePart(shape=one(spec), pose=Pose(position=Vector(values=tuple(local[:3, 3])))) for spec, local in parts
        ]
    )  # the bench's unions are not turned


def vkgl_row(
    repeat: int, qs: list[np.ndarray]
) -> tuple[str, dict[str, float], float, float, list[list[bool]], list[bool], str]:
    """The same queries through vkgl.motion.collision / sweep / arm_collision (DART's FCL + a numpy cull)."""
    from vkgl.lang.compiler import compile_file
    from vkgl.lang.ir.nodes import PrismaticC, Vector
    from vkgl.motion.arm_collision import ArmCollision
    from vkgl.motion.collision import CollisionScene
    from vkgl.plan.geometry.sweep import sample_values, sweep
    from vkgl.robot import Arm

    pairs, answers = {}, []
    poses = _pair_poses(np.random.default_rng(0), repeat)
    for label, (a, b) in PAIRS.items():
        scene = CollisionScene({"a": _ir(a), "b": _ir(b)})
        pairs[label] = best_of(lambda s=scene: [s.overlap({"a": np.eye(4), "b": p}) for p in poses], len(poses))
        answers.append([bool(scene.overlap({"a": np.eye(4), "b": p})) for p in poses[:400]])
    bodies, where = _scene()
    shapes = {name: _ir(parts) for name, parts in bodies.items() if name != "table"}
    table = {"table_center": np.array([0.5, 0.0]), "table_size": np.array([1.6, 1.2])}
    scene = CollisionScene({**shapes, "moving": _ir(BLOCK)}, **table)
    still = {n: p for n, p in where.items() if n != "table"}
    scene.place(still)
    others = list(still) + ["table"]
    path = _sweep_poses(50)
    per_sweep = best_of(lambda: [scene.hits("moving", p, others) for _ in range(20) for p in path], 20)
    along = PrismaticC(axis=Vector(values=(1.0, 0.0, 0.0)))
    beside = _pose(0.2, 0.35, 0.03)
    n = len(sample_values(along, 0.6, scene.radius["moving"]))
    assert sweep(scene, beside, along, 0.6, {"moving": beside}, still) == []
    free_sweep = best_of(lambda: [sweep(scene, beside, along, 0.6, {"moving": beside}, still) for _ in range(20)], 20)
    robot = compile_file(str(REPO / "examples" / "tasks" / "a_push.vkg")).robots["Panda"]
    arm = ArmCollision(CollisionScene(shapes, **table), Arm.load(robot, "fingertip", np.eye(4)))
    arm.scene.place(still)
    arm_answers = [not arm.free(q) for q in qs]
    arm_us = best_of(lambda: [arm.free(q) for q in qs], len(qs))
    note = f"vkgl sweep(): a free 0.6 m slide beside the bodies, {n} samples (6 mm apart), {free_sweep:.0f} µs"
    return "vkgl (dart-fcl)", pairs, per_sweep, arm_us, answers, arm_answers, note


def backends() -> list[Any]:
    out: list[Any] = []
    for make in (
        CoalBackend,
        PyFclBackend,
        lambda: DartBackend("fcl"),
        lambda: DartBackend("dart"),
        lambda: DartBackend("bullet"),
    ):
        try:
            out.append(make())
        except (ImportError, AttributeError, RuntimeError) as error:
            print(f"skipped: {error}")
    return out


EXTRA = [(0.9 + 0.12 * (i % 4), (-0.5, 0.5)[i // 4]) for i in range(8)]
"""Where 8 extra blocks stand on the tabletop scene's table for the `--tasks` scaling column: off the plans' way."""


def _check_plan(problem: Any, result: Any, extra: int) -> tuple[float, float, float, list[Any]]:
    """Build scene and arm, then checks (a)-(d) along the found plan, with `extra` more blocks.

    Returns (ms, ms, ms, contacts).
    """
    from vkgl.motion.arm_collision import ArmCollision
    from vkgl.motion.collision import CollisionScene, pair
    from vkgl.plan.geometry.sweep import sweep_mode

    block = problem.bodies["block"]
    more = {f"extra{i}": _pose(x, y, block.rest[2, 3]) for i, (x, y) in enumerate(EXTRA[:extra])}
    start = time.perf_counter()
    shapes = {name: body.type.shape for name, body in problem.bodies.items()}
    shapes.update({name: block.type.shape for name in more})
    scene = CollisionScene(
        shapes, table_center=problem.table_center, table_size=problem.table_size, table_z=problem.table_z
    )
    arm = ArmCollision(scene, problem.arm)
    built = time.perf_counter()
    found = []
    graphs = result.sequence.graphs
    traces = [(dict(t.start, **more), dict(t.end, **more), t) for t in result.task.traces]
    for k, (first, last, trace) in enumerate(traces):
        tools = [(problem.effector(e.effector).tool, e.body) for e in graphs[k].engaged]
        ignore = {pair(tool, body) for tool, body in tools if tool is not None}
        for poses in (first, last):
            found += scene.overlap(poses, ignore)
        trace.start, trace.end = first, last
        found += sweep_mode(scene, problem, trace)
    bodies = time.perf_counter()
    for k, (first, last, _) in enumerate(traces):
        touched = {e.body for e in graphs[k].engaged}
        for q, poses in ((result.joints.q_start[k], first), (result.joints.q_end[k], last)):
            found += arm.overlap(q, poses, ignore=touched)
    done = time.perf_counter()
    return 1e3 * (built - start), 1e3 * (bodies - built), 1e3 * (done - bodies), found


def paper_tasks() -> None:
    """Per paper task: the checks along its found plan (ms), what overlaps, and the same with 8 more blocks."""
    import copy

    from vkgl.lang.compiler import compile_file
    from vkgl.plan.problem.problem import build_problem
    from vkgl.plan.search.search import search

    print(f"{'task':>22} | build ms | bodies ms | arm ms | +8 blocks: build, bodies, arm ms | overlaps")
    for path in sorted((REPO / "examples" / "tasks").glob("*.vkg")):
        program = compile_file(str(path))
        problem = build_problem(program, program.task())
        result = search(problem, deadline=time.perf_counter() + 30)
        if result.task is None or result.joints is None or result.sequence is None:
            print(f"{path.stem:>22} | not solved")
            continue
        build, bodies, arm, found = _check_plan(problem, copy.deepcopy(result), 0)
        build8, bodies8, arm8, found8 = _check_plan(problem, copy.deepcopy(result), 8)
        what = ", ".join(f"{c.body_a}/{c.body_b} {c.depth * 1000:.1f} mm" for c in found + found8) or "none"
        print(
            f"{path.stem:>22} | {build:8.1f} | {bodies:9.1f} | {arm:6.1f} | "
            f"{build8:9.1f}, {bodies8:6.1f}, {arm8:5.1f} {'':>9} | {what}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2000, help="pair queries per shape pair")
    parser.add_argument("--rounds", type=int, default=ROUNDS, help="each time is the best of this many rounds")
    parser.add_argument("--tasks", action="store_true", help="instead: the checks along the paper tasks' plans")
    args = parser.parse_args()
    globals()["ROUNDS"] = args.rounds
    if args.tasks:
        paper_tasks()
        return
    qs = arm_configurations()
    truth_pairs = {label: pair_truth(label, 400) for label in PAIRS}
    truth_arm: list[bool] | None = None
    rows = []
    for backend in backends():
        pairs = time_pairs(backend, args.repeat)
        agree = []
        for label, (a, b) in PAIRS.items():
            query = backend.pair(a, b)
            got = [query(np.eye(4), p) for p in _pair_poses(np.random.default_rng(0), 400)]
            agree.append(sum(t == g for t, g in zip(truth_pairs[label], got)) / len(got))
        arm_us, arm_answers = time_arm(backend, qs)
        truth_arm = arm_answers if truth_arm is None else truth_arm  # coal (first) is the reference
        arm_agree = sum(t == g for t, g in zip(truth_arm, arm_answers)) / len(qs)
        rows.append((backend.name, pairs, time_sweep(backend), arm_us, min(agree), arm_agree))
    name, pairs, sweep, arm_us, answers, arm_answers, note = vkgl_row(args.repeat, qs)
    agree = min(sum(t == g for t, g in zip(truth_pairs[k], a)) / len(a) for k, a in zip(PAIRS, answers))
    arm_agree = sum(t == g for t, g in zip(truth_arm or [], arm_answers)) / len(qs)
    rows.append((name, pairs, sweep, arm_us, agree, arm_agree))
    header = ["library", *PAIRS, "sweep 50x11", "arm 18x11", "pairs agree", "arm agrees"]
    print(" | ".join(f"{h:>12}" for h in header))
    for name, pairs, sweep, arm, agree, arm_agree in rows:
        cells = [
            name,
            *(f"{pairs[k]:.1f}" for k in PAIRS),
            f"{sweep:.0f}",
            f"{arm:.0f}",
            f"{agree:.1%}",
            f"{arm_agree:.1%}",
        ]
        print(" | ".join(f"{c:>12}" for c in cells))
    overlap = {k: sum(v) / len(v) for k, v in truth_pairs.items()}
    print("µs per query. Pair columns: one query of two bodies at given poses (a union = all its part pairs),")
    print("  transforms set from numpy 4x4s; sweep: a block at 50 poses x (10 bodies + table), every pair;")
    print("  arm: FK + 18 URDF collision shapes x (10 bodies + table) at one joint configuration.")
    print("pairs agree: worst share over the pair types of 400 random queries answered like coal's signed")
    print(f"  penetration > 1 mm (overlap shares: {', '.join(f'{k} {v:.0%}' for k, v in overlap.items())});")
    print(
        f"arm agrees: share of {len(qs)} random configurations answered like coal's "
        f"({sum(truth_arm or [])} in collision)."
    )
    print(note)


if __name__ == "__main__":
    main()
