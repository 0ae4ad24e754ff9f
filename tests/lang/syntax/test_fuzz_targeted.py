"""Targeted fuzz cases for each category of the adversarial review (at least TARGETED_MINIMUM of them).

Every case goes through `check_files` in-process under the time limit of
tests/lang/fuzzing.py and must give only well-formed, positioned diagnostics
(never an exception, never a hang); each category also checks its own promise.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from fuzzing import check_data, check_path

from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.syntax.sources import MAX_SOURCE_BYTES

TARGETED_MINIMUM = 300

# A module with every numeric position of the language; `{}` is replaced in one place at a time.
POSITIONS = {
    "mass": "body B {{ shape box (1, 1, 1) cm mass {} kg }}",
    "friction": "body B {{ shape box (1, 1, 1) cm mass 1 kg friction {} }}",
    "box": "body B {{ shape box (1, {}, 1) cm mass 1 kg }}",
    "radius": "body B {{ shape cylinder radius {} cm height 1 cm mass 1 kg }}",
    "height": "body B {{ shape cylinder radius 1 cm height {} m mass 1 kg }}",
    "scale": 'body B {{ shape mesh "m.stl" scale {} mass 1 kg }}',
    "steps": (
        "body B {{ shape box (1, 1, 1) cm mass 1 kg explore e {{ contacts on faces +x steps {} "
        "force normal 1 N duration 1 s }} }}"
    ),
    "force": (
        "body B {{ shape box (1, 1, 1) cm mass 1 kg explore e {{ contacts on faces +x steps 3 "
        "force normal {} N duration 1 s }} }}"
    ),
    "duration": (
        "body B {{ shape box (1, 1, 1) cm mass 1 kg explore e {{ contacts on faces +x steps 3 "
        "force normal 1 N duration {} s }} }}"
    ),
    "grid": (
        "body B {{ shape box (1, 1, 1) cm mass 1 kg frame h = (0, 0, 0) m explore g {{ grasp h "
        "force directions 3 x {} x 3 1 N duration 1 s }} }}"
    ),
    "trials": "affordances B {{ affordance a {{ action fixed motion free evidence trials {} loglik 1 posterior 1 }} }}",
    "loglik": "affordances B {{ affordance a {{ action fixed motion free evidence trials 3 loglik {} posterior 1 }} }}",
    "max_depth": "task t {{ scene s goal b at (0, 0) m search {{ max_depth {} }} }}",
    "timeout": "task t {{ scene s goal b at (0, 0) m search {{ timeout {} s }} }}",
    "tolerance": "task t {{ scene s goal b at (0, 0) m within {} cm }}",
    "position": "task t {{ scene s goal b at ({}, 0) m }}",
    "yaw": "task t {{ scene s goal b yaw {} deg }}",
}
NUMBERS = [
    "9" * 16,
    "9" * 4299,
    "9" * 4300,
    "9" * 4301,
    "1" + "0" * 20_000,
    "1e308",
    "1e309",
    "-1e308",
    "1e-320",
    "1e-400",
    "1e99999999999",
    "1e-99999999999",
    "1." + "0" * 5000,
    "0." + "0" * 5000 + "1",
    "9" * 5000 + ".5",
    "１",
    "٣",
    "1_000",
]
COUNT_POSITIONS = {"steps", "grid", "trials", "max_depth"}


@pytest.mark.parametrize("number", NUMBERS, ids=[f"n{i}" for i in range(len(NUMBERS))])
@pytest.mark.parametrize("position", sorted(POSITIONS))
def test_extreme_numbers_in_every_position(tmp_path: Path, position: str, number: str) -> None:
    diagnostics = check_data(tmp_path, POSITIONS[position].format(number))
    if position in COUNT_POSITIONS and number.isdigit() and len(number) > 15:
        assert any(d.code == "E210" for d in diagnostics), [d.headline() for d in diagnostics]


# Characters that some tools take for line breaks, control characters and terminal escapes.
ODD = ["\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029", "\r", "\x00", "\x07", "\x08"]
ODD += ["\x1b", "\x1b[31m", "\x1b]0;title\x07", "\x7f", "\x9b", "\u202e", "\u2066", "\ufeff", "\t"]
PLACES = {
    "comment": "# note{}here\nbody B {{ mass = 1 kg }}\n",
    "string": 'use "x{}y.vkg"\nbody B {{ mass = 1 kg }}\n',
    "between": "body B {{{} mass = 1 kg }}\n",
    "name": "body B{}C {{ mass 1 kg }}\n",
}


@pytest.mark.parametrize("char", ODD, ids=[f"c{i}" for i in range(len(ODD))])
@pytest.mark.parametrize("place", sorted(PLACES))
def test_control_characters_and_odd_line_breaks(tmp_path: Path, place: str, char: str) -> None:
    """The line shown is the line Lark counts, and no control character reaches the terminal."""
    diagnostics = check_data(tmp_path, PLACES[place].format(char))
    assert diagnostics
    if place in ("comment", "string") and char not in ("\r",):
        last = [d for d in diagnostics if d.code == "E101"]
        assert last and last[-1].span is not None and last[-1].span.line == 2, [d.headline() for d in diagnostics]


BAD_BYTES = [b"\xff", b"\xc3", b"\x80", b"\xfe", b"\xed\xa0\x80", b"\xf4\x90\x80\x80", b"\xc0\xaf"]
OFFSETS = [0, 1, 9, 24, -1]


@pytest.mark.parametrize("offset", OFFSETS)
@pytest.mark.parametrize("bad", BAD_BYTES, ids=[b.hex() for b in BAD_BYTES])
def test_bytes_that_are_not_utf8_anywhere(tmp_path: Path, bad: bytes, offset: int) -> None:
    """E508 at the line and column of the first bad byte, the text never shown."""
    good = b"body B {\n  shape box (1, 1, 1) cm\n  mass 1 kg\n}\n"
    at = len(good) if offset < 0 else offset
    data = good[:at] + bad + good[at:]
    [diag] = check_data(tmp_path, data)
    line = data.count(b"\n", 0, at) + 1
    assert diag.code == "E508" and diag.span is not None and diag.span.line == line and f"line {line}" in diag.message


USES = [
    "/etc/shadow",
    "/etc/passwd",
    "../../../../etc/passwd",
    "/proc/self/environ",
    "/proc/self/cmdline",
    "/dev/zero",
    "/dev/stdin",
    "/",
    ".",
    "..",
    "",
    "x.vkg/",
    "/dev/zero.vkg",
    "pipe.vkg",
    "loop.vkg",
    "dir.vkg",
    "big.vkg",
    "dangling.vkg",
    "link_to_passwd.vkg",
    "link_to_dev_zero.vkg",
    "latin.vkg",
    "../" * 40 + "etc/passwd.vkg",
]


@pytest.fixture
def odd_files(tmp_path: Path) -> Path:
    """A folder of files that are not readable modules, as `USES` names them."""
    os.mkfifo(tmp_path / "pipe.vkg")
    (tmp_path / "loop.vkg").symlink_to(tmp_path / "loop.vkg")
    (tmp_path / "dir.vkg").mkdir()
    with open(tmp_path / "big.vkg", "wb") as stream:
        stream.truncate(MAX_SOURCE_BYTES + 1)
    (tmp_path / "dangling.vkg").symlink_to(tmp_path / "nowhere.vkg")
    (tmp_path / "link_to_passwd.vkg").symlink_to("/etc/passwd")
    (tmp_path / "link_to_dev_zero.vkg").symlink_to("/dev/zero")
    (tmp_path / "latin.vkg").write_bytes(b"# caf\xe9\n")
    return tmp_path


@pytest.mark.parametrize("target", USES)
def test_use_of_files_that_are_not_modules(odd_files: Path, target: str) -> None:
    """Never read, never quoted, never a hang: every line shown is from the importing file."""
    diagnostics = check_data(odd_files, f'use "{target}"\n', name="main.vkg")
    assert any(d.is_error for d in diagnostics)
    assert all(d.span is not None and d.span.file.endswith("main.vkg") for d in diagnostics)


COMMAND_LINE = ["pipe.vkg", "loop.vkg", "dir.vkg", "big.vkg", "dangling.vkg", "link_to_dev_zero.vkg", "latin.vkg"]


@pytest.mark.parametrize("name", COMMAND_LINE + ["/dev/zero", "/dev/null", "/proc/self/environ", "missing.vkg"])
def test_command_line_files_that_are_not_modules(odd_files: Path, name: str) -> None:
    diagnostics: list[Diagnostic] = check_path(odd_files / name)
    assert diagnostics and diagnostics[0].is_error


def test_there_are_enough_targeted_cases() -> None:
    count = len(POSITIONS) * len(NUMBERS) + len(PLACES) * len(ODD) + len(BAD_BYTES) * len(OFFSETS)
    count += len(USES) + len(COMMAND_LINE) + 4
    assert count >= TARGETED_MINIMUM, count
