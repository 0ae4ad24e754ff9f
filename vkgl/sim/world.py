"""DART worlds built from the IR: the table, and bodies with their shapes, mass and joints.

Used by exploration (`vkgl.sim.explore`) and by plan execution
(`vkgl.execute.replay`), so that a body behaves the same wherever it is simulated.

Choices (docs/exploration.md explains them):
- time step 1 ms, gravity -9.81 m/s^2 along z;
- collision detection by ODE's detector: it gives multi-point contact
  manifolds for box, cylinder and mesh pairs (DART's own detector and FCL let
  a cylinder sink into the table, see the docs);
- contacts and joint limits by DART's friction-cone solver (NSGS, Coulomb law:
  `use_contact_solver`), in every world: exploration learns the models in the
  same physics that execution carries the plans out in (`PHYSICS_REVISION`
  names it, so that nothing learned under another physics is reused); grasp
  trials alone keep DART's boxed LCP (`new_grasp_world` says why); execution
  keeps exploration's stop of the solver's sweeps too (`EXECUTION_SOLVER_TOLERANCE`
  says what a looser one changed);
- friction: DART pairs two surfaces with the smaller of their coefficients; the
  table's is 1.0, so a body slides on the table with exactly the coefficient it
  declares (`friction`, default 0.5).

Bodies: shapes become DART shapes (box, cylinder, mesh, or one shape node per
part of a union); the mass properties come from the body's triangle mesh
(trimesh) scaled to the declared mass. A body without a joint hangs on a free
joint; a body with `joint prismatic|revolute` hangs on that joint, anchored to
the world where the body stands, with its limits enforced and its `damping`
and `friction` (Coulomb) if it declares them.
"""

from __future__ import annotations

from typing import Any

import dartpy as dart
import numpy as np
import trimesh

from vkgl.errors import InputError
from vkgl.lang.ir.geometry import JOINT_LIFT, shape_mesh
from vkgl.lang.ir.nodes import Body, Quantity, Table
from vkgl.shapes import dart_shapes, isometry, translation

TIME_STEP = 0.001  # s
GRAVITY = (0.0, 0.0, -9.81)  # m/s^2
DEFAULT_FRICTION = 0.5  # for bodies that declare none
TABLE_FRICTION = 1.0  # >= any sensible body coefficient: the body's own coefficient governs
TABLE_THICKNESS = 0.05  # m
EXPLORATION_TABLE_SIZE = (2.0, 2.0)  # m, centred under the explored body
JOINT_CLEARANCE = JOINT_LIFT  # m a jointed body is lifted so that it hangs on its joint (the planner's lift too)
# What the worlds simulate, named: learned models depend on it, so caches of them are keyed by it. Bump it with any
# change to `new_world`'s or `new_grasp_world`'s settings (revision 1 explored pushes under DART's default boxed LCP,
# friction bounded along world x and y).
PHYSICS_REVISION = "vkgl-physics/2 (ODE contacts, NSGS Coulomb friction cone, 1 ms)"
EXECUTION_SOLVER_TOLERANCE: float | None = None
"""The residual at which the friction-cone solver stops its sweeps in the execution world: None, DART's 1e-5, the
same as exploration's (one physics). Tried and measured (docs/execution.md, "The contact solver's tolerance"): at
1e-4 a push step costs a quarter of the CPU and straight pushes end within 0.06 mm of where they end at 1e-5, but
a crate turned 67 deg by the fingertip about its arc (the physical bench's gen2_046) ended 6 deg further round and
missed its goal by 1.44 cm (0.37 cm at 1e-5): what the laws were learned in is what plans are carried out in."""


def new_world(time_step: float = TIME_STEP, *, tolerance: float | None = None) -> Any:
    """An empty DART world with the project's gravity, collision detector and contact solver (the cone);
    `tolerance`: the solver's stopping residual (None: DART's, every world's; bench/sim/bench_step.py tries 1e-4)."""
    world = _bare_world(time_step)
    use_contact_solver(world, tolerance)
    return world


def _bare_world(time_step: float) -> Any:
    """An empty DART world with the project's time step, gravity and collision detector; DART's default
    contact solver (the boxed LCP: Dantzig, PGS as fallback, one thread)."""
    world = dart.simulation.World()
    world.setTimeStep(time_step)
    world.setGravity(np.array(GRAVITY))
    world.setCollisionDetector(dart.collision.OdeCollisionDetector())
    return world


def use_contact_solver(world: Any, tolerance: float | None = None) -> None:
    """Solve contacts with DART's friction-cone solver (NSGS, Coulomb law) instead of its default boxed LCP.

    The boxed LCP bounds friction separately along two fixed tangent axes
    (world x and y on the table): a body pushed at an angle to them slides
    along the nearer axis instead of the way it is pushed (a block pushed
    10 cm along a heading of -20 deg ended 3.6 cm to the side), and a tall
    crate pushed off its centre turns 11.7 deg where the cone turns it 35.
    The cone treats every direction alike. Every world uses it (through
    `new_world`): a model learned under one friction law and carried out
    under another misses (docs/exploration.md, "The contact solver").
    `tolerance` (None: DART's 1e-5) is where its sweeps stop.
    """
    solver = dart.constraint.NsgsFrictionSolver()
    options = dart.constraint.NsgsFrictionSolver.Options()
    options.law = dart.constraint.NsgsFrictionSolver.Law.Coulomb
    if tolerance is not None:
        options.tolerance = tolerance
    solver.setOptions(options)
    world.getConstraintSolver().setBoxedLcpSolver(solver)


def new_grasp_world(time_step: float = TIME_STEP) -> Any:
    """`new_world` with DART's boxed LCP (Dantzig, PGS as fallback) for contacts: the world of a grasp trial.

    Only here does a body rest on DART's contacts between two pressed fingers,
    and the friction cone does not hold it there at a 1 ms step: the fingers
    sink 3 mm into the stdlib Stick and it turns 16 deg in the grip under its
    own weight, where the pads' friction carries 0.27 N m against its 0.15
    (docs/execution.md, "The grip on a held tool"). Under the cone the stdlib
    Hook kept none of its grasps (each slipped 5 mm on the 10 cm lift).
    Execution does not hold a tool on DART's finger contacts either: it
    models the pads' Coulomb friction (`vkgl.execute.grip`). Pushes, which
    execution does simulate contact by contact, are explored in `new_world`.
    """
    return _bare_world(time_step)


def solver_settings(world: Any) -> dict[str, object]:
    """What a world simulates with, read back from DART: time step, gravity, collision detector, contact solvers.

    Two worlds with equal settings simulate the same physics (the bodies in them aside).
    """
    solver = world.getConstraintSolver()
    primary = solver.getBoxedLcpSolver()
    secondary = solver.getSecondaryBoxedLcpSolver()
    option = solver.getCollisionOption()
    settings: dict[str, object] = {
        "time_step": float(world.getTimeStep()),
        "gravity": tuple(float(g) for g in world.getGravity()),
        "collision_detector": world.getCollisionDetector().getType(),
        "contacts": (bool(option.enableContact), int(option.maxNumContacts)),
        "solver": primary.getType(),
        "fallback": secondary.getType() if secondary is not None else None,
        "split_impulse": bool(solver.isSplitImpulseEnabled()),
        "threads": int(solver.getNumSimulationThreads()),
    }
    if isinstance(primary, dart.constraint.NsgsFrictionSolver):
        options = primary.getOptions()
        settings["friction"] = (str(options.law), int(options.maxSweeps), float(options.tolerance))
    return settings


def add_table(world: Any, table: Table | None = None) -> tuple[Any, Any]:
    """Add a static table (a box whose top is the table's z) and return (skeleton, body node).

    Without a `Table`, the exploration table: 2 x 2 m, top at z = 0, centred on the origin.
    """
    size: tuple[float, ...]
    centre: tuple[float, ...]
    if table is None:
        size, centre = EXPLORATION_TABLE_SIZE, (0.0, 0.0, 0.0)
    else:
        size = tuple(table.size.values[:2])
        values = list(table.position.values) + [0.0] * (3 - len(table.position.values))
        centre = tuple(values[:3])
    skeleton = dart.dynamics.Skeleton("table")
    joint, node = skeleton.createWeldJointAndBodyNodePair()
    joint.setTransformFromParentBodyNode(
        isometry(translation(np.array([centre[0], centre[1], centre[2] - TABLE_THICKNESS / 2])))
    )
    node.setName("table")
    shape = node.createShapeNode(dart.dynamics.BoxShape(np.array([size[0], size[1], TABLE_THICKNESS])))
    shape.createVisualAspect()
    shape.createCollisionAspect()
    shape.createDynamicsAspect().setFrictionCoeff(TABLE_FRICTION)
    world.addSkeleton(skeleton)
    return skeleton, node


def add_body(
    world: Any, name: str, body: Body, pose: np.ndarray, joint_position: float | None = None
) -> tuple[Any, Any]:
    """Add `body` standing at the 4x4 world `pose`; return (skeleton, body node).

    The body node's frame is the body frame. A body with a physical joint is
    anchored to the world at `pose` (joint position 0), lifted by
    JOINT_CLEARANCE so that it does not rub on the table it stands on; it
    starts at `joint_position` (SI, clipped to its limits), by default at 0
    or the limit nearest to it.
    """
    skeleton = dart.dynamics.Skeleton(name)
    pose = np.asarray(pose, dtype=float)
    if body.joint is None:
        joint, node = skeleton.createFreeJointAndBodyNodePair()
        joint.setPositions(dart.dynamics.FreeJoint.convertToPositions(isometry(pose)))
    else:
        anchor = translation(np.array([0.0, 0.0, JOINT_CLEARANCE])) @ pose
        joint, node = _add_jointed(skeleton, body, anchor, 0.0 if joint_position is None else joint_position)
    node.setName(name)
    dress_body_node(node, body)
    world.addSkeleton(skeleton)
    return skeleton, node


def _add_jointed(skeleton: Any, body: Body, anchor: np.ndarray, position: float) -> tuple[Any, Any]:
    spec = body.joint
    assert spec is not None
    axis = spec.axis.array()
    norm = float(np.linalg.norm(axis))
    if norm == 0.0:
        raise InputError(f"{spec.axis.span or body.name}: the joint axis of {body.name} is zero; give a direction")
    through = spec.through.array() if spec.through is not None else np.zeros(3)
    if spec.type == "prismatic":
        joint, node = skeleton.createPrismaticJointAndBodyNodePair()
    else:
        joint, node = skeleton.createRevoluteJointAndBodyNodePair()
    # The joint frame sits on the axis (at `through`), in the body's orientation.
    joint.setTransformFromParentBodyNode(isometry(anchor @ translation(through)))
    joint.setTransformFromChildBodyNode(isometry(translation(through)))
    joint.setAxis(axis / norm)
    lower, upper = spec.lower.value, spec.upper.value
    if lower > upper:
        raise InputError(
            f"{spec.span or body.name}: the joint limits of {body.name} are reversed "
            f"({lower:g} > {upper:g}); write them as (lower, upper)"
        )
    joint.setPositionLowerLimit(0, lower)
    joint.setPositionUpperLimit(0, upper)
    joint.setLimitEnforcement(True)
    joint.setPosition(0, min(max(position, lower), upper))  # by default the declared pose, or the nearest limit
    # Viscous damping (N*s/m or N*m*s/rad: DART integrates it implicitly, stable for any value) and Coulomb
    # friction (N or N*m: a constraint of the LCP solver, so a push below it leaves the joint at rest).
    if spec.damping is not None:
        joint.setDampingCoefficient(0, _non_negative(spec.damping, f"the damping of {body.name}'s joint"))
    if spec.friction is not None:
        joint.setCoulombFriction(0, _non_negative(spec.friction, f"the friction of {body.name}'s joint"))
    return joint, node


def _non_negative(q: Quantity, what: str) -> float:
    """The SI value of `q` if it is finite and >= 0 (as the checker wants, E440), else an InputError."""
    if not (np.isfinite(q.value) and q.value >= 0.0):
        raise InputError(f"{q.span or 'the IR'}: {what} must be zero or positive, got {q.value:g}")
    return float(q.value)


def dress_body_node(node: Any, body: Body) -> None:
    """Give a DART body node the body's collision shapes, friction and mass properties."""
    friction = body.friction if body.friction is not None else DEFAULT_FRICTION
    for shape, pose in dart_shapes(body.shape):
        shape_node = node.createShapeNode(shape)
        shape_node.setRelativeTransform(isometry(pose))
        shape_node.createVisualAspect()
        shape_node.createCollisionAspect()
        shape_node.createDynamicsAspect().setFrictionCoeff(friction)
    mass, com, inertia = mass_properties(body)
    node.setInertia(dart.dynamics.Inertia(mass, com, inertia))


def mass_properties(body: Body) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, centre of mass, inertia tensor about the centre of mass), body frame, SI.

    Uniform density over the body's solid (trimesh); a mesh that does not
    enclose a volume is replaced by its convex hull for this purpose.
    """
    mass = float(body.mass.value)
    if not np.isfinite(mass) or mass <= 0.0:
        raise InputError(f"{body.mass.span or body.name}: the mass of {body.name} must be positive")
    mesh = solid_mesh(shape_mesh(body.shape), f"{body.span or body.name}: the shape of body `{body.name}`")
    volume = float(mesh.volume)
    mesh.density = mass / volume
    inertia = np.asarray(mesh.moment_inertia, dtype=float)
    return mass, np.asarray(mesh.center_mass, dtype=float), 0.5 * (inertia + inertia.T)


def solid_mesh(mesh: trimesh.Trimesh, what: str = "the shape") -> trimesh.Trimesh:
    """The mesh if it encloses a volume, else its convex hull; `what` names it in the error if neither does."""
    if mesh.is_volume and mesh.volume > 0.0:
        return mesh
    hull = mesh.convex_hull
    if hull.volume <= 0.0:
        raise InputError(f"{what} encloses no volume (it is flat or degenerate), so it cannot carry a mass")
    return hull
