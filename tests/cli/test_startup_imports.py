"""`vkgc check`, `fmt` and `lsp` load no back end: neither SciPy, DART, NLopt nor OMPL; `vkgc solve` no SciPy;
`vkgc fmt` not even numpy (nothing it parses or prints computes with arrays).

Their start is most of their time (docs/internals.md, "Start-up time"): importing SciPy's
rotations alone took longer than a whole `vkgc check` may. Each case runs in a fresh process and
prints which of the heavy packages it imported. The first `check` of a robot asks DART whether its
URDF loads and remembers the answer in the cache folder (`vkgl.lang.checks.urdf`); from the second on,
DART is not imported either.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import EXAMPLES, REPO

HEAVY = ("scipy", "dartpy", "nlopt", "ompl")
TASK = EXAMPLES / "tasks" / "b_stick_push.vkg"  # a scene, a robot with a URDF, a stick with frames

_REPORT = "import sys; print('heavy:', *sorted({m.split('.')[0] for m in sys.modules} & set(sys.argv[1].split(','))))"


def _heavy_modules(code: str, cache: Path, packages: tuple[str, ...] = HEAVY) -> set[str]:
    """Which of `packages` (the heavy ones by default) a fresh process running `code` (then the report) imported."""
    env = {**os.environ, "VKGL_CACHE_DIR": str(cache), "PYTHONPATH": str(REPO)}
    script = f"{code}\n{_REPORT}"
    result = subprocess.run(
        [sys.executable, "-c", script, ",".join(packages)],
        capture_output=True,
        text=True,
        cwd=REPO,
        env=env,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    report = [line for line in result.stdout.splitlines() if line.startswith("heavy:")]
    assert len(report) == 1, result.stdout
    return set(report[0].split()[1:])


CHECK = f"from vkgl.cli import main; assert main(['check', {str(TASK)!r}]) == 0"
FMT = f"from vkgl.cli import main; assert main(['fmt', '--check', {str(TASK)!r}]) == 0"
LSP = (
    "import vkgl.editor.server; from vkgl.editor.analysis import analyze; "
    f"assert not [d for d in analyze({str(TASK)!r}).diagnostics if d.is_error]"
)


@pytest.fixture(scope="module")
def first_check(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, set[str]]:
    """The first `vkgc check` of TASK, with an empty cache folder: that folder as it leaves it (DART has seen the
    arm's URDF; made once, copied by the tests that start from it) and the heavy packages it imported."""
    cache = tmp_path_factory.mktemp("checked-once")
    return cache, _heavy_modules(CHECK, cache)


@pytest.fixture
def checked_once(first_check: tuple[Path, set[str]]) -> Path:
    """A cache folder as one `vkgc check` of TASK leaves it (DART has seen the arm's URDF)."""
    return first_check[0]


def _copy_of(cache: Path, tmp_path: Path) -> Path:
    """A copy of `cache` of this test's own: what one test's processes keep there, no other test sees."""
    return Path(shutil.copytree(cache, tmp_path / "cache"))


def test_check_imports_no_back_end_once_the_urdf_is_known(first_check: tuple[Path, set[str]], tmp_path: Path) -> None:
    cache, first = first_check
    assert first <= {"dartpy"}, f"a first `vkgc check` imported {sorted(first)}"  # DART loads the URDF once
    assert _heavy_modules(CHECK, _copy_of(cache, tmp_path)) == set()


@pytest.mark.parametrize("code", [FMT, LSP], ids=["fmt", "lsp"])
def test_fmt_and_the_language_server_import_no_back_end(code: str, checked_once: Path, tmp_path: Path) -> None:
    assert _heavy_modules(code, _copy_of(checked_once, tmp_path)) == set()  # DART has seen the arm's URDF


def test_fmt_imports_no_numpy(tmp_path: Path) -> None:
    """numpy was a fifth of a fresh `vkgc fmt`'s instructions: the IR's regions import it when they compute."""
    assert _heavy_modules(FMT, tmp_path, ("numpy",)) == set()


SOLVE = f"from vkgl.cli import main; assert main(['solve', {str(TASK)!r}]) == 0"


def test_solve_imports_no_scipy_once_its_hulls_are_known(tmp_path: Path) -> None:
    """`vkgc solve` computes its rotations without SciPy (vkgl.rotations) and reads the bodies' hulls back from
    the cache folder (vkgl.plan.problem.hulls): from the second solve of a task on, SciPy is not imported."""
    _heavy_modules(SOLVE, tmp_path)  # the first computes the hulls with Qhull (and the arm's reach)
    assert "scipy" not in _heavy_modules(SOLVE, tmp_path)


def test_check_imports_no_numpy(checked_once: Path, tmp_path: Path) -> None:
    """numpy was a third of a `vkgc check`'s instructions: the scene checks compute in plain Python
    (vkgl.lang.checks.geometry.rigid, solids), and numpy is imported only to compute a relative placement, a
    relative goal or a region's fit."""
    cache = _copy_of(checked_once, tmp_path)  # DART (and numpy with it) loaded the arm's URDF once
    assert _heavy_modules(CHECK, cache, ("numpy",)) == set()


@pytest.mark.parametrize("task", ["g_open_drawer", "p_knob_drawer", "k_region_goal"])
def test_check_of_a_drawer_or_a_region_goal_imports_no_trimesh_nor_scipy(
    task: str, checked_once: Path, tmp_path: Path
) -> None:
    """trimesh (with SciPy) was two thirds of a `vkgc check` of a drawer or a door: the check of contact
    points and contact frames (E415) finds them on plain-Python triangles (vkgl.lang.checks.geometry.rays).
    A region goal's fit (E453) is a 2-variable linear program, solved exactly without SciPy's `linprog`.
    The task's first check (its own modules not yet parsed nor kept), once DART has seen the arm's URDF."""
    check = f"from vkgl.cli import main; assert main(['check', {str(EXAMPLES / 'tasks' / f'{task}.vkg')!r}]) == 0"
    assert _heavy_modules(check, _copy_of(checked_once, tmp_path), ("trimesh", *HEAVY)) == set()
