"""The code base's own rules, checked by the tools that state them: layers, lint, format, types.

A missing tool is a failure (the test extra installs them), never a skip.
"""

from __future__ import annotations

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
    result = _run(sys.executable, "-m", "mypy", "vkgl")
    assert result.returncode == 0, result.stdout[-3000:]


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
