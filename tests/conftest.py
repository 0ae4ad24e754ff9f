"""Shared fixtures: paths of the repository's examples and stdlib."""

from __future__ import annotations

import io
import os
import pickle
import shutil
import tempfile
from collections.abc import Callable
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path
from typing import Any

import pytest
from hypothesis import settings

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None  # type: ignore[assignment]

_MEMORY = Path("/dev/shm")

# Property tests draw the same examples on every run: a run on a fresh clone must not go red on a draw nobody made
# before (test_checks_regions found, unseeded, a footprint that fits to within HiGHS's own tolerance). To look for
# new cases, run with VKGL_HYPOTHESIS=explore (docs/internals.md).
settings.register_profile("fixed", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile("explore" if os.environ.get("VKGL_HYPOTHESIS") == "explore" else "fixed")


def _cache_folder() -> str:
    """A new folder for this run's caches: in memory where there is a tmpfs (Linux), else in the temp folder.

    Every parse of a module file read from disk is kept there through vkgl's atomic writer, which fsyncs:
    the 5000 mutants of tests/lang/test_robustness.py alone made 5000 fsyncs, 5 to 50 s of waiting for the
    disk. On a tmpfs the same code runs (write, fsync, rename) without the wait."""
    memory = _MEMORY.is_dir() and os.access(_MEMORY, os.W_OK | os.X_OK)
    return tempfile.mkdtemp(prefix="vkgl-test-cache-", dir=str(_MEMORY) if memory else None)


# the reach, parses and tables kept between processes (vkgl.resources.cache_folder): in a folder of this test
# run, never the user's; pytest-xdist's workers and the subprocesses the tests start inherit it
_OWN_CACHE = "VKGL_CACHE_DIR" not in os.environ
if _OWN_CACHE:
    os.environ["VKGL_CACHE_DIR"] = _cache_folder()

REPO = Path(__file__).resolve().parent.parent
EXAMPLES = REPO / "examples"
STDLIB = REPO / "stdlib"

SLOWEST_FIRST = [  # CPU-seconds of each file's tests, fixtures and subprocesses (2026-11-28, 2 workers, load 5 to 9)
    "tests/infer/test_learn.py",  # 73: learns the whole stdlib, making `stdlib_explored`'s explorations (45 of it)
    "tests/execute/test_closed_loop.py",  # 45 (62 while its closed-loop tests pushed 15 cm, not 5)
    "tests/test_tooling.py",  # 39: mypy of a fresh clone (Ray not followed); 2 once the checkout has .mypy_cache
    "tests/scenarios/tools/test_generated_execution.py",  # 39
    "tests/plan/geometry/test_geometry_check.py",  # 35: 7 of it the search proving block2 in the way is no plan
    "tests/scenarios/tools/test_wide_pulls.py",  # 34
    "tests/lang/test_robustness.py",  # 29
    "tests/scenarios/goals/test_tall_bodies.py",  # 24 (41 while every height was carried out in DART)
    "tests/sim/test_interrupt.py",  # 19
    "tests/scenarios/goals/test_goal_forms_in_dart.py",  # 15
    "tests/execute/test_resolving.py",  # 14
    "tests/lang/syntax/test_printer.py",  # 13
    "tests/cli/test_startup_imports.py",  # 13: 11 fresh Python processes (15 until 2026-11-28)
    "tests/scenarios/tools/test_contact_chain.py",  # 13
    "tests/test_docs_api.py",  # 12; 25 to 30 while its moved-start example waited out a 30 s timeout
    "tests/bench/test_generated_plans.py",  # 12
    "tests/scenarios/goals/test_drawer_and_door.py",  # 11 (9: the drawer and door converge either way)
    "tests/scenarios/tools/test_stick_clears_blocker.py",  # 11
    "tests/scenarios/goals/test_open_slides.py",  # 10
    "tests/plan/search/bounds/test_bound.py",  # 10
    "tests/execute/test_disturbed.py",  # 10 (12 while block2 was shoved 9 cm: 0.9 CPU-s a cm)
    "tests/scenarios/tools/test_long_stick.py",  # 9
    "tests/scenarios/goals/test_handle_grasps_in_dart.py",  # 9
    "tests/cli/test_hash_seed.py",  # 9
    "tests/sim/test_ray_runner.py",  # 9 in this process, and Ray's own processes (not its children): 20 to 100 s wall
    "tests/plan/result/test_picture.py",  # 9
    "tests/plan/arm/test_contact_chains.py",  # 9
    "tests/formats/test_plan_format.py",  # 9
    "tests/lang/checks/test_checks_rays.py",  # 8
    "tests/cli/test_execute_cli.py",  # 8 (10 while its missed execution pushed 15 cm)
    "tests/test_docs_samples.py",  # 8 when it makes a_push_executed (the first of two files to ask); else 2
    "tests/sim/test_furniture.py",  # 7 (18 while it asked DART for two names per contact and step)
    "tests/scenarios/tools/test_side_approach.py",  # 7
    "tests/scenarios/tools/test_hook_drawer.py",  # 7
    "tests/scenarios/goals/test_arc_push.py",  # 7
    "tests/sim/test_explore.py",  # 6 once `stdlib_explored` has the Block and the Stick (test_learn.py makes them)
    "tests/plan/task_space/test_slides.py",  # 6
    "tests/execute/grip/test_grip.py",  # 6
    "tests/plan/test_examples.py",  # 5
    "tests/lang/checks/test_checks_solids.py",  # 4
    "tests/infer/test_ending.py",  # 1; 13 when it explores the Drawer before test_learn.py does
    "tests/execute/test_animate.py",  # 3; carrying out a_push_recorded: 10 before the solver's tolerance, ~half now
    "tests/cli/test_execution_progress.py",  # 0; making a_push_executed: 5 before the solver's tolerance, ~half now
]
"""The test files that take longest, slowest first: every file of 5 CPU-seconds or more on a loaded machine (the
others take 0 to 4).

They run first, in this order, and the many quick files after them, as collected: xdist hands each worker a
whole file at a time (`--dist loadfile`, `--no-loadscope-reorder` in pyproject.toml), so a long file started
last would keep one worker busy while the other has nothing left to do. Its own default order (files with more
tests first) put the one-test physics files and mypy at the very end. A new file of 5 CPU-seconds or more goes
into its place here; how to measure: docs/internals.md, "The test run's time"."""


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Run the files of `SLOWEST_FIRST` first, in its order; the rest keep the order they were collected in."""
    rank = {path: k for k, path in enumerate(SLOWEST_FIRST)}
    missing = [path for path in SLOWEST_FIRST if not (REPO / path).is_file()]
    assert not missing, f"SLOWEST_FIRST names files that are not there: {missing}"
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))  # stable: in-file order kept


@pytest.hookimpl(tryfirst=True)
def pytest_configure(config: pytest.Config) -> None:
    """`tmp_path` in memory too, inside the run's cache folder (xdist's workers get a folder in it each): on ext4,
    writing over a file flushes it to disk on close (auto_da_alloc), 0.4 to 3 ms a write, and the fuzz tests write
    each of their thousands of cases over the last one (tests/lang/test_robustness.py alone 5000)."""
    in_memory = os.environ["VKGL_CACHE_DIR"].startswith(str(_MEMORY) + os.sep)
    if _OWN_CACHE and in_memory and config.option.basetemp is None:  # a worker's was set by the controller
        config.option.basetemp = os.path.join(os.environ["VKGL_CACHE_DIR"], "tmp")


def pytest_unconfigure(config: pytest.Config) -> None:
    """The process that made the run's cache folder (not an xdist worker, which inherits it) removes it."""
    if _OWN_CACHE:
        shutil.rmtree(os.environ["VKGL_CACHE_DIR"], ignore_errors=True)


@pytest.fixture
def repo() -> Path:
    """The repository root."""
    return REPO


def vkg_files() -> list[Path]:
    """Every .vkg file of examples/ and stdlib/, sorted."""
    return sorted([*EXAMPLES.rglob("*.vkg"), *STDLIB.rglob("*.vkg")])


def example_tasks() -> list[Path]:
    """The task files of examples/tasks/, sorted."""
    return sorted((EXAMPLES / "tasks").glob("*.vkg"))


@pytest.fixture(scope="session")
def a_push_scripted() -> tuple[Any, Any]:
    """Task (a) compiled, and its hand-derived plan (push the block 15 cm) as a vkg-plan/8 document."""
    from plan_script import EXAMPLE_SCRIPTS, scripted_plan

    from vkgl.lang.compiler import compile_file

    program = compile_file(str(EXAMPLES / "tasks" / "a_push.vkg"))
    return program, scripted_plan(program, "a_push", EXAMPLE_SCRIPTS["a_push"])


@pytest.fixture(scope="session")
def a_push_recorded(a_push_scripted: tuple[Any, Any]) -> Any:
    """That plan carried out once in DART, open loop, with frames recorded: tests/execute/test_closed_loop.py
    and tests/execute/test_animate.py both read it (4 to 6 CPU-s of physics). pytest-xdist gives the two files to
    either worker, so the first worker to need it carries it out and leaves the report in the run's cache folder;
    the other reads it there (the lock makes it wait while the first is still running it)."""
    from vkgl.execute.closed_loop import execute

    program, plan = a_push_scripted
    return _made_once("a_push_recorded", lambda: execute(program, "a_push", plan, record=True))


@pytest.fixture(scope="session")
def a_push_executed() -> tuple[int, str, str]:
    """`vkgc solve examples/tasks/a_push.vkg --execute` from the repository root, its stderr taken for a terminal:
    the exit code, stdout and stderr. The planner's plan of task (a) carried out in DART, open loop (4 to 6 CPU-s
    of physics), once per run (`_made_once`): tests/cli/test_execution_progress.py reads the live bar on stderr,
    tests/test_docs_samples.py the report on stdout (docs/execution.md's sample; stdout is the same on a pipe)."""
    return _made_once("a_push_executed", _execute_a_push_on_a_terminal)


def _execute_a_push_on_a_terminal() -> tuple[int, str, str]:
    from vkgl.cli import commands, main

    out, err = io.StringIO(), io.StringIO()
    with pytest.MonkeyPatch.context() as patch, redirect_stdout(out), redirect_stderr(err):
        patch.setattr(commands, "_is_terminal", lambda stream: True)
        patch.chdir(REPO)
        patch.delenv("VKG_PATH", raising=False)  # the stdlib of this checkout
        code = main(["solve", "examples/tasks/a_push.vkg", "--execute"])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="session")
def stdlib_explored() -> Callable[[str], Any]:
    """`stdlib_explored(stem)`: the body of stdlib/bodies/<stem>.vkg explored as `vkgc learn` explores it (every
    `explore` block, seed 0; on 2 processes, which gives the same bytes as any other number), once per run
    (`explored_stdlib_body`). tests/infer/test_learn.py learns the whole stdlib from these (the Block alone is 27
    CPU-s of physics); `block_pushes`, `stick_trials` and tests/infer/test_ending.py take trials of them."""
    return explored_stdlib_body


_EXPLORED: dict[str, Any] = {}


def explored_stdlib_body(stem: str) -> Any:
    """stdlib/bodies/<stem>.vkg's body explored as `vkgc learn` explores it, the `vkg-trials/1` dataset: made once in
    this pytest-xdist run (`_made_once`) and kept in this process."""
    if stem not in _EXPLORED:
        _EXPLORED[stem] = _made_once(f"explored-{stem}", lambda: _explore_stdlib_body(stem))
    return _EXPLORED[stem]


def stdlib_body_of(stem: str) -> Any:
    """The body of stdlib/bodies/<stem>.vkg, compiled."""
    from vkgl.lang.compiler import compile_file

    (body,) = compile_file(str(STDLIB / "bodies" / f"{stem}.vkg")).bodies.values()
    return body


def _explore_stdlib_body(stem: str) -> Any:
    from vkgl.sim.explore import explore

    return explore(stdlib_body_of(stem), jobs=2)


def trials_of(trials: Any, indices: list[int]) -> Any:
    """The trials `indices` of a dataset, as a dataset of their own (padded to the longest of them, as `explore`
    pads a dataset to its longest trial)."""
    from vkgl.formats.trials import Trials

    longest = max(trials.samples(i) for i in indices)
    timed = {key: getattr(trials, key)[indices, :longest] for key in ("t", "T_ro", "T_ow")}
    return Trials(
        trials.body, **timed, **{key: getattr(trials, key)[indices] for key in ("contact", "force", "ok", "reason")}
    )


@pytest.fixture(scope="session")
def block_pushes() -> Any:
    """The stdlib Block pushed toward +x at the 9 points of its -x face, 2 s each: those trials of its `pushes`
    exploration (`stdlib_explored("block")`, as `vkgc learn` explores it). tests/sim/test_explore.py checks the
    trials, tests/infer/test_ending.py what inference makes of how they ended."""
    from vkgl.sim.policy import plan_trials

    specs = plan_trials(stdlib_body_of("block"))
    minus_x = [s.index for s in specs if s.policy == "pushes" and s.contact[0] < 0]
    assert len(minus_x) == 9 and all(s.duration == 2.0 for s in specs if s.index in minus_x)
    return trials_of(explored_stdlib_body("block"), minus_x)


@pytest.fixture(scope="session")
def stick_trials() -> Any:
    """The stdlib Stick explored as `vkgl.explore(stick, jobs=2)` does (its whole `wield` grid, 26 trials of 1 s,
    seed 0; `stdlib_explored("stick")`): tests/sim/test_explore.py checks the trials, and tests/test_docs_api.py's
    page, which learns and explores this body with these arguments, is given them."""
    return explored_stdlib_body("stick")


def _made_once(name: str, make: Callable[[], Any]) -> Any:
    """`make()`, called once in this pytest-xdist run whichever worker asks first; the others read its pickled
    result from a folder of this run alone (named by xdist's id of the run: nothing is read from another run)."""
    run = os.environ.get("PYTEST_XDIST_TESTRUNUID")
    if run is None or fcntl is None:  # one process (or no flock, Windows): nothing to share
        return make()
    folder = Path(os.environ["VKGL_CACHE_DIR"]) / f"test-results-{run}"
    folder.mkdir(exist_ok=True)
    path = folder / f"{name}.pickle"
    with open(folder / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if path.is_file():
            return pickle.loads(path.read_bytes())
        result = make()
        path.write_bytes(pickle.dumps(result))
        return result
