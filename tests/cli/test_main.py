"""The `vkgc` command line: exit codes, help, error reporting."""

from __future__ import annotations

import subprocess
import sys

from conftest import vkg_files

from vkgl.cli import main


def test_no_command_prints_help_and_exits_1(capsys) -> None:
    assert main([]) == 1
    assert "usage: vkgc" in capsys.readouterr().out


def test_check_all_examples_and_stdlib_is_clean(capsys) -> None:
    files = [str(p) for p in vkg_files()]
    assert main(["check", *files]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert out == [f"checked {len(files)} files: no errors"]


def test_check_missing_file_is_an_input_error(capsys, tmp_path) -> None:
    assert main(["check", str(tmp_path / "nope.vkg")]) == 1
    out = capsys.readouterr().out
    assert "nope.vkg" in out and "error[" in out


def test_help_imports_no_heavy_back_end() -> None:
    """`vkgc --help` must start fast: DART, NLopt, SciPy, Lark and trimesh load lazily."""
    script = (
        "import sys, runpy\n"
        "sys.argv = ['vkgc', '--help']\n"
        "try:\n"
        "    runpy.run_module('vkgl.cli', run_name='__main__')\n"
        "except SystemExit:\n"
        "    pass\n"
        "heavy = [m for m in ('dartpy', 'nlopt', 'scipy', 'lark', 'trimesh') if m in sys.modules]\n"
        "print('HEAVY', heavy)\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert "usage: vkgc" in result.stdout
    assert "HEAVY []" in result.stdout


def test_an_output_in_a_missing_directory_is_refused_before_any_work(capsys, tmp_path) -> None:
    from conftest import EXAMPLES

    missing = tmp_path / "no" / "plan.json"
    assert main(["solve", str(EXAMPLES / "tasks" / "a_push.vkg"), "--json", str(missing)]) == 1
    captured = capsys.readouterr()
    assert f"--json {missing}: there is no directory" in captured.err
    assert "solved" not in captured.out  # nothing was planned


def test_an_output_that_is_a_directory_is_refused(capsys, tmp_path) -> None:
    assert main(["infer", str(tmp_path / "t.npz"), "-o", str(tmp_path)]) == 1
    assert "is a directory; name a file in it" in capsys.readouterr().err


def test_learn_names_what_a_file_without_bodies_lacks(capsys) -> None:
    from conftest import REPO

    assert main(["learn", str(REPO / "stdlib" / "tools.vkg")]) == 1
    assert "declares no body; give a file with a `body NAME { ... }` declaration" in capsys.readouterr().err
