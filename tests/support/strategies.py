"""Hypothesis strategies that generate valid IR modules (as the parser would build them).

Every value a strategy draws is one the parser can produce: SI floats that are
the conversion of some decimal in the display unit (any finite float is, with
the exact conversion), display units of the right dimension, names that are
not keywords, 2-vectors where a planar position is meant. Spans are left None
(equality ignores them).

Every strategy is built once (`functools.cache`): the `flatmap`s ask for one per draw (a unit drawn, then the
values in it), and Hypothesis validates each new strategy object, its parts again, before drawing from it. Reused,
they draw the same examples from the same choices, at a third of the cost.
"""

from __future__ import annotations

import functools
import string

from hypothesis import strategies as st

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import to_si

PATH = "generated.vkg"

UNITS = {
    "length": ["m", "cm", "mm"],
    "angle": ["deg", "rad"],
    "mass": ["kg", "g"],
    "force": ["N"],
    "time": ["s", "ms"],
    "linear damping": ["N*s/m"],
    "angular damping": ["N*m*s/rad"],
    "torque": ["N*m"],
}

KEYWORDS = frozenset(
    [
        "use",
        "body",
        "shape",
        "mass",
        "friction",
        "frame",
        "joint",
        "prismatic",
        "revolute",
        "axis",
        "through",
        "limits",
        "damping",
        "open",
        "explore",
        "contacts",
        "on",
        "faces",
        "steps",
        "heights",
        "tips",
        "above",
        "force",
        "normal",
        "directions",
        "x",
        "grasp",
        "duration",
        "box",
        "cylinder",
        "radius",
        "height",
        "mesh",
        "scale",
        "union",
        "at",
        "yaw",
        "rpy",
        "robot",
        "urdf",
        "effector",
        "link",
        "offset",
        "affordances",
        "affordance",
        "action",
        "motion",
        "evidence",
        "trials",
        "loglik",
        "posterior",
        "fixed",
        "along",
        "from",
        "about",
        "free",
        "correspondences",
        "scene",
        "table",
        "size",
        "task",
        "goal",
        "and",
        "within",
        "search",
        "max_depth",
        "timeout",
        "range",
        "to",
        "moved",
        "turned",
        "by",
        "in",
        "region",
        "polygon",
        "keep",
        "out",
        "of",
        "m",
        "cm",
        "mm",
        "deg",
        "rad",
        "kg",
        "g",
        "N",
        "s",
        "ms",
    ]
)

FACES = ["+x", "-x", "+y", "-y", "+z", "-z"]

# Names that start like a keyword or a unit: the lexer must not split them.
TRICKY_NAMES = ["mass1", "box_", "cm2", "deg_", "at_", "x1", "rad90", "Stick", "tip", "_a", "goals", "uses"]


# ---------------------------------------------------------------- leaves


@functools.cache
def names() -> st.SearchStrategy[str]:
    """Identifiers `[A-Za-z_][A-Za-z0-9_]*` that are not keywords or units."""
    generated = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,8}", fullmatch=True).filter(lambda s: s not in KEYWORDS)
    return st.one_of(st.sampled_from(TRICKY_NAMES), generated)


@functools.cache
def refs() -> st.SearchStrategy[ir.Ref]:
    return st.builds(ir.Ref, name=names())


@functools.cache
def file_paths(ext: str) -> st.SearchStrategy[str]:
    """Relative paths without quotes, backslashes or newlines (string literals have no escapes)."""
    part = st.text(alphabet=string.ascii_letters + string.digits + "_- .", min_size=1, max_size=8)
    return st.lists(part, min_size=1, max_size=3).map(lambda parts: "/".join(parts) + ext)


@functools.cache
def counts(low: int = 1, high: int = 50) -> st.SearchStrategy[int]:
    return st.integers(min_value=low, max_value=high)


@functools.cache
def plain_floats() -> st.SearchStrategy[float]:
    """Dimensionless numbers: short decimals, integers, negative ones, and any finite float."""
    short = st.builds(lambda n, k: float(f"{n}e-{k}"), st.integers(-100000, 100000), st.integers(0, 6))
    return st.one_of(short, st.floats(allow_nan=False, allow_infinity=False))


@functools.cache
def si_values(unit: str) -> st.SearchStrategy[float]:
    """SI values as the parser computes them from a number written in `unit`."""
    written = st.builds(lambda n, k: to_si(f"{n}e-{k}", unit), st.integers(-100000, 100000), st.integers(0, 5))
    anything = st.floats(allow_nan=False, allow_infinity=False)
    return st.one_of(written, written, anything)


@functools.cache
def units(dimension: str) -> st.SearchStrategy[str]:
    return st.sampled_from(UNITS[dimension])


@functools.cache
def quantities(dimension: str) -> st.SearchStrategy[ir.Quantity]:
    return units(dimension).flatmap(lambda u: st.builds(ir.Quantity, value=si_values(u), unit=st.just(u)))


@functools.cache
def vectors(dimension: str | None, n: int) -> st.SearchStrategy[ir.Vector]:
    """`n` components in one unit of `dimension`, or unitless (directions) when None."""
    if dimension is None:
        return st.builds(ir.Vector, values=st.tuples(*[plain_floats()] * n), unit=st.just(""))
    return units(dimension).flatmap(
        lambda u: st.builds(ir.Vector, values=st.tuples(*[si_values(u)] * n), unit=st.just(u))
    )


@functools.cache
def poses(n: int = 3, rpy: bool = True) -> st.SearchStrategy[ir.Pose]:
    """A position with no rotation, a yaw or (if `rpy`) roll-pitch-yaw angles."""
    position = vectors("length", n)
    options = [
        st.builds(ir.Pose, position=position),
        st.builds(ir.Pose, position=position, yaw=quantities("angle")),
    ]
    if rpy:
        options.append(st.builds(ir.Pose, position=position, rpy=vectors("angle", 3)))
    return st.one_of(options)


# ---------------------------------------------------------------- shapes and bodies


@functools.cache
def simple_shapes() -> st.SearchStrategy[ir.Shape]:
    return st.one_of(
        st.builds(ir.BoxShape, size=vectors("length", 3)),
        st.builds(ir.CylinderShape, radius=quantities("length"), height=quantities("length")),
        st.builds(ir.MeshShape, path=file_paths(".stl"), scale=st.one_of(st.just(1.0), plain_floats())),
    )


@functools.cache
def shapes() -> st.SearchStrategy[ir.Shape]:
    """Boxes, cylinders, meshes and unions of them, nested up to a few levels."""

    def unions(children: st.SearchStrategy[ir.Shape]) -> st.SearchStrategy[ir.Shape]:
        part = st.builds(ir.ShapePart, shape=children, pose=poses())
        return st.builds(ir.UnionShape, parts=st.lists(part, min_size=1, max_size=3))

    return st.recursive(simple_shapes(), unions, max_leaves=6)


@functools.cache
def joints() -> st.SearchStrategy[ir.Joint]:
    """Prismatic and revolute joints, each with or without a damping and a friction of its kind."""

    @functools.cache
    def joint(kind: str, unit: str) -> st.SearchStrategy[ir.Joint]:
        limit = st.builds(ir.Quantity, value=si_values(unit), unit=st.just(unit))
        damping, friction = ("linear damping", "force") if kind == "prismatic" else ("angular damping", "torque")
        return st.builds(
            ir.Joint,
            type=st.just(kind),
            axis=vectors(None, 3),
            through=st.none() | vectors("length", 3),
            lower=limit,
            upper=limit,
            damping=st.none() | quantities(damping),
            friction=st.none() | quantities(friction),
        )

    return st.one_of(
        units("length").flatmap(lambda u: joint("prismatic", u)),
        units("angle").flatmap(lambda u: joint("revolute", u)),
    )


@functools.cache
def force_specs() -> st.SearchStrategy[ir.ForceSpec]:
    return st.one_of(
        st.builds(ir.ForceSpec, mode=st.just("normal"), magnitude=quantities("force")),
        st.builds(
            ir.ForceSpec,
            mode=st.just("directions"),
            grid=st.tuples(counts(1, 9), counts(1, 9), counts(1, 9)),
            magnitude=quantities("force"),
        ),
    )


@functools.cache
def explores() -> st.SearchStrategy[ir.Explore]:
    on_faces = st.builds(
        ir.ContactSpec,
        faces=st.lists(st.sampled_from(FACES), min_size=1, max_size=4),
        steps=counts(),
        heights=st.just(1) | counts(),
    )
    at_frames = st.builds(ir.ContactSpec, frames=st.lists(refs(), min_size=1, max_size=3))
    contacts = on_faces | at_frames
    return st.builds(
        ir.Explore,
        name=names(),
        contacts=st.none() | contacts,
        grasp=st.none() | refs(),
        force=st.none() | force_specs(),
        duration=st.none() | quantities("time"),
    )


@functools.cache
def grasp_policies() -> st.SearchStrategy[ir.GraspPolicy]:
    """`explore grasps { ... }` with any subset of its items (approaches: any names; the checker knows the words)."""
    return st.builds(
        ir.GraspPolicy,
        approaches=st.none() | st.lists(names(), min_size=1, max_size=3),
        max_width=st.none() | quantities("length"),
        force=st.none() | quantities("force"),
        lift=st.none() | quantities("length"),
        slip=st.none() | quantities("length"),
        trials=st.none() | counts(0, 1000),
    )


@functools.cache
def bodies() -> st.SearchStrategy[ir.Body]:
    frame = st.builds(ir.Frame, name=names(), pose=poses())
    return st.builds(
        ir.Body,
        name=names(),
        shape=shapes(),
        mass=quantities("mass"),
        friction=st.none() | plain_floats(),
        frames=st.lists(frame, max_size=3),
        joint=st.none() | joints(),
        explores=st.lists(explores(), max_size=2),
        grasps=st.none() | grasp_policies(),
    )


# ---------------------------------------------------------------- robots, affordances, correspondences


@functools.cache
def robots() -> st.SearchStrategy[ir.Robot]:
    effector = st.builds(ir.Effector, name=names(), link=names(), offset=poses())
    return st.builds(ir.Robot, name=names(), urdf=file_paths(".urdf"), effectors=st.lists(effector, max_size=3))


@functools.cache
def motion_ranges(dimension: str) -> st.SearchStrategy[ir.MotionRange | None]:
    """No range, or `range LO to HI UNIT [open]` with both bounds in one unit or each in its own."""

    @functools.cache
    def bounds(lower_unit: str, upper_unit: str) -> st.SearchStrategy[ir.MotionRange]:
        return st.builds(
            ir.MotionRange,
            lower=st.builds(ir.Quantity, value=si_values(lower_unit), unit=st.just(lower_unit)),
            upper=st.builds(ir.Quantity, value=si_values(upper_unit), unit=st.just(upper_unit)),
            open=st.booleans(),
        )

    same = units(dimension).flatmap(lambda u: bounds(u, u))
    mixed = st.tuples(units(dimension), units(dimension)).flatmap(lambda us: bounds(*us))
    return st.none() | same | mixed


@functools.cache
def constraints(ranged: bool = False) -> st.SearchStrategy[ir.Constraint]:
    """Any constraint; with `ranged` (a motion), prismatic and revolute ones may carry a `range`."""
    slide_range = motion_ranges("length") if ranged else st.none()
    turn_range = motion_ranges("angle") if ranged else st.none()
    return st.one_of(
        st.builds(ir.FixedC, pose=st.none() | poses()),
        st.builds(ir.PrismaticC, axis=vectors(None, 3), origin=st.none() | vectors("length", 3), range=slide_range),
        st.builds(ir.RevoluteC, center=vectors("length", 3), axis=vectors(None, 3), range=turn_range),
        st.builds(ir.FreeC),
        grasps(),
    )


@functools.cache
def grasps() -> st.SearchStrategy[ir.GraspC]:
    """`grasp at POSE width W force F`, its width and force in any unit of theirs."""
    return st.tuples(units("length"), units("force")).flatmap(
        lambda us: st.builds(
            ir.GraspC,
            pose=poses(),
            width=si_values(us[0]),
            width_unit=st.just(us[0]),
            force=si_values(us[1]),
            force_unit=st.just(us[1]),
        )
    )


@functools.cache
def evidences() -> st.SearchStrategy[ir.Evidence]:
    """`evidence trials N loglik L posterior P`, with a `slip` in any length unit or none."""
    slips = units("length").flatmap(lambda u: st.tuples(si_values(u), st.just(u)))
    return st.builds(
        lambda trials, loglik, posterior, slip: ir.Evidence(
            trials=trials,
            loglik=loglik,
            posterior=posterior,
            slip=None if slip is None else slip[0],
            slip_unit="mm" if slip is None else slip[1],
        ),
        counts(0, 1000),
        plain_floats(),
        plain_floats(),
        st.none() | slips,
    )


@functools.cache
def families() -> st.SearchStrategy[ir.Family]:
    """`family along DIR from LO to HI UNIT [drift VEC] [arc ...] [sigma Q]`, bounds in one unit or each in its own."""

    @functools.cache
    def family(lower_unit: str, upper_unit: str) -> st.SearchStrategy[ir.Family]:
        return st.builds(
            ir.Family,
            along=vectors(None, 3),
            lower=st.builds(ir.Quantity, value=si_values(lower_unit), unit=st.just(lower_unit)),
            upper=st.builds(ir.Quantity, value=si_values(upper_unit), unit=st.just(upper_unit)),
            drift=st.none() | vectors(None, 3),
            arc=st.none() | arcs(),
            sigma=st.none() | quantities("length") | quantities("angle"),
        )

    return st.tuples(units("length"), units("length")).flatmap(lambda us: family(*us))


@functools.cache
def arcs() -> st.SearchStrategy[ir.Arc]:
    """`arc lever Q bias Q ahead Q`: three lengths, each in its own unit."""
    return st.builds(ir.Arc, lever=quantities("length"), bias=quantities("length"), ahead=quantities("length"))


@functools.cache
def affordance_sets() -> st.SearchStrategy[ir.AffordanceSet]:
    evidence = evidences()
    affordance = st.builds(
        ir.Affordance,
        name=names(),
        action=constraints(),
        motion=constraints(ranged=True),
        family=st.none() | families(),
        evidence=st.none() | evidence,
    )
    tipping = st.builds(
        ir.Tipping, height=quantities("length"), faces=st.lists(st.sampled_from(FACES), max_size=4, unique=True)
    )
    return st.builds(
        ir.AffordanceSet,
        body=refs(),
        affordances=st.lists(affordance, min_size=1, max_size=3),
        tipping=st.lists(tipping, max_size=2),
    )


@functools.cache
def correspondence_blocks() -> st.SearchStrategy[ir.Correspondences]:
    item = st.builds(ir.Correspondence, frame=st.builds(ir.FrameRef, body=names(), frame=names()), effector=refs())
    return st.builds(ir.Correspondences, items=st.lists(item, min_size=1, max_size=3))


# ---------------------------------------------------------------- scenes, tasks
