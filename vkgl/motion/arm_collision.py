"""The arm's links (and a tool in its hand) against the bodies and the table, at a joint configuration.

The link geometry is the URDF's own `<collision>` elements (the Panda's are
cylinders and boxes, stdlib/robots/panda.urdf) as DART loads them: the arm's
skeleton is a clone of the one its `Arm` parsed, with the base pose put on its
root joint, and its collision shape nodes form one FCL group. A query sets the
joint positions (DART updates the links' transforms) and collides that group
with the scene's cached group of the bodies in question: one call into C++,
FCL's broad phase included. That makes it usable as the state-validity check
of transit planning (bench/robot/bench_collision.py: tens of microseconds per
configuration with 10 bodies and the table).

Self-collision of the arm is not checked here.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import dartpy as dart
import numpy as np

from vkgl.motion.clearance import SAFETY, Clearance, cover_box, cover_shape, scene_boxes, spheres_to_boxes
from vkgl.motion.collision import TABLE, CollisionScene, Contact
from vkgl.robot import Arm, load_skeleton
from vkgl.robot.kinematics import link_probe
from vkgl.robot.pad import FINGER_PAD_WIDTH, FINGERTIP_RADIUS, pad_pose

PAD = "fingertip"
"""What contacts call the fingertip pad."""


@dataclass(frozen=True)
class Held:
    """A scene body held in the hand: `in_hand` is its pose in the effector frame (the frame `Arm.fk` gives).

    For a tool grasped by an affordance whose action pose is `A` (the effector
    frame in the tool's frame), `in_hand` is `inv(A)`. `acts_on`: bodies the
    tool may touch (the one it pushes or pulls). `opening`: m each finger stands
    open around the tool (`vkgl.robot.grip.holding_opening`: as the executor
    closes them onto its faces); the fingers are checked so opened while it is
    held, closed otherwise (the hand pushes with its closed fingertip).
    """

    body: str
    in_hand: np.ndarray
    acts_on: frozenset[str] = frozenset()
    opening: float = 0.0


class ArmCollision:
    """The collision shapes of an arm's links, checked against a `CollisionScene`.

    Built once per planning problem (it groups the URDF's shapes; the clone of
    the arm's skeleton that carries them is made once per process); each query
    costs one forward kinematics of the clone and one FCL call per group (two
    when a tool is held).
    """

    def __init__(self, scene: CollisionScene, arm: Arm, skip_links: Iterable[str] = ()) -> None:
        """The links of `arm` (all with collision geometry, but `skip_links`) against `scene`'s bodies."""
        self.scene = scene
        self.arm = arm
        self.skeleton, shape_nodes, pad = _collision_links(arm)
        self._dofs = [int(self.skeleton.getJoint(name).getIndexInSkeleton(0)) for name in arm.joint_names]
        self._all_dofs = self._dofs == list(range(self.skeleton.getNumDofs()))
        self._finger_dofs = _finger_dofs(self.skeleton, arm)
        self._opening = 0.0
        self._link = _probe(self.skeleton, arm.effector_link)
        self._q: np.ndarray | None = None
        self._other_lists: dict[tuple[tuple[str, ...], str | None, bool], list[str]] = {}
        self.group = scene.detector.createCollisionGroup()
        self.link_of: dict[str, str] = {}  # shape node name -> link name (what contacts call it)
        skip = set(skip_links)
        for shape_node, link in shape_nodes:
            if link not in skip:
                self.group.addShapeFrame(shape_node)
                self.link_of[shape_node.getName()] = link
        self.links = tuple(dict.fromkeys(self.link_of.values()))
        """The links whose geometry is checked, root first."""
        self.finger_links = _finger_links(self.skeleton, arm)
        """The gripper's fingers: links moved by joints with degrees of freedom that are not the arm's (the
        Panda's `panda_leftfinger`, `panda_rightfinger`). A grasp's check skips them on the body they close on."""
        # the fingertip pad (`vkgl.robot.pad`, welded to the effector link: `_collision_links`), in a group of
        # its own: the pad is what pushes, it may touch the body the hand acts on, and it is not checked while
        # the hand holds a tool (the executed arm's pad is then switched off too)
        self.pad_group = scene.detector.createCollisionGroup()
        self.pad_group.addShapeFrame(pad)
        self.link_of[pad.getName()] = PAD
        self._spheres = _link_spheres(self.skeleton, [(n, link) for n, link in shape_nodes if link not in skip], pad)
        self._pad_probe = _probe(self.skeleton, PAD)
        # links and pad in one group: one FCL call where both are checked against the same bodies (the bare
        # arm's transits, the common validity check)
        self._links_and_pad = scene.detector.createCollisionGroup()
        for shape_node, link in shape_nodes:
            if link not in skip:
                self._links_and_pad.addShapeFrame(shape_node)
        self._links_and_pad.addShapeFrame(pad)

    def set_configuration(self, q: Sequence[float] | np.ndarray, opening: float = 0.0) -> None:
        """Put the arm's joints (order of `Arm.joint_names`) at `q`, and every finger `opening` m open (the
        skeleton is shared with the arm's other checkers: every query sets its fingers)."""
        self._q = np.array(q, dtype=float)
        self._opening = opening
        if self._all_dofs:
            self.skeleton.setPositions(self._q)
        else:
            self.skeleton.setPositions(self._dofs, self._q)
            if self._finger_dofs:
                self.skeleton.setPositions(self._finger_dofs, np.full(len(self._finger_dofs), opening))

    def effector_pose(self) -> np.ndarray:
        """The world pose of the effector frame at the current configuration (equals `Arm.fk(q)`)."""
        if self._q is not None:  # the skeleton is shared with the arm's other checkers: be at our configuration
            self.set_configuration(self._q, self._opening)
        return self._link.getTransform().matrix() @ self.arm.link_offset

    def overlap(
        self,
        q: Sequence[float] | np.ndarray,
        poses: Mapping[str, np.ndarray] | None = None,
        ignore: Iterable[str] = (),
        held: Held | None = None,
        table: bool = True,
        pad_may_touch: Iterable[str] = (),
    ) -> list[Contact]:
        """The overlaps of the arm at `q` (and of a held tool) with the bodies and the table.

        `poses`: world poses of bodies to place first (bodies not given stay where
        they were last placed: place them once, then query many configurations);
        `ignore`: bodies the links may touch (e.g. the block the fingertip pushes);
        `held`: a tool in the hand, placed by forward kinematics and checked against
        every body and the table but the ones it acts on; the links do not check it.
        `pad_may_touch`: bodies the fingertip pad may touch (the body a straight
        approach or retreat pushes); the pad is not checked while a tool is held.
        Contacts name the arm's links by their URDF names.
        """
        if poses is not None:
            self.scene.place(poses)
        self.set_configuration(q, _opening(held))
        others = self._others(ignore, held, table)
        out = self.scene.collide(self.group, self.scene.group(others), self.link_of) if others else []
        pad_others = self._pad_others(others, held, pad_may_touch)
        if pad_others:
            out.extend(self.scene.collide(self.pad_group, self.scene.group(pad_others), self.link_of))
        if held is not None:
            tool_pose = self.effector_pose() @ held.in_hand
            targets = [n for n in others if n not in held.acts_on]
            out.extend(self.scene.against(held.body, tool_pose, targets))
        return out

    def free(
        self,
        q: Sequence[float] | np.ndarray,
        poses: Mapping[str, np.ndarray] | None = None,
        ignore: Iterable[str] = (),
        held: Held | None = None,
        table: bool = True,
        pad_may_touch: Iterable[str] = (),
    ) -> bool:
        """Whether nothing overlaps at `q` (see `overlap`): the state-validity check of transit planning.

        Faster than `overlap` where something does: it stops at the first deep contact.
        """
        if poses is not None:
            self.scene.place(poses)
        self.set_configuration(q, _opening(held))
        others = self._others(ignore, held, table)
        if held is None and not pad_may_touch:
            return not (others and self.scene.collides(self._links_and_pad, self.scene.group(others)))
        if others and self.scene.collides(self.group, self.scene.group(others)):
            return False
        pad_others = self._pad_others(others, held, pad_may_touch)
        if pad_others and self.scene.collides(self.pad_group, self.scene.group(pad_others)):
            return False
        if held is not None:
            # the joints were just set: read the link's pose directly (no re-set, see effector_pose)
            self.scene.place({held.body: self._link.getTransform().matrix() @ self.arm.link_offset @ held.in_hand})
            targets = [n for n in others if n not in held.acts_on]
            return not (targets and self.scene.collides(self.scene.group([held.body]), self.scene.group(targets)))
        return True

    def clearance(self, held: Held | None = None, table: bool = True) -> Clearance:
        """A lower bound on how far the arm (its links and pad, or its links and a held tool) is from what
        `free` checks it against at a configuration, with the bodies as they are placed now
        (`vkgl.motion.clearance`): for conservative advancement along transits."""
        others = self._others((), held, table)
        link_boxes = scene_boxes(self.scene, others)
        # the pad is not checked while a tool is held (`free`): its spheres are left out then
        spheres = self._spheres if held is None else [s for s in self._spheres if s[0] is not self._pad_probe]
        probes = [probe for probe, _, _ in spheres]
        which = np.concatenate([np.full(local.shape[1], i) for i, (_, local, _) in enumerate(spheres)])
        local = np.hstack([local for _, local, _ in spheres]).T  # (S, 4) homogeneous, each in its link's frame
        radii = np.concatenate([r for _, _, r in spheres])

        opening = _opening(held)

        def links(q: np.ndarray) -> float:
            self.set_configuration(q, opening)
            frames = np.array([probe.getTransform().matrix() for probe in probes])[which, :3, :]
            return spheres_to_boxes(np.einsum("sij,sj->si", frames, local), radii, link_boxes)

        if held is None:
            return lambda q: links(q) - SAFETY
        tool_boxes = scene_boxes(self.scene, [n for n in others if n not in held.acts_on])
        tool_centres, tool_radii = _cover_boxes(self.scene.part_boxes_local(held.body))
        in_hand = self.arm.link_offset @ held.in_hand

        def with_tool(q: np.ndarray) -> float:
            room = links(q)  # sets the joints
            tool = (self._link.getTransform().matrix() @ in_hand @ tool_centres)[:3].T
            return min(room, spheres_to_boxes(tool, tool_radii, tool_boxes)) - SAFETY

        return with_tool

    @staticmethod
    def _pad_others(others: list[str], held: Held | None, pad_may_touch: Iterable[str]) -> list[str]:
        """What the fingertip pad is checked against: nothing while a tool is held (the executed arm's pad is
        switched off then), else `others` but the bodies it may touch."""
        if held is not None:
            return []
        skip = set(pad_may_touch)
        return [n for n in others if n not in skip]

    def _others(self, ignore: Iterable[str], held: Held | None, table: bool) -> list[str]:
        """The scene's bodies (and table) the links are checked against (remembered: transit planning asks
        the same question thousands of times; do not change the list)."""
        ignored = tuple(ignore)
        key = (ignored, None if held is None else held.body, table)
        found = self._other_lists.get(key)
        if found is None:
            skip = set(ignored)
            if held is not None:
                skip.add(held.body)
            found = [n for n in self.scene.names if n not in skip and (table or n != TABLE)]
            self._other_lists[key] = found
        return found


def _opening(held: Held | None) -> float:
    """m each finger stands open at a query: around a held tool as `held` says, closed without one."""
    return 0.0 if held is None else held.opening


_LINKS: dict[tuple[str, bytes, str, bytes], tuple[Any, list[tuple[Any, str]], Any]] = {}
"""Per URDF, base pose and effector: a skeleton for collision queries, its collision shape nodes with their
links, and the fingertip pad's shape node.

One clone per arm and process instead of one per planning problem. The `ArmCollision`s of an arm share it,
which is sound because each of them sets the joints before every use of the links' poses (`overlap`, `free`,
`effector_pose`)."""


_PROBES: dict[tuple[int, str], Any] = {}


def _probe(skeleton: Any, link: str) -> Any:
    """A frame on `link` of a shared skeleton (`vkgl.robot.kinematics.link_probe`), one per skeleton and link."""
    key = (id(skeleton), link)
    if key not in _PROBES:
        _PROBES[key] = link_probe(skeleton.getBodyNode(link))
    return _PROBES[key]


def _collision_links(arm: Arm) -> tuple[Any, list[tuple[Any, str]], Any]:
    """The shared skeleton of `arm` (root at its base), its shape nodes with collision geometry (root first)
    and the shape node of the fingertip pad welded to its effector link."""
    key = (arm.urdf, np.asarray(arm.base, dtype=float).tobytes(), arm.effector_link, arm.link_offset.tobytes())
    found = _LINKS.get(key)
    if found is None:
        skeleton = load_skeleton(arm.urdf)
        iso = dart.math.Isometry3()
        iso.set_matrix(np.asarray(arm.base, dtype=float))
        skeleton.getRootJoint().setTransformFromParentBodyNode(iso)
        shape_nodes = []
        for i in range(skeleton.getNumBodyNodes()):
            node = skeleton.getBodyNode(i)
            for j in range(node.getNumShapeNodes()):
                shape_node = node.getShapeNode(j)
                if shape_node.hasCollisionAspect():
                    shape_nodes.append((shape_node, node.getName()))
        found = _LINKS[key] = (skeleton, shape_nodes, _pad(skeleton.getBodyNode(arm.effector_link), arm))
    return found


def _cover_boxes(boxes: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Spheres (centres 4 x k homogeneous in the boxes' frame, radii k) that contain the boxes (pose, half)."""
    centres, radii = [], []
    for pose, half in boxes:
        local, radius = cover_box(2 * np.asarray(half, dtype=float))
        centres.append(pose @ np.vstack([local.T, np.ones(len(radius))]))
        radii.append(radius)
    return np.hstack(centres), np.concatenate(radii)


def _link_spheres(
    skeleton: Any, shape_nodes: list[tuple[Any, str]], pad: Any
) -> list[tuple[Any, np.ndarray, np.ndarray]]:
    """Per moving link: its probe, the centres (4 x k, homogeneous, link frame) and radii of spheres that contain
    its collision shapes (`vkgl.motion.clearance`). The root link never moves: it is left out (it stands on the
    table, where a bound would always be zero)."""
    root = skeleton.getBodyNode(0).getName()
    per_link: dict[str, tuple[list[np.ndarray], list[np.ndarray]]] = {}
    for node, link in [*shape_nodes, (pad, PAD)]:
        if link == root:
            continue
        covered = cover_shape(node.getShape())
        if covered is None:
            raise ValueError(f"no sphere cover for the {node.getShape().getType()} of link {link}")
        centres, radii = covered
        placed = np.asarray(node.getRelativeTransform().matrix()) @ np.vstack([centres.T, np.ones(len(radii))])
        found = per_link.setdefault(link, ([], []))
        found[0].append(placed)
        found[1].append(radii)
    return [
        (_probe(skeleton, link), np.hstack(centres), np.concatenate(radii))
        for link, (centres, radii) in per_link.items()
    ]


def _pad(link: Any, arm: Arm) -> Any:
    """The fingertip pad (`vkgl.robot.pad`) welded to the effector `link`: its collision shape node."""
    joint, body = link.createWeldJointAndBodyNodePair()
    iso = dart.math.Isometry3()
    iso.set_matrix(np.asarray(arm.link_offset, dtype=float) @ pad_pose())
    joint.setTransformFromParentBodyNode(iso)
    body.setName(PAD)
    # FCL has no capsules: the cylinder that holds the capsule (its caps included) stands in for it
    node = body.createShapeNode(dart.dynamics.CylinderShape(FINGERTIP_RADIUS, FINGER_PAD_WIDTH + 2 * FINGERTIP_RADIUS))
    node.createCollisionAspect()
    return node


def _finger_dofs(skeleton: Any, arm: Arm) -> list[int]:
    """The skeleton's indices of the fingers' degrees of freedom (those of `_finger_links`' joints)."""
    names = set(arm.joint_names)
    out: list[int] = []
    for i in range(skeleton.getNumJoints()):
        joint = skeleton.getJoint(i)
        if joint.getNumDofs() > 0 and joint.getName() not in names and joint is not skeleton.getRootJoint():
            out.extend(int(joint.getIndexInSkeleton(d)) for d in range(joint.getNumDofs()))
    return out


def _finger_links(skeleton: Any, arm: Arm) -> tuple[str, ...]:
    """The child links of the skeleton's joints that move but are not the arm's (the gripper's fingers)."""
    names = set(arm.joint_names)
    out = []
    for i in range(skeleton.getNumJoints()):
        joint = skeleton.getJoint(i)
        if joint.getNumDofs() > 0 and joint.getName() not in names and joint is not skeleton.getRootJoint():
            out.append(joint.getChildBodyNode().getName())
    return tuple(out)
