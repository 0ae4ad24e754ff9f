"""The values of the IR: source spans, the frozen base `Node`, quantities, vectors, poses and references.

`vkgl.lang.ir.nodes` re-exports every name here; import them from there.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import BaseModel, ConfigDict, Field

from vkgl.lang.ir.units import measured_repr
from vkgl.rotations import Matrix3, rpy_matrix, yaw_matrix

if TYPE_CHECKING:  # numpy and SciPy are imported where numbers are wanted: `vkgc check` needs no SciPy
    import numpy as np
    from scipy.spatial.transform import Rotation


class Span(BaseModel):
    """A region of a source file. Lines and columns are 1-based; `end_col` is exclusive."""

    model_config = ConfigDict(frozen=True, extra="forbid", defer_build=True)

    file: str
    line: int
    col: int
    end_line: int
    end_col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


class Node(BaseModel):
    """Base of every IR node: frozen, no extra fields, a span that equality ignores."""

    model_config = ConfigDict(frozen=True, extra="forbid", defer_build=True)

    span: Span | None = Field(default=None, exclude=True, repr=False)

    def __eq__(self, other: object) -> bool:
        # Spans are where a node was written, not what it means.
        if not isinstance(other, Node) or type(self) is not type(other):
            return NotImplemented
        return meaning(self) == meaning(other)

    def __hash__(self) -> int:
        return hash(repr(meaning(self)))


def meaning(value: object) -> object:
    """`value.model_dump()` for a model (every field but the excluded spans, nested models as dicts), without
    pydantic's serializer: the first dump of a class builds its schema and its validator, which looks for
    pydantic plugins among every installed package (tens of milliseconds of a `vkgc solve`, which hashes
    shapes to cache their vertices)."""
    if isinstance(value, BaseModel):
        fields = type(value).model_fields
        return {name: meaning(getattr(value, name)) for name, field in fields.items() if not field.exclude}
    if isinstance(value, list):
        return [meaning(item) for item in value]
    if isinstance(value, tuple):
        return tuple(meaning(item) for item in value)
    if isinstance(value, dict):
        return {key: meaning(item) for key, item in value.items()}
    return value


# ---------------------------------------------------------------- values


class Quantity(Node):
    """A scalar with a dimension. `value` is SI; `unit` is how it was written (e.g. "cm")."""

    value: float
    unit: str = ""
    __repr__ = __str__ = measured_repr("value")  # not `Quantity(value=0.01, unit='cm')`: 0.01 is metres


class Vector(Node):
    """2 or 3 components in SI, one unit for all (`unit == ""` for dimensionless)."""

    values: tuple[float, ...]
    unit: str = ""
    __repr__ = __str__ = measured_repr("values")

    def array(self) -> np.ndarray:
        """The components as a float numpy array."""
        import numpy as np

        return np.asarray(self.values, dtype=float)


class Pose(Node):
    """A position, optionally with a yaw or a roll-pitch-yaw orientation.

    At most one of `yaw` and `rpy` is set; neither means identity rotation.
    """

    position: Vector
    yaw: Quantity | None = None
    rpy: Vector | None = None

    def rotation(self) -> Rotation:
        """The orientation as a scipy Rotation (extrinsic xyz = roll, pitch, yaw)."""
        from scipy.spatial.transform import Rotation

        if self.rpy is not None:
            return Rotation.from_euler("xyz", self.rpy.values)
        if self.yaw is not None:
            return Rotation.from_euler("z", self.yaw.value)
        return Rotation.identity()

    def rotation_matrix(self) -> Matrix3:
        """The orientation as a 3x3 matrix (rows): `rotation().as_matrix()` to the last bit, without SciPy."""
        if self.rpy is not None:
            roll, pitch, yaw = self.rpy.values
            return rpy_matrix(roll, pitch, yaw)
        return yaw_matrix(self.yaw.value if self.yaw is not None else 0.0)

    def matrix(self) -> np.ndarray:
        """The pose as a 4x4 homogeneous transform (position padded with z = 0 if 2-d)."""
        import numpy as np

        m = np.eye(4)
        m[:3, :3] = self.rotation_matrix()
        p = list(self.position.values) + [0.0] * (3 - len(self.position.values))
        m[:3, 3] = p
        return m


class Ref(Node):
    """A reference to a declared name (resolved by the checker)."""

    name: str


class FrameRef(Node):
    """`Body.frame` (used in correspondences)."""

    body: str
    frame: str
