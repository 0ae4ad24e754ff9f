"""The code base's own rules, checked by the tools that state them: layers, lint, format, types.

A missing tool is a failure (the test extra installs them), never a skip.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def _run(*command: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)


def test_the_pipeline_layers_hold() -> None:
    result = _run(str(BIN / "lint-imports"), "--no-cache")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-2000:]


def test_ruff_finds_nothing() -> None:
    result = _run(str(BIN / "ruff"), "check", "vkgl", "tests", "bench")
    assert result.returncode == 0, result.stdout[-3000:]


def test_ruff_format_is_clean() -> None:
    result = _run(str(BIN / "ruff"), "format", "--check", "vkgl", "tests", "bench")
    assert result.returncode == 0, result.stdout[-3000:]


def test_mypy_finds_nothing() -> None:
    """mypy as a developer runs it: its cache in the checkout's .mypy_cache (mypy's default), none in a fresh clone
    (36 CPU-s there; a few on the next run, where mypy checks again every module whose source changed)."""
    result = _run(sys.executable, "-m", "mypy", "vkgl")
    assert result.returncode == 0, result.stdout[-3000:]


WRAP = '    """`angle` wrapped into [-pi, pi)."""\n'
INJECTED = "    turns: int = angle / (2 * math.pi)  # a float\n"
"""In place of WRAP, the function's docstring: one line for one, so that no definition after it moves."""


def test_mypy_finds_a_type_error_in_vkgl_with_the_cache_it_made(tmp_path: Path) -> None:
    """The run above must be able to fail: the same command on vkgl with a float put into an `int` in
    `wrap_angle` of vkgl/se3.py, which every stage imports (mypy's `--shadow-file` reads that text for the file;
    the checkout is untouched). It starts from a copy of the cache the run above left in the checkout (a fresh
    clone has none, and this file's tests run in order on one worker), so it also shows that the cache hides no
    error in a module changed since the cache was made. A local variable on a line of its own leaves the module's
    interface as it was: mypy checks that module again, not the ones that import it (under a CPU-second; a new
    function, or any line that moves the definitions below it, changes the interface, and mypy checks every
    importer again: 6 CPU-s)."""
    cache = tmp_path / "mypy_cache"
    if (REPO / ".mypy_cache").is_dir():
        shutil.copytree(REPO / ".mypy_cache", cache)
    module = REPO / "vkgl" / "se3.py"
    text = module.read_text(encoding="utf-8")
    assert text.count(WRAP) == 1, "wrap_angle's docstring moved: inject the error elsewhere"
    line = text[: text.index(WRAP)].count("\n") + 1
    broken = tmp_path / "se3.py"
    broken.write_text(text.replace(WRAP, INJECTED), encoding="utf-8")
    shadow = ("--cache-dir", str(cache), "--shadow-file", str(module), str(broken))
    result = _run(sys.executable, "-m", "mypy", "vkgl", *shadow)
    assert result.returncode == 1, result.stdout[-3000:]
    assert f"vkgl/se3.py:{line}: error: Incompatible types in assignment" in result.stdout, result.stdout[-3000:]
    assert "Found 1 error in 1 file" in result.stdout, result.stdout[-3000:]


def test_no_module_is_over_500_lines() -> None:
    long = {
        str(path.relative_to(REPO)): n
        for path in sorted((REPO / "vkgl").rglob("*.py"))
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > 500
    }
    assert not long, f"split these modules along their jobs: {long}"


def test_no_back_end_compiles_files() -> None:
    """Only the front end and the driver compile `.vkg` files; the stages take typed objects."""
    offenders = [
        str(path.relative_to(REPO))
        for stage in ("sim", "infer", "plan", "execute", "robot", "formats")
        for path in sorted((REPO / "vkgl" / stage).rglob("*.py"))
        if "compile_file" in (text := path.read_text(encoding="utf-8")) or "compile_source" in text
    ]
    assert not offenders, offenders
