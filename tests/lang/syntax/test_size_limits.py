"""Memory is bounded per byte of source and per mesh face (issue 25): E510 past MAX_TOKENS, E511 past the mesh limits.

A 9 MB one-line file took 80 s and 7 GB, 100,000 bodies in 4.9 MB 36 s and
1.8 GB, a mesh of 1.3 million faces 22 s and 2.2 GB: each is now refused before
it is parsed or loaded (bench/lang/bench_limits.py measures both sides).
"""

from __future__ import annotations

from pathlib import Path

from vkgl.lang.compiler import check_files
from vkgl.lang.ir.mesh_limits import MAX_MESH_FACES, file_too_large
from vkgl.lang.syntax.parser import MAX_TOKENS, parse_collecting, too_many_tokens

ROW = "x = (1, 2, 3) m\n"  # 10 tokens


def test_a_file_of_exactly_max_tokens_is_read_and_one_more_is_e510() -> None:
    at_limit = "# a comment is not a token\n" + ROW * (MAX_TOKENS // 10)
    assert too_many_tokens(at_limit, "at_limit.vkg") is None
    past = at_limit + "y"
    refused = too_many_tokens(past, "past.vkg")
    assert refused is not None and refused.code == "E510"
    assert refused.span is not None and (refused.span.line, refused.span.col) == (MAX_TOKENS // 10 + 2, 1)


def test_a_9_mb_line_is_refused_without_being_parsed() -> None:
    line = "body B { shape box (1, 1, 1) cm mass 1 kg } " * 200_000  # 8.8 MB, 2.8 million tokens
    module, _, diagnostics = parse_collecting(line, "one_line.vkg")
    assert module is None and [d.code for d in diagnostics] == ["E510"]


def binary_stl(path: Path, faces: int) -> Path:
    """A binary STL whose header says `faces` triangles, sparse (its triangles all zero, never read)."""
    with open(path, "wb") as stream:
        stream.write(b"made by a test".ljust(80, b" ") + faces.to_bytes(4, "little"))
        stream.truncate(84 + 50 * faces)
    return path


def test_a_binary_stl_past_the_face_limit_is_e511_before_it_is_read(tmp_path: Path) -> None:
    assert file_too_large(str(binary_stl(tmp_path / "ok.stl", MAX_MESH_FACES))) is None
    huge = binary_stl(tmp_path / "huge.stl", MAX_MESH_FACES + 1)
    assert "500,001 triangles" in (file_too_large(str(huge)) or "")
    body = tmp_path / "statue.vkg"
    body.write_text('body Statue {\n    shape mesh "huge.stl"\n    mass 20 kg\n}\n', encoding="utf-8")
    diagnostics, _ = check_files([str(body)])
    assert [d.code for d in diagnostics] == ["E511"]
