"""IR nodes compare and hash by `meaning()`, which is `model_dump()` computed without pydantic's serializer.

`model_dump()` builds a class's schema on first use and looks for pydantic plugins among every installed
package; `vkgc solve` hashes shapes to cache their vertices. Equality must mean what it meant: every field
but the spans, nested nodes by their fields.
"""

from __future__ import annotations

from pathlib import Path

from conftest import EXAMPLES, STDLIB
from pydantic import BaseModel

from vkgl.lang.compiler import check_file
from vkgl.lang.ir.nodes import Pose, Quantity, Span, Vector
from vkgl.lang.ir.values import meaning


def _nodes(value: object) -> list[BaseModel]:
    if isinstance(value, BaseModel):
        found = [value]
        for name in type(value).model_fields:
            found += _nodes(getattr(value, name))
        return found
    if isinstance(value, (list, tuple)):
        return [node for item in value for node in _nodes(item)]
    if isinstance(value, dict):
        return [node for item in value.values() for node in _nodes(item)]
    return []


def test_the_meaning_of_every_node_of_the_examples_is_its_model_dump() -> None:
    files = sorted([*EXAMPLES.rglob("*.vkg"), *STDLIB.rglob("*.vkg")])
    count = 0
    for path in files:
        program, _ = check_file(Path(path))
        assert program is not None, path
        for node in _nodes([program.root, program.bodies, program.scenes, program.tasks, program.robots]):
            dumped = node.model_dump()
            assert meaning(node) == dumped and repr(meaning(node)) == repr(dumped), (path, type(node).__name__)
            count += 1
    assert count > 1000


def test_nodes_that_differ_only_where_they_were_written_are_equal_and_hash_alike() -> None:
    here, there = (
        Span(file="a.vkg", line=1, col=1, end_line=1, end_col=9),
        Span(file="b.vkg", line=7, col=3, end_line=7, end_col=4),
    )
    first = Pose(position=Vector(values=(0.1, 0.2, 0.3), unit="cm", span=here), yaw=Quantity(value=0.5, span=here))
    second = Pose(position=Vector(values=(0.1, 0.2, 0.3), unit="cm", span=there), yaw=Quantity(value=0.5), span=there)
    assert first == second and hash(first) == hash(second)
    third = Pose(position=Vector(values=(0.1, 0.2, 0.3), unit="cm"), yaw=Quantity(value=0.6))
    assert first != third
    assert Quantity(value=1.0) != Vector(values=(1.0,))  # another kind of node is never equal
