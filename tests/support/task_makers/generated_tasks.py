"""Seeded generator of tabletop tasks on bodies and scenes nobody tuned for.

`task_spec(seed, index)` is a pure function: it draws, from a random
generator seeded with `(seed, index)` only, a target body, its start and goal
on the tabletop of examples/scenes/tabletop.vkg (1.6 x 1.2 m table at
(0.5, 0, 0), Panda at the origin, the stick at (0.3, -0.4) and the hook at
(0.3, 0.4)), and 1 to 4 clutter bodies placed without overlap. `write_task`
turns a spec into `.vkg` files in one folder:

- `bodies.vkg`: the generated body types the scene uses (boxes with a mass from
  a density, friction 0.5, explored as a user who wants to slide them far
  explores them, like the stdlib Block: short pushes at 9 points of each long
  face, whose pushes near the ends turn it, and a long push at each face's
  centre, `SLIDE_SECONDS`, which slides it 19 to 32 cm);
- `affordances.vkg`: their learned affordances (copied from a cache, see
  `learned_affordances`), importing `bodies.vkg`;
- `scene.vkg` and `task.vkg`.

Goals are `near` (start and goal within the fingertip's reach, a push),
`far-push` (the goal beyond the reach: the stick) or `far-pull` (the start
beyond the reach: the hook). Some tasks put a clutter body in the straight
path of the target (`in_path`); the others keep the straight path clear of
every other body, the tools included. Footprints are unions of oriented
rectangles (every body here is a box or a union of boxes) and overlap is
tested by separating axes.
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from checkers.footprints import hull, on_table, overlaps, polygons

from task_makers.generated_bodies import (  # noqa: F401  (re-exported: the tests and benches read them from here)
    BLOCK,
    FOUR_FACES,
    GENERATED_TYPES,
    HOOK,
    LEARNED_MODULES,
    MOVABLE_TYPES,
    SLIDE_SECONDS,
    STICK,
    TOOLS,
    TWO_FACES,
    TYPES,
    BodyType,
)
from task_makers.generated_bodies import num as _num

GAP = 0.015  # m: the least gap between two bodies at the start
NEAR_RADIUS = (0.35, 0.72)  # m from the arm's base: inside the fingertip's reach (0.09 to 0.80 m)
FAR_RADIUS = (0.86, 0.98)  # m: beyond the fingertip's reach
SOLVE_TIMEOUT_S = 20
TEST_SOLVE_TIMEOUT_S = 120.0
"""s: what tests that need a generated task solved give its solve. The task's own 20 s deadline is wall-clock
time; these tasks solve in a few seconds idle, but a machine running several suites at once can stretch that past
20 s, and a test must fail for a wrong plan, not for the load. The plan is the same under either deadline."""


@dataclass(frozen=True)
class Placement:
    """A scene body: its scene name, type name and planar pose (m, m, deg)."""

    name: str
    type: str
    x: float
    y: float
    yaw: float


@dataclass(frozen=True)
class TaskSpec:
    """Everything one generated task says, and the metadata the benchmark groups by."""

    name: str
    seed: int
    index: int
    bodies: tuple[Placement, ...]  # the target first, then the clutter, then the tools
    goal: tuple[float, float, float | None]  # x, y (m), yaw (deg) or None: heading free
    reach: str  # near, far-push, far-pull
    in_path: bool
    distance: float  # m, start to goal

    @property
    def scene_name(self) -> str:
        """The scene's name (scenes and tasks share one namespace)."""
        return f"{self.name}_scene"

    @property
    def target(self) -> Placement:
        """The body the goal is about (scene name `target`)."""
        return self.bodies[0]

    @property
    def clutter(self) -> tuple[Placement, ...]:
        """The other movable bodies."""
        return tuple(b for b in self.bodies if b.name.startswith("clutter"))

    def generated_types(self) -> list[BodyType]:
        """The generated body types the scene uses, by name (they need learned affordances)."""
        names = sorted({b.type for b in self.bodies if not TYPES[b.type].stdlib})
        return [TYPES[n] for n in names]

    def metadata(self) -> dict[str, object]:
        """Flat metadata: kind, size class, height, clutter count, reach, in_path, ..."""
        target = TYPES[self.target.type]
        return {
            "name": self.name,
            "seed": self.seed,
            "index": self.index,
            "target_type": target.name,
            "kind": target.kind,
            "size_class": target.size_class,
            "height_cm": round(target.size[2] * 100, 1),
            "size_cm": [round(v * 100, 1) for v in target.size],
            "clutter": len(self.clutter),
            "reach": self.reach,
            "far": self.reach != "near",
            "in_path": self.in_path,
            "yaw_free": self.goal[2] is None,
            "distance_m": round(self.distance, 3),
        }


# ---------------------------------------------------------------- footprints


def footprint(placement: Placement) -> list[np.ndarray]:
    """The footprint of a placed body."""
    return polygons(TYPES[placement.type], placement.x, placement.y, placement.yaw)


# ---------------------------------------------------------------- sampling


def task_spec(seed: int, index: int) -> TaskSpec:
    """The task number `index` of `seed`: a pure function of both."""
    rng = np.random.default_rng([seed, index])
    for _ in range(5000):
        spec = _try_spec(rng, seed, index)
        if spec is not None:
            return spec
    raise RuntimeError(f"no valid task for seed {seed}, index {index}")  # pragma: no cover


def _try_spec(rng: np.random.Generator, seed: int, index: int) -> TaskSpec | None:
    # Stratified by index, so that every kind meets every reach: 7 and 4 are coprime.
    target_type = MOVABLE_TYPES[index % len(MOVABLE_TYPES)]
    reach = ("near", "far-push", "near", "far-pull")[index % 4]
    in_path = index % 5 in (1, 3)
    clutter_count = int(rng.integers(1, 5))
    yaw = float(rng.integers(-6, 7) * 5)
    straight = bool(rng.random() < 0.6)  # along the body's x axis, heading kept; else heading free
    heading = math.radians(yaw)
    if reach == "near":
        radius = rng.uniform(*NEAR_RADIUS)
        backwards = bool(rng.random() < 0.5)
    elif reach == "far-push":
        radius = rng.uniform(0.55, 0.72)
        backwards = False
    else:
        radius = rng.uniform(*FAR_RADIUS)
        backwards = True
    bearing = math.radians(rng.uniform(-35, 35))
    start = np.array([radius * math.cos(bearing), radius * math.sin(bearing)])
    direction = heading + (math.pi if backwards else 0.0)
    if not straight:
        direction += math.radians(rng.choice([-1, 1]) * rng.uniform(10, 30))
    step = np.array([math.cos(direction), math.sin(direction)])
    if reach == "near":
        distance = rng.uniform(0.08, 0.22)
    else:
        distance = rng.uniform(0.2, 0.4)
    if in_path:  # room for a body between the start and the goal
        distance = target_type.size[0] + rng.uniform(0.1, 0.2)
    goal = start + distance * step
    goal_radius = float(np.hypot(*goal))
    if reach == "near" and not NEAR_RADIUS[0] <= goal_radius <= NEAR_RADIUS[1]:
        return None
    if reach == "far-push" and not FAR_RADIUS[0] <= goal_radius <= FAR_RADIUS[1]:
        return None
    if reach == "far-pull" and not 0.45 <= goal_radius <= NEAR_RADIUS[1]:
        return None
    target = Placement("target", target_type.name, _r(start[0]), _r(start[1]), yaw)
    goal_yaw = yaw if straight else None
    goal_pose = (_r(goal[0]), _r(goal[1]), goal_yaw)
    start_fp = footprint(target)
    goal_fp = polygons(target_type, goal_pose[0], goal_pose[1], yaw)
    if not (on_table(start_fp) and on_table(goal_fp)):
        return None
    corridor = [hull(np.vstack(start_fp + goal_fp))]
    tools = [Placement(n, t.name, x, y, a) for n, t, x, y, a in TOOLS]
    placed = [target, *tools]
    if any(overlaps(footprint(t), corridor, GAP) for t in tools):
        return None  # the tools stay out of every straight path: clutter is what blocks it
    clutter: list[Placement] = []
    for k in range(clutter_count):
        name = f"clutter{k + 1}"
        blocking = in_path and k == 0
        body = _place_clutter(rng, name, placed, goal_fp, corridor, start, goal, blocking)
        if body is None:
            return None
        clutter.append(body)
        placed.append(body)
    spec = TaskSpec(
        name=f"gen{seed}_{index:03d}",
        seed=seed,
        index=index,
        bodies=(target, *clutter, *tools),
        goal=goal_pose,
        reach=reach,
        in_path=in_path,
        distance=float(distance),
    )
    return spec


def _place_clutter(
    rng: np.random.Generator,
    name: str,
    placed: list[Placement],
    goal_fp: list[np.ndarray],
    corridor: list[np.ndarray],
    start: np.ndarray,
    goal: np.ndarray,
    blocking: bool,
) -> Placement | None:
    """A clutter body that overlaps no placed body nor the goal; in the corridor iff `blocking`."""
    others = [footprint(other) for other in placed] + [goal_fp]
    for _ in range(30 if blocking else 60):
        kind = MOVABLE_TYPES[int(rng.integers(len(MOVABLE_TYPES)))]
        yaw = float(rng.integers(-6, 7) * 15)
        if blocking:
            at = start + rng.uniform(0.35, 0.75) * (goal - start)
            at = at + rng.uniform(-0.03, 0.03, size=2)
        else:
            at = np.array([rng.uniform(0.3, 1.1), rng.uniform(-0.5, 0.5)])
        body = Placement(name, kind.name, _r(at[0]), _r(at[1]), yaw)
        fp = footprint(body)
        if not on_table(fp) or float(np.hypot(*at)) < 0.3:
            continue
        if any(overlaps(fp, other, GAP) for other in others):
            continue
        if overlaps(fp, corridor) != blocking:
            continue
        return body
    return None


def _r(value: float) -> float:
    """Positions are written with 3 decimals (mm)."""
    return round(float(value), 3)


# ---------------------------------------------------------------- files


def scene_source(spec: TaskSpec) -> str:
    """The `scene.vkg` of a task."""
    uses = ["stdlib.robots.panda", "stdlib.bodies.block", "stdlib.bodies.stick", "stdlib.bodies.hook"]
    lines = [
        f"# Generated by {GENERATOR} (seed {spec.seed}, task {spec.index}). Do not edit.",
        "",
    ]
    lines += [f"use {u}" for u in uses]
    if spec.generated_types():
        lines.append('use "bodies.vkg"')
    lines += [
        "",
        f"scene {spec.scene_name} {{",
        "    table size (1.6, 1.2) m at (0.5, 0, 0) m",
        "    robot arm : Panda at (0, 0, 0) m",
    ]
    for b in spec.bodies:
        lines.append(f"    {b.name} : {b.type} on table at ({_num(b.x)}, {_num(b.y)}) m yaw {_num(b.yaw)}deg")
    lines.append("}")
    return "\n".join(lines) + "\n"


def task_source(spec: TaskSpec) -> str:
    """The `task.vkg` of a task."""
    x, y, yaw = spec.goal
    uses = ['"scene.vkg"', "stdlib.affordances.block", "stdlib.affordances.stick", "stdlib.affordances.hook"]
    uses.append("stdlib.tools")
    if spec.generated_types():
        uses.append('"affordances.vkg"')
    heading = f" yaw {_num(yaw)}deg within 1 cm, 3deg" if yaw is not None else " within 1 cm"
    lines = [
        f"# Generated by {GENERATOR} (seed {spec.seed}, task {spec.index}). Do not edit.",
        "",
    ]
    lines += [f"use {u}" for u in uses]
    lines += [
        "",
        f"task {spec.name} {{",
        f"    scene {spec.scene_name}",
        f"    goal target at ({_num(x)}, {_num(y)}) m{heading}",
        f"    search {{ timeout {SOLVE_TIMEOUT_S} s }}",  # max_depth: the default (the bound makes it cheap)
        "}",
    ]
    return "\n".join(lines) + "\n"


def bodies_source(types: list[BodyType]) -> str:
    """The `bodies.vkg` of a task: its generated body types."""
    header = "# Generated by tests/support/task_makers/generated_tasks.py. Do not edit.\n"
    return header + "".join("\n" + t.source() for t in types)


def write_task(
    spec: TaskSpec,
    folder: Path,
    library: dict[str, Path | None] | None = None,
    *,
    long_slides: bool = True,
    slide_steps: int = 1,
    faces: tuple[str, ...] = TWO_FACES,
) -> Path:
    """Write the task's `.vkg` files into `folder`; return the task file.

    `library` maps a generated body type's name to its learned affordance
    module (`learned_affordances`); without it `affordances.vkg` is not
    written (the scene still compiles, the task does not). `long_slides`:
    whether the bodies declare the long `explore slides` block (else the
    short push grid only); `slide_steps`: its points per face (`BodyType.slide_steps`); `faces`: the side
    faces both explore blocks push on (`BodyType.faces`).
    """
    folder.mkdir(parents=True, exist_ok=True)
    types = [replace(t, long_slides=long_slides, slide_steps=slide_steps, faces=faces) for t in spec.generated_types()]
    if types:
        (folder / "bodies.vkg").write_text(bodies_source(types), encoding="utf-8")
        if library is not None:
            modules = [library[t.name] for t in types]
            blocks = [_affordance_blocks(m.read_text(encoding="utf-8")) for m in modules if m is not None]
            text = '# Learned with vkgl.learn (cached by body source hash). Do not edit.\n\nuse "bodies.vkg"\n'
            (folder / "affordances.vkg").write_text(text + "".join("\n" + b for b in blocks), encoding="utf-8")
    (folder / "scene.vkg").write_text(scene_source(spec), encoding="utf-8")
    task_file = folder / "task.vkg"
    task_file.write_text(task_source(spec), encoding="utf-8")
    return task_file


def _affordance_blocks(module: str) -> str:
    """The `affordances NAME { ... }` blocks of a learned module, without its header and `use`."""
    at = module.find("\naffordances ")
    if at < 0:
        raise ValueError("the learned module holds no affordances block")
    return module[at + 1 :]


def learned_affordances(types: list[BodyType], cache: Path, *, jobs: int | None = None) -> dict[str, Path | None]:
    """Each generated type's learned affordance module, learning (with `vkgl.learn`) only what the cache lacks.

    The cache holds one folder per body source hash: `body.vkg` and the module
    `vkgl.learn` wrote from it, or `failed.txt` saying why learning found no
    affordance (the type then maps to None: nothing can move it).
    """
    import vkgl
    from vkgl.errors import InputError

    out: dict[str, Path | None] = {}
    for body in types:
        folder = cache / body.source_hash()
        module = folder / f"{body.name.lower()}.vkg"
        if not folder.is_dir():
            # one partial folder per process: two benches learning the same body at once (they share the cache)
            # must not write into, or delete, each other's; the first to finish keeps its folder
            partial = folder.with_name(f"{folder.name}.partial.{os.getpid()}")
            shutil.rmtree(partial, ignore_errors=True)
            partial.mkdir(parents=True)
            (partial / "body.vkg").write_text(body.source(), encoding="utf-8")
            try:
                vkgl.learn([partial / "body.vkg"], out_dir=partial, jobs=jobs)
            except InputError as exc:
                (partial / "failed.txt").write_text(f"{exc}\n", encoding="utf-8")
            try:
                partial.rename(folder)
            except OSError:  # another process learned it first (the same trials: deterministic)
                if not folder.is_dir():
                    raise
                shutil.rmtree(partial, ignore_errors=True)
        out[body.name] = module if module.is_file() else None
    return out


@dataclass(frozen=True)
class GeneratedTask:
    """A written task: its spec, its folder and task file."""

    spec: TaskSpec
    folder: Path
    task_file: Path

    @property
    def name(self) -> str:
        """The task's (and scene's) name."""
        return self.spec.name

    def metadata(self) -> dict[str, object]:
        """The spec's metadata plus the task file."""
        return {**self.spec.metadata(), "task_file": str(self.task_file)}


def generate_tasks(
    seed: int,
    count: int,
    out_dir: Path,
    *,
    cache: Path | None = None,
    jobs: int | None = None,
    long_slides: bool = True,
    faces: tuple[str, ...] = TWO_FACES,
) -> list[GeneratedTask]:
    """Write `count` tasks of `seed` into `out_dir/<name>/`; learn affordances into `cache` when given.

    `long_slides=False` explores the generated bodies with the short push grid only (no `explore slides`);
    `faces`: the side faces they are explored on (`FOUR_FACES`: pushed sideways too, not only along x).
    """
    specs = [task_spec(seed, i) for i in range(count)]
    library = None
    if cache is not None:
        types = sorted({t for s in specs for t in s.generated_types()}, key=lambda t: t.name)
        explored = [replace(t, long_slides=long_slides, faces=faces) for t in types]
        library = learned_affordances(explored, cache, jobs=jobs)
    return [
        GeneratedTask(
            s, out_dir / s.name, write_task(s, out_dir / s.name, library, long_slides=long_slides, faces=faces)
        )
        for s in specs
    ]


GENERATOR = "tests/support/task_makers/generated_tasks.py"
"""Named in the header of every file it writes."""

FIXTURES = Path(__file__).resolve().parents[2] / "bench" / "learned"
"""The tests' learned modules of the generated types, in the layout of `learned_affordances`'s cache."""


WIDE_TYPES = ("SlabW", "CrateM", "CrateT")
"""The generated types 24 to 30 cm wide: the hook pulls them from 1.0 m off their far face's centre (its shaft
would lie inside them at the centre), so their fixtures are also learned with `slide_steps` 5 (long turns)."""

WIDE_SLIDE_STEPS = 5
"""Long pushes at 5 points per face: the centre and 6 and 12 cm (4.8 and 9.6 cm on a 24 cm face) each side."""


def fixture_library(names: tuple[str, ...] | None = None, *, slide_steps: int = 1) -> dict[str, Path | None]:
    """Each generated type's learned module (`names`: those types only; `slide_steps`: explored with long pushes
    at that many points per face) from the tests' fixtures (None: learning found no affordance); fails saying how
    to refresh them when a type's source changed."""
    library: dict[str, Path | None] = {}
    for body in (replace(t, slide_steps=slide_steps) for t in GENERATED_TYPES if names is None or t.name in names):
        folder = FIXTURES / body.source_hash()
        assert folder.is_dir(), (
            f"no learned affordances of {body.name} for its current source under {FIXTURES}: refresh them with "
            f'`python -c "import generated_tasks as g; from dataclasses import replace; from pathlib import Path; '
            f"g.learned_affordances([replace(t, slide_steps={slide_steps}) for t in g.GENERATED_TYPES], "
            f"Path('{FIXTURES}'))\"` (PYTHONPATH=tests/support)"
        )
        assert (folder / "body.vkg").read_text(encoding="utf-8") == body.source()
        module = folder / f"{body.name.lower()}.vkg"
        library[body.name] = module if module.is_file() else None
    return library


def body_uses(name: str, folder: Path) -> str | None:
    """The `use` lines that bring body type `name` and its affordances into a task written in `folder` (the stdlib
    Block's modules, or the learned fixture's copied into `folder`); None when learning found no affordance."""
    if name == "Block":
        return "use stdlib.bodies.block\nuse stdlib.affordances.block\n"
    module = fixture_library()[name]
    if module is None:
        return None
    (folder / "body.vkg").write_text(module.with_name("body.vkg").read_text(encoding="utf-8"), encoding="utf-8")
    (folder / "affordances.vkg").write_text(module.read_text(encoding="utf-8"), encoding="utf-8")
    return 'use "affordances.vkg"\n'
