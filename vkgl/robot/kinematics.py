"""The kinematic chain of an arm: DART's forward kinematics and Jacobian from the URDF's root to one effector.

Everything here is in the URDF root's frame; `Arm` applies the base pose in
numpy, so that one parsed URDF serves every base.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from vkgl.errors import InputError
from vkgl.robot.urdf import chain_joints


class Chain:
    """The joints that move one effector link of a DART skeleton, and the effector frame on that link.

    Attributes: `skeleton` (owned by the chain: its positions change on every
    call), `link` (the effector's DART body node), `link_offset` (4x4: the
    effector frame in the link's frame), `joint_names` (root first), `lower`,
    `upper` (their URDF position limits, rad).
    """

    def __init__(self, skeleton: Any, link_name: str, link_offset: np.ndarray, *, robot: str) -> None:
        """The chain of `skeleton` from its root to `link_name`; `robot` names the arm in errors.

        Raises InputError when no joint moves the link or a joint of the chain
        has other than one degree of freedom.
        """
        self.skeleton = skeleton
        self.link = skeleton.getBodyNode(link_name)
        self.link_offset = link_offset
        joints = chain_joints(self.link)
        if not joints:
            raise InputError(f"{robot}: no joint of the URDF moves the effector link {link_name}")
        if any(j.getNumDofs() != 1 for j in joints):
            raise InputError(
                f"{robot}: the joints from the URDF's root to {link_name} must each have one degree of freedom"
            )
        self.joint_names: list[str] = [j.getName() for j in joints]
        self.lower = np.array([j.getPositionLowerLimit(0) for j in joints])
        self.upper = np.array([j.getPositionUpperLimit(0) for j in joints])
        dofs = [int(j.getIndexInSkeleton(0)) for j in joints]
        self._dofs = dofs
        # setting all positions at once is faster than by index, when the chain is the whole skeleton
        self._all_dofs = dofs == list(range(skeleton.getNumDofs()))
        self._jacobian_columns = self._columns_of_chain()
        self._point = self.link_offset[:3, 3].copy()
        self._probe = link_probe(self.link)
        self._wrist_node = joints[-1].getChildBodyNode()

    def _columns_of_chain(self) -> np.ndarray | None:
        """Which columns of the link's DART Jacobian belong to `joint_names`, in their order (None: all, in order)."""
        dependent = [self.link.getDependentGenCoordIndex(i) for i in range(self.link.getNumDependentGenCoords())]
        columns = [dependent.index(d) for d in self._dofs]
        return None if columns == list(range(len(dependent))) else np.array(columns)

    def _set(self, q: np.ndarray) -> None:
        if self._all_dofs:
            self.skeleton.setPositions(q)
        else:
            self.skeleton.setPositions(self._dofs, q)

    def link_pose(self, q: np.ndarray) -> np.ndarray:
        """The effector link's pose (4x4) in the root frame at joint angles `q` (without the effector offset)."""
        self._set(q)
        return self._probe.getTransform().matrix()

    def wrist_in_effector(self, q: np.ndarray) -> np.ndarray:
        """Where the origin of the link the chain's last joint moves (the wrist: for the Panda, panda_link7 on the
        hand's axis, 21 cm above the fingertip) lies in the effector frame at joint angles `q` (3-vector)."""
        self._set(q)
        effector = self._probe.getTransform().matrix() @ self.link_offset
        wrist = self._wrist_node.getTransform().matrix()[:3, 3]
        return np.linalg.inv(effector)[:3, :3] @ (wrist - effector[:3, 3])

    def pose_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The effector frame in the root frame and its 6 x n Jacobian (angular rows first, root frame)."""
        self._set(q)
        pose = self._probe.getTransform().matrix() @ self.link_offset
        jac = self.link.getWorldJacobian(self._point)
        if self._jacobian_columns is not None:
            jac = jac[:, self._jacobian_columns]
        return pose, jac

    def at_last_q(self) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """`pose_and_jacobian`, remembering its last answer: for NLopt problems whose objective and constraints
        are all asked at the same point (one kinematics per point instead of one per function; same numbers)."""
        last: list[Any] = [None, None]

        def kinematics(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            key = q.tobytes()
            if last[0] != key:
                last[0], last[1] = key, self.pose_and_jacobian(q)
            return last[1]  # type: ignore[no-any-return]

        return kinematics

    def reach_bound(self) -> tuple[np.ndarray, float]:
        """A point that no joint moves (on the first joint's axis) and how far from it the effector can ever be.

        The bound is the sum of the lengths of the chain's fixed offsets after
        that point: rotations never lengthen them (triangle inequality). It lets
        IK reject far targets at once.
        """
        q = np.zeros(len(self.joint_names))
        child = self.skeleton.getJoint(self.joint_names[0]).getChildBodyNode()
        anchors = []
        for angle in (0.0, 1.0):
            q[0] = angle
            self._set(q)
            anchors.append(child.getWorldTransform().translation())
        if np.linalg.norm(anchors[0] - anchors[1]) < 1e-9:
            start, anchor = child.getName(), anchors[0]
        else:
            start, anchor = None, np.zeros(3)
        length = float(np.linalg.norm(self._point))
        node = self.link
        while node is not None and node.getName() != start:
            joint = node.getParentJoint()
            length += float(np.linalg.norm(joint.getTransformFromParentBodyNode().translation()))
            length += float(np.linalg.norm(joint.getTransformFromChildBodyNode().translation()))
            node = node.getParentBodyNode()
        return anchor, length


def link_probe(link: Any) -> Any:
    """A frame fixed on `link` at its origin: its world transform is the link's, the same matrix, read in a sixth
    of the time (dartpy's BodyNode getters are slow to call; a SimpleFrame's are not). This is the innermost call
    of IK and of the reach. The link's skeleton may go first: DART then hangs the frame on the world."""
    import dartpy as dart

    return dart.dynamics.SimpleFrame(link, f"{link.getName()}#probe")


__all__ = ["Chain", "link_probe"]
