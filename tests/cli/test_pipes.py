"""A reader that goes away (`vkgc ... | head -1`): `vkgc` goes quiet, still writes its files, exits 141.

Each case gives the child a pipe whose read end is already closed, so the first
write meets a closed pipe every time (a real `head -1` races with the writer).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from conftest import REPO

from vkgl.cli.exit_codes import EXIT_INPUT, EXIT_PIPE_CLOSED
from vkgl.cli.pipes import _PipeEnd

_UNFORMATTED = "body   Box {  shape box(0.1,0.1,0.1) m\n mass 1 kg }\n"


def _run_with_reader_gone(code: str, *, stderr_too: bool = False) -> subprocess.CompletedProcess[str]:
    """Run `code` in a fresh Python whose stdout (and stderr with `stderr_too`) is a pipe nobody reads."""
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        return subprocess.run(
            [sys.executable, "-c", code],
            stdout=write_end,
            stderr=write_end if stderr_too else subprocess.PIPE,
            text=True,
            cwd=REPO,
            env={**os.environ, "PYTHONPATH": str(REPO)},
            timeout=120,
        )
    finally:
        os.close(write_end)


def _vkgc(*args: str) -> str:
    return f"import sys; sys.argv = ['vkgc', *{list(args)!r}]; from vkgl.cli import run; run()"


def test_a_closed_pipe_ends_vkgc_quietly_with_141_and_the_files_written(tmp_path: Path) -> None:
    module = tmp_path / "box.vkg"
    module.write_text(_UNFORMATTED)
    result = _run_with_reader_gone(_vkgc("fmt", str(module)))
    assert result.returncode == EXIT_PIPE_CLOSED
    assert result.stderr == ""  # no "Broken pipe", no traceback
    assert module.read_text() != _UNFORMATTED  # the rewrite happened although its line could not be printed
    module.write_text(_UNFORMATTED)
    assert _run_with_reader_gone(_vkgc("fmt", str(module)), stderr_too=True).returncode == EXIT_PIPE_CLOSED


def test_a_failing_command_keeps_its_exit_code_when_the_pipe_closes(tmp_path: Path) -> None:
    result = _run_with_reader_gone(_vkgc("check", str(tmp_path / "missing.vkg")))
    assert result.returncode == EXIT_INPUT  # says more than 141: the input was wrong
    assert result.stderr == ""


def test_an_output_named_dev_stdout_meets_the_closed_pipe_quietly() -> None:
    """`--json /dev/stdout | head -1`: the bytes go through `sys.stdout`'s buffer, after what was printed."""
    code = (
        "import sys\n"
        "from vkgl.cli import pipes\n"
        "from vkgl.atomic import write_text\n"
        "pipes.install()\n"
        "print('summary line')\n"
        "write_text('/dev/stdout', '{}\\n' * 20000)\n"
        "print('after', file=sys.stderr)\n"
        "sys.exit(141 if pipes.closed_by_reader() else 0)\n"
    )
    result = _run_with_reader_gone(code)
    assert (result.returncode, result.stderr) == (EXIT_PIPE_CLOSED, "after\n")


def test_the_pipe_end_puts_dev_null_in_place_of_a_closed_pipe() -> None:
    read_end, write_end = os.pipe()
    os.close(read_end)
    end = _PipeEnd(write_end)
    try:
        assert end.write(b"lost") == 4 and end.reader_gone
        assert os.write(write_end, b"more") == 4  # the descriptor is /dev/null now: no BrokenPipeError
        assert os.path.realpath(f"/proc/self/fd/{write_end}") == os.devnull
    finally:
        os.close(write_end)


def test_closing_the_pipe_end_leaves_the_process_descriptor_open() -> None:
    """`vkgc lsp`: pygls closes the stream it wrote to; Python must not then flush a closed file at exit (120)."""
    read_end, write_end = os.pipe()
    end = _PipeEnd(write_end)
    try:
        end.close()
        assert end.closed
        assert os.write(write_end, b"still open") == 10
    finally:
        os.close(read_end)
        os.close(write_end)
