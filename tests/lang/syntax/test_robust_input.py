"""The adversarial review's findings, one test each: no exit 4, no hang, a positioned diagnostic instead.

Numbers too large for Python's int parsing, absurd physical values, files that
are not regular (FIFO, device, directory, symlink loop), too large or not
UTF-8, `use` of files that are not modules, line breaks that only Python sees,
control characters in quoted source, fullwidth digits, and command-line file
errors in the diagnostic form.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from vkgl.cli import main
from vkgl.cli.arguments import MAX_DEPTH_LIMIT as CLI_MAX_DEPTH
from vkgl.errors import CompileError
from vkgl.lang.compiler import check_files, compile_source
from vkgl.lang.diagnostics.diagnostic import Diagnostic, escape_controls, render, source_lines
from vkgl.lang.ir import limits
from vkgl.lang.syntax.printer import format_source
from vkgl.lang.syntax.sources import MAX_SOURCE_BYTES

BODY = (
    "body B {{\n    shape {shape}\n    mass {mass}\n    friction {friction}\n"
    "    explore e {{\n        contacts on faces +x steps {steps}\n        force normal {force}\n"
    "        duration {duration}\n    }}\n}}\n"
)
GOOD = {
    "shape": "box (10, 10, 10) cm",
    "mass": "1 kg",
    "friction": "0.5",
    "steps": "3",
    "force": "1 N",
    "duration": "1 s",
}


def body(**changes: str) -> str:
    """A body that checks clean, with some of its values replaced."""
    return BODY.format(**{**GOOD, **changes})


def errors_of(text: str, tmp_path: Path | None = None) -> list[Diagnostic]:
    """The errors of `text` compiled as a module (none when it compiles)."""
    try:
        compile_source(text, "t.vkg", base_dir=tmp_path)
    except CompileError as exc:
        return [d for d in exc.diagnostics if d.is_error]
    return []


def only(text: str, code: str) -> Diagnostic:
    """The one error of `text`, which must be of `code` and have a position."""
    found = errors_of(text)
    assert [d.code for d in found] == [code], [d.headline() for d in found]
    assert found[0].span is not None
    return found[0]


# ---------------------------------------------------------------- huge integers (were exit 4)

BIG = "9" * 4301


@pytest.mark.parametrize("digits", [16, 4299, 4301, 10_000])
def test_huge_steps_is_a_count_out_of_range(digits: int) -> None:
    diag = only(body(steps="9" * digits), "E210")
    assert "`steps` must be from 1 to 100" in diag.message and f"{digits} digits" in diag.message
    assert diag.span is not None and (diag.span.line, diag.span.col) == (6, 36)


def test_huge_max_depth_grid_and_trials_are_counts_out_of_range() -> None:
    task = f"task t {{ scene s goal b at (0, 0) m search {{ max_depth {BIG} }} }}"
    assert any(d.code == "E210" and "`max_depth` must be from 1 to 12" in d.message for d in errors_of(task))
    grasp = (
        "body G { shape box (1, 1, 1) cm mass 1 kg frame h = (0, 0, 0) m "
        f"explore g {{ grasp h force directions {BIG} x 3 x 3 1 N duration 1 s }} }}"
    )
    assert only(grasp, "E210").message.startswith("a grid size must be from 1 to 15")
    evidence = (
        f"affordances B {{ affordance a {{ action fixed motion free evidence trials {BIG} loglik 1 posterior 1 }} }}"
    )
    assert any(d.code == "E210" and "`trials`" in d.message for d in errors_of(evidence))


def test_long_decimals_and_huge_exponents_neither_raise_nor_hang() -> None:
    assert errors_of(body(mass="1." + "0" * 5000 + " kg")) == []
    assert only(body(mass="1e-99999999999 g"), "E401").span is not None  # underflows to 0
    assert only(body(mass="1e99999999999 g"), "E208").span is not None


# ---------------------------------------------------------------- plausible ranges


@pytest.mark.parametrize(
    ("changes", "code", "allowed"),
    [
        ({"mass": "1e300 kg"}, "E209", "from 1 g to 10000 kg"),
        ({"mass": "1e-320 kg"}, "E209", "from 1 g to 10000 kg"),
        ({"mass": "0.5 g"}, "E209", "from 1 g to 10000 kg"),
        ({"friction": "1e300"}, "E209", "from 0 to 10"),
        ({"force": "1e300 N"}, "E209", "from 0.001 N to 1000 N"),
        ({"duration": "1e308 s"}, "E209", "from 1 ms to 600 s"),
        ({"duration": "0.1 ms"}, "E209", "from 1 ms to 600 s"),
        ({"steps": "99999999999999999999"}, "E210", "from 1 to 100"),
        ({"steps": "101"}, "E210", "from 1 to 100"),
        ({"shape": "box (1, 1, 1e9) cm"}, "E209", "from 1 mm to 10 m"),
        ({"shape": "cylinder radius 0.1 mm height 1 m"}, "E209", "from 1 mm to 10 m"),
        ({"shape": "cylinder radius 1 cm height 11 m"}, "E209", "from 1 mm to 10 m"),
    ],
)
def test_absurd_values_are_errors_with_the_range(changes: dict[str, str], code: str, allowed: str) -> None:
    diag = only(body(**changes), code)
    assert allowed in diag.message


@pytest.mark.parametrize(
    "changes",
    [
        {"mass": "1 g"},
        {"mass": "10000 kg"},
        {"friction": "0"},
        {"friction": "10"},
        {"force": "0.001 N"},
        {"force": "1000 N"},
        {"duration": "1 ms"},
        {"duration": "600 s"},
        {"steps": "1"},
        {"steps": "100"},
        {"shape": "box (1, 1, 1) mm"},
        {"shape": "box (10, 10, 1) m"},
    ],
)
def test_the_ends_of_each_range_are_allowed(changes: dict[str, str]) -> None:
    assert errors_of(body(**changes)) == []


def test_mesh_scale_timeout_and_max_depth_ranges() -> None:
    mesh = body(shape='mesh "m.stl" scale 1e9')
    assert any(d.code == "E209" and "from 0.0001 to 10000" in d.message for d in errors_of(mesh))
    task = "task t { scene s goal b at (0, 0) m search { max_depth 13 timeout 1e308 s } }"
    found = {d.code: d.message for d in errors_of(task) if d.code in ("E209", "E210")}
    assert "from 1 to 12" in found["E210"] and "from 1 ms to 3600 s" in found["E209"]


def test_max_depth_limit_is_the_clis() -> None:
    assert limits.MAX_DEPTH_LIMIT == CLI_MAX_DEPTH == 12


# ---------------------------------------------------------------- one notion of a line

ODD_BREAKS = ["\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"]


@pytest.mark.parametrize("brk", ODD_BREAKS, ids=[f"U+{ord(c):04X}" for c in ODD_BREAKS])
def test_diagnostics_show_the_line_lark_counts(brk: str) -> None:
    text = f"# one{brk}two{brk}three\nbody B {{ mass = 1 kg }}\n"
    diag = only(text, "E101")
    assert diag.span is not None and diag.span.line == 2
    shown = render(diag, text).split("\n")[1]
    assert shown.strip() == "body B { mass = 1 kg }"


@pytest.mark.parametrize("brk", ODD_BREAKS, ids=[f"U+{ord(c):04X}" for c in ODD_BREAKS])
def test_fmt_keeps_comments_in_place_across_odd_breaks(brk: str) -> None:
    text = (
        f"body B {{\n    shape box (1, 1, 1) m\n    # a{brk}b\n    mass 1 kg  # m\n"
        "    # before friction\n    friction 0.5\n}\n"
    )
    out = format_source(text, "x.vkg")
    lines = out.split("\n")
    assert lines[2] == f"    # a{brk}b" and lines[3] == "    mass 1 kg  # m" and lines[4] == "    # before friction"
    assert format_source(out, "x.vkg") == out


def test_source_lines_split_at_newline_only() -> None:
    assert source_lines("a\x0bb\r\nc\u2028d\n") == ["a\x0bb", "c\u2028d", ""]


def test_control_characters_are_escaped_in_the_source_line_and_messages() -> None:
    text = 'use "x\x1b[31m.vkg"\nbody \x1b[2J B { }\n'
    diagnostics, sources = check_files_text(text)
    rendered = "\n".join(render(d, sources.get(d.span.file) if d.span else None) for d in diagnostics)
    assert "\x1b" not in rendered and "\\x1b" in rendered
    assert escape_controls("a\x07b\u202ec\td") == "a\\x07b\\u202ec\\x09d"


def check_files_text(text: str) -> tuple[list[Diagnostic], dict[str, str]]:
    """check_files on `text` written to a temporary module."""
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "t.vkg"
        path.write_text(text, encoding="utf-8")
        return check_files([str(path)])


def test_caret_stays_under_an_escaped_character() -> None:
    text = "body \x1b B { }\n"
    diag = only(text, "E102")
    line, carets = render(diag, text).split("\n")[1:3]
    assert line == "    body \\x1b B { }" and carets == "         ^^^^"


# ---------------------------------------------------------------- fullwidth digits


@pytest.mark.parametrize("digit", ["１", "٣", "߁", "𝟗"])
def test_unicode_digits_are_not_numbers(digit: str) -> None:
    diag = only(body(mass=f"{digit} kg"), "E102")
    assert "ASCII digits" in diag.message


# ---------------------------------------------------------------- files


def _check(path: Path | str) -> list[Diagnostic]:
    diagnostics, _ = check_files([str(path)])
    return diagnostics


@pytest.fixture
def fifo(tmp_path: Path) -> Path:
    path = tmp_path / "pipe.vkg"
    os.mkfifo(path)
    return path


def test_a_fifo_is_not_a_regular_file_and_is_never_opened(fifo: Path) -> None:
    [diag] = _check(fifo)
    assert diag.code == "E506" and "named pipe" in diag.message and diag.span is None and diag.file


def test_dev_zero_is_a_device(tmp_path: Path) -> None:
    [diag] = _check("/dev/zero")
    assert diag.code == "E506" and "character device" in diag.message
    assert diag.headline().startswith("/dev/zero: error[E506]")


def test_a_symlink_loop_on_the_command_line(tmp_path: Path) -> None:
    loop = tmp_path / "loop.vkg"
    loop.symlink_to(loop)
    [diag] = _check(loop)
    assert diag.code == "E506" and "symbolic link loop" in diag.message


def test_a_directory_is_not_a_regular_file(tmp_path: Path) -> None:
    [diag] = _check(tmp_path)
    assert diag.code == "E506" and "directory" in diag.message


def test_a_file_over_the_limit_is_too_large(tmp_path: Path) -> None:
    big = tmp_path / "big.vkg"
    with open(big, "wb") as stream:
        stream.truncate(MAX_SOURCE_BYTES + 1)
    [diag] = _check(big)
    assert diag.code == "E507" and "10 MiB" in diag.message


def test_not_utf8_gives_the_line_and_column_of_the_byte(tmp_path: Path) -> None:
    path = tmp_path / "latin.vkg"
    path.write_bytes(b"body B {\n  # caf\xe9\n}\n")
    [diag] = _check(path)
    assert diag.code == "E508" and "line 2, column 8" in diag.message
    assert diag.span is not None and (diag.span.line, diag.span.col) == (2, 8)
    assert "caf" not in render(diag, None)


@pytest.mark.parametrize("target", ["/etc/shadow", "../../../../etc/passwd", "/proc/self/environ", "notes.txt"])
def test_use_of_a_file_that_is_not_a_module_is_refused_unread(tmp_path: Path, target: str) -> None:
    (tmp_path / "notes.txt").write_text("secret line\n", encoding="utf-8")
    diagnostics, sources = check_files_text_in(tmp_path, f'use "{target}"\n')
    assert [d.code for d in diagnostics] == ["E509"]
    rendered = render(diagnostics[0], sources.get(diagnostics[0].span.file if diagnostics[0].span else ""))
    assert "root:" not in rendered and "secret" not in rendered and len(sources) == 1


def test_use_of_a_vkg_link_to_a_file_that_is_not_a_module(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("secret line\n", encoding="utf-8")
    (tmp_path / "evil.vkg").symlink_to(tmp_path / "notes.txt")
    diagnostics, sources = check_files_text_in(tmp_path, 'use "evil.vkg"\n')
    assert [d.code for d in diagnostics] == ["E509"] and "secret" not in str(sources)


@pytest.mark.parametrize(
    "command",
    [["check"], ["fmt"], ["fmt", "--check"], ["solve"], ["explore", "-o", "{out}"], ["learn", "-o", "{out}"]],
)
def test_a_command_line_link_to_a_file_that_is_not_a_module_is_never_echoed(
    tmp_path: Path, command: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    """`vkgc check pw.vkg`, pw.vkg a link to /etc/passwd, printed the file's first line (E509 covered only `use`)."""
    from vkgl.cli import main

    secret = tmp_path / "elsewhere" / "passwd"
    secret.parent.mkdir()
    secret.write_text("root:x:0:0:SECRET:/root:/bin/bash\n", encoding="utf-8")
    link = tmp_path / "work" / "pw.vkg"
    link.parent.mkdir()
    link.symlink_to(secret)
    (tmp_path / "work" / "inside").symlink_to(secret.parent, target_is_directory=True)
    for name in (link, tmp_path / "work" / "inside" / "passwd"):
        args = [a.replace("{out}", str(tmp_path / "out")) for a in command]
        assert main([args[0], str(name), *args[1:]]) == 1
        captured = capsys.readouterr()
        assert "error[E509]" in captured.out + captured.err
        assert "SECRET" not in captured.out + captured.err
    assert link.is_symlink() and secret.read_text(encoding="utf-8").startswith("root:x")
    assert not (tmp_path / "out").exists()


def test_use_of_a_fifo_module_does_not_hang(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "pipe.vkg")
    diagnostics, _ = check_files_text_in(tmp_path, 'use "pipe.vkg"\n')
    assert [d.code for d in diagnostics] == ["E506"] and diagnostics[0].span is not None


def check_files_text_in(folder: Path, text: str) -> tuple[list[Diagnostic], dict[str, str]]:
    """check_files on `text` written as `folder/main.vkg`."""
    path = folder / "main.vkg"
    path.write_text(text, encoding="utf-8")
    return check_files([str(path)])


def test_a_local_stdlib_that_differs_from_the_installed_one_is_a_warning(tmp_path: Path) -> None:
    (tmp_path / "stdlib" / "bodies").mkdir(parents=True)
    (tmp_path / "stdlib" / "bodies" / "block.vkg").write_text(body(), encoding="utf-8")
    diagnostics, _ = check_files_text_in(tmp_path, "use stdlib.bodies.block\n")
    [warning] = [d for d in diagnostics if d.code == "W603"]
    assert not warning.is_error
    assert "stdlib/bodies/block.vkg" in warning.message and str(tmp_path) in warning.message
    assert len(re.findall(r"stdlib/bodies/block\.vkg", warning.message)) == 2


# ---------------------------------------------------------------- the command line


def test_check_names_a_missing_file_without_a_position(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    missing = tmp_path / "missing.vkg"
    assert main(["check", str(missing)]) == 1
    assert capsys.readouterr().out.startswith(f"{missing}: error[E505]: cannot read")


@pytest.mark.parametrize("command", ["fmt", "solve", "explore", "learn", "infer"])
def test_commands_report_a_fifo_input_as_a_diagnostic(
    command: str, fifo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = {
        "fmt": ["fmt", str(fifo)],
        "solve": ["solve", str(fifo)],
        "explore": ["explore", str(fifo), "-o", str(tmp_path / "t.npz")],
        "learn": ["learn", str(fifo), "-o", str(tmp_path)],
        "infer": ["infer", str(fifo), "-o", str(tmp_path / "a.vkg")],
    }[command]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{fifo}: error[E506]: ") and "vkgc: error" not in err


@pytest.mark.parametrize("command", ["fmt", "solve"])
def test_commands_report_missing_and_not_utf8_inputs_as_diagnostics(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([command, str(tmp_path / "missing.vkg")]) == 1
    assert f"{tmp_path / 'missing.vkg'}: error[E505]: " in capsys.readouterr().err
    latin = tmp_path / "latin.vkg"
    latin.write_bytes(b"# \xe9\n")
    assert main([command, str(latin)]) == 1
    assert f"{latin}:1:3: error[E508]: " in capsys.readouterr().err


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_a_mesh_or_urdf_that_is_a_fifo_or_a_device_is_reported_as_what_it_is(tmp_path: Path, kind: str) -> None:
    """A mesh or URDF path that was a FIFO or /dev/zero was reported as "no such file"."""
    for name in ("part.stl", "arm.urdf"):
        if kind == "fifo":
            os.mkfifo(tmp_path / name)
        else:
            (tmp_path / name).symlink_to("/dev/zero")  # never opened: `stat` says what it is
    (tmp_path / "m.vkg").write_text(
        'body Part {\n    shape mesh "part.stl"\n    mass 1 kg\n}\n'
        'robot Arm {\n    urdf "arm.urdf"\n    effector tip = link hand offset (0, 0, 0) cm\n}\n',
        encoding="utf-8",
    )
    diagnostics = _check(tmp_path / "m.vkg")
    what = "a named pipe (FIFO)" if kind == "fifo" else "a character device"
    assert sorted(d.code for d in diagnostics) == ["E503", "E504"]
    for diag in diagnostics:
        assert f"it is {what}, not a regular file" in diag.message and "no such file" not in diag.message
