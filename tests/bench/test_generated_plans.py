"""Plans for generated tasks pass the independent geometry check (issue 12: every plan it solves is collision-free).

A seeded selection of the physical benchmark's tasks (`tests/support/task_makers/generated_tasks.py`,
bench/physical/bench_physical.py)
that the planner solves in well under a second each, covering what the examples do not: generated body types
(slabs, cubes, a crate 25 cm tall), 1 to 4 clutter bodies on the table, a motion repeated past its explored range,
a turn before a push, the stick and the hook. Each plan is checked by `tests/support/checkers/plan_geometry.py`,
which builds
its own DART world from the IR and samples every motion 20 times; it shares no code with the planner's collision
checks. Its contact chains are checked by `tests/support/checkers/contact_chain_check.py` (the hand moves rigidly
with the
body).

The generated bodies' affordances are fixtures: `learned/` holds what `vkgl.learn` wrote for each generated type,
in the layout of bench_physical's cache (one folder per hash of the body's source). Learning them again takes a
minute per type; when the generator's bodies change, the test says how to refresh them.
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Any

import pytest
from checkers.contact_chain_check import check_contact_chains
from checkers.plan_geometry import check_plan
from task_makers.generated_tasks import TEST_SOLVE_TIMEOUT_S, fixture_library, task_spec, write_task

import vkgl

SUPPORT = Path(__file__).resolve().parents[1] / "support" / "checkers"

SELECTION = [
    (1, 20),  # the Block pushed once, a cube behind it
    (1, 44),  # SlabN turned, then pushed, 4 clutter bodies
    (1, 49),  # the stick pushes a cube, 4 clutter bodies
    (1, 15),  # the hook pulls a cube, 1 clutter body
    (2, 17),  # SlabW pushed twice (31 cm; its push was explored over 21 cm), the second time with the stick
    (2, 40),  # a crate 25 cm tall pushed, 4 clutter bodies
]
"""(seed, index) of generated tasks: `task_spec(seed, index)` is a pure function of both."""


@pytest.fixture(scope="module")
def library() -> dict[str, Path | None]:
    return fixture_library()


@pytest.mark.parametrize(("seed", "index"), SELECTION)
def test_a_generated_tasks_plan_passes_the_independent_check(
    tmp_path: Path, library: dict[str, Path | None], seed: int, index: int
) -> None:
    spec = task_spec(seed, index)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, library))
    plan = vkgl.solve(program, spec.name, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", f"{spec.name} (selected as one the planner solves): {plan.reason}"
    plan_json: dict[str, Any] = plan.to_json()
    assert check_plan(program, spec.name, plan_json, samples=20) == []
    assert check_contact_chains(program, plan_json) == []  # the hand holds the body rigidly along each contact


def test_the_selection_has_what_the_examples_lack(library: dict[str, Path | None]) -> None:
    specs = [task_spec(seed, index) for seed, index in SELECTION]
    assert {s.target.type for s in specs} >= {"SlabN", "SlabW", "CubeS", "CubeM", "CrateT", "Block"}
    assert max(len(s.clutter) for s in specs) == 4 and min(len(s.clutter) for s in specs) == 1
    assert all(library[t.name] is not None for s in specs for t in s.generated_types() if t.name == s.target.type)


@pytest.mark.parametrize("module", ["plan_geometry.py", "contact_chain_check.py"])
def test_the_independent_check_shares_no_code_with_the_planner(module: str) -> None:
    tree = ast.parse((SUPPORT / module).read_text(encoding="utf-8"))
    imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert not {m for m in imported if m.startswith(("vkgl.plan", "vkgl.execute", "vkgl.sim"))}, imported
