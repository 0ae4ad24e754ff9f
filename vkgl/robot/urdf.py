"""Loading a robot's URDF with DART, and reading the kinematic chain out of the skeleton."""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import Any

from vkgl.errors import InputError


@cache
def _parsed_skeleton(path: str) -> Any:
    """The URDF at `path` parsed by DART with its root welded to the world (one parse per path)."""
    import dartpy as dart

    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    # The arm stands on the table: its root link is welded, not floating.
    options.mDefaultRootJointType = dart.utils.DartLoaderRootJointType.FIXED
    loader.setOptions(options)
    return loader.parseSkeleton(path)


def load_skeleton(path: str | Path) -> Any:
    """A fresh DART skeleton of the URDF at `path` (a clone of the cached parse).

    Raises InputError when the file is missing or DART cannot read it.
    """
    path = str(Path(path).resolve())
    if not Path(path).is_file():
        raise InputError(f"URDF file not found: {path}")
    skeleton = _parsed_skeleton(path)
    if skeleton is None:
        raise InputError(f"DART cannot load the URDF {path}: check that it is valid URDF")
    return skeleton.clone()


def link_names(skeleton: Any) -> list[str]:
    """The names of the skeleton's links (DART body nodes), in DART's order."""
    return [skeleton.getBodyNode(i).getName() for i in range(skeleton.getNumBodyNodes())]


def chain_joints(link: Any) -> list[Any]:
    """The joints with degrees of freedom from the skeleton's root to `link` (a DART body node), root first."""
    joints = []
    node = link
    while node is not None:
        joint = node.getParentJoint()
        if joint.getNumDofs() > 0:
            joints.append(joint)
        node = node.getParentBodyNode()
    return joints[::-1]


__all__ = ["chain_joints", "link_names", "load_skeleton"]
