"""vkgl/editor/protocol.py: position units counted with the codecs give pygls's own numbers."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

from vkgl.editor.protocol import count_units_fast

ENCODINGS = [types.PositionEncodingKind.Utf16, types.PositionEncodingKind.Utf8, types.PositionEncodingKind.Utf32]
TEXT = st.text(alphabet=st.sampled_from(list("ab é€😋\u2028\t")), max_size=30)


@settings(max_examples=200, deadline=None)
@given(line=TEXT, character=st.integers(0, 40), encoding=st.sampled_from(ENCODINGS))
def test_fast_unit_counts_are_pyglss(line: str, character: int, encoding: types.PositionEncodingKind) -> None:
    slow, fast = PositionCodec(encoding=encoding), PositionCodec(encoding=encoding)
    count_units_fast(fast)
    lines = [line + "\n", "x\n"]
    assert fast.client_num_units(line) == slow.client_num_units(line)
    asked = types.Position(line=0, character=character)
    assert fast.position_from_client_units(lines, asked) == slow.position_from_client_units(lines, asked)
    inside = types.Position(line=0, character=min(character, len(line)))
    assert fast.position_to_client_units(lines, inside) == slow.position_to_client_units(lines, inside)
