"""`vkg-plan/8` (vkgl.formats.plan): round trips, the example plans' JSON against golden files (as numbers,
see tests/support/checkers/plan_close.py), and every bad field named by its JSON path."""

from __future__ import annotations

import copy
import json
import math
import os
import re
import stat
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from checkers.plan_close import assert_plans_close, plan_differences
from conftest import EXAMPLES, REPO, example_tasks
from plan_script import EXAMPLE_SCRIPTS, scripted_plan

from vkgl.errors import InputError, PlanFormatError
from vkgl.formats import plan as plan_format
from vkgl.formats.plan import PlanDocument, dumps, from_json, read, to_json, write
from vkgl.lang.compiler import compile_file

GOLDEN = Path(__file__).resolve().parent / "golden"
"""The `vkgc solve --json` output of each example task (timings zeroed, the stdlib's path as `<repo>/stdlib`)."""


def _normalised(text: str) -> str:
    """Timings zeroed; the stdlib's path shown as the checkout's, wherever the package is installed."""
    from vkgl.resources import stdlib_dir

    text = re.sub(r'"solve_time_s": [0-9.eE+-]+', '"solve_time_s": 0.0', text)
    text = text.replace(f'"{stdlib_dir().resolve()}/', f'"{REPO}/stdlib/')
    return text.replace(json.dumps(str(REPO / "stdlib")), json.dumps("<repo>/stdlib")).replace(
        f'"{REPO}/stdlib/', '"<repo>/stdlib/'
    )


@pytest.fixture(scope="module")
def solved() -> dict[str, Any]:
    """The planner's plan of every example task."""
    from vkgl.plan.solve import solve

    programs = {path.stem: compile_file(str(path)) for path in example_tasks()}
    return {name: solve(program, program.task()) for name, program in programs.items()}


@pytest.fixture(scope="module")
def scripted() -> dict[str, Any]:
    """Task (b)'s hand-scripted plan as JSON data: a grasp and a push with the held stick."""
    program = compile_file(str(EXAMPLES / "tasks" / "b_stick_push.vkg"))
    return to_json(scripted_plan(program, "b_stick_push", EXAMPLE_SCRIPTS["b_stick_push"]))


# ---------------------------------------------------------------- round trips


@pytest.mark.parametrize("name", [p.stem for p in example_tasks()])
def test_the_json_of_each_example_plan_is_unchanged(solved, name):
    """The plan is the golden one as a result: task-space numbers within 1e-7, each arm configuration by the
    effector pose it gives, everything else equal (tests/support/checkers/plan_close.py says why, with the numbers
    measured between two CPUs). Not byte for byte: another CPU's IK lands elsewhere within its tolerance."""
    text = dumps(solved[name].document())
    assert text == json.dumps(solved[name].to_json(), indent=1) + "\n"
    expected = json.loads((GOLDEN / f"{name}.json").read_text(encoding="utf-8"))
    assert_plans_close(json.loads(_normalised(text)), expected, what=f"the plan of {name}")


def _perturbed(value: Any, relative: float) -> Any:
    """Every float of a JSON value times (1 + relative), zeros moved to 1e-12: what another CPU might give."""
    if isinstance(value, dict):
        return {k: _perturbed(v, relative) for k, v in value.items()}
    if isinstance(value, list):
        return [_perturbed(v, relative) for v in value]
    if isinstance(value, float):
        return value * (1.0 + relative) if value != 0.0 else 1e-12
    return value


def _golden(name: str) -> dict[str, Any]:
    return json.loads((GOLDEN / f"{name}.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize("name", [p.stem for p in example_tasks()])
def test_every_float_perturbed_by_1e_9_still_matches_the_golden_plan(name):
    golden = _golden(name)
    moved = _perturbed(golden, 1e-9)
    assert json.dumps(moved) != json.dumps(golden)  # the floats moved: not the same text
    assert plan_differences(moved, golden) == []


def _step_changes() -> list[tuple[str, Any]]:
    """Changes of one step a golden test must catch, each with the path its message names."""

    def value(data: dict[str, Any]) -> None:
        data["steps"][1]["value"] *= 1.0 + 1e-5  # 1e-5 relative: 100 times the tolerance

    def affordance(data: dict[str, Any]) -> None:
        data["steps"][1]["affordance"] = "Block.push_center_nx"

    def pose(data: dict[str, Any]) -> None:
        data["steps"][1]["poses_end"]["block"][0][3] += 1e-6  # a micrometre

    def joint(data: dict[str, Any]) -> None:
        data["steps"][1]["q_end"][1] += 1e-2  # the shoulder: the fingertip moves about 7 mm

    def contact(data: dict[str, Any]) -> None:
        data["steps"][1]["contact"][2][0] += 1e-2  # the base joint: about 5 mm at the block

    def waypoints(data: dict[str, Any]) -> None:
        del data["steps"][0]["path"][0]["joints"][-1], data["steps"][0]["path"][0]["times"][-1]

    def count(data: dict[str, Any]) -> None:
        data["stats"]["task_space_checks"] += 1

    def as_float(data: dict[str, Any]) -> None:
        data["depth"] = float(data["depth"])

    return [
        ("steps[1].value", value),
        ("steps[1].affordance", affordance),
        ("steps[1].poses_end.block[0][3]", pose),
        ("steps[1].q_end", joint),
        ("steps[1].contact[2]", contact),
        ("steps[0].path[0]", waypoints),
        ("stats.task_space_checks", count),
        ("depth", as_float),
    ]


@pytest.mark.parametrize(("where", "change"), _step_changes(), ids=[w for w, _ in _step_changes()])
def test_a_changed_step_does_not_match_the_golden_plan(where, change):
    golden = _golden("b_stick_push")
    changed = copy.deepcopy(golden)
    change(changed)
    differences = plan_differences(changed, golden)
    assert differences and all(line.startswith(where) for line in differences), differences


def test_a_joint_change_below_the_ik_tolerance_is_what_another_cpu_gives():
    """1e-3 rad on one joint moves the fingertip by under a millimetre: within what two IK runs may differ
    (FK_POSITION, 2 mm), so it matches; the joint values themselves differ by up to 0.03 rad between CPUs."""
    golden = _golden("b_stick_push")
    changed = copy.deepcopy(golden)
    changed["steps"][1]["q_end"][0] += 1e-3
    assert changed != golden and plan_differences(changed, golden) == []
    changed["steps"][1]["q_end"][0] += 0.02  # the base joint 0.02 rad further: about a centimetre, caught
    assert [line.split(":")[0] for line in plan_differences(changed, golden)] == ["steps[1].q_end"]


@pytest.mark.parametrize("name", [p.stem for p in example_tasks()])
def test_reading_back_a_plan_gives_the_same_json(solved, name):
    data = json.loads(dumps(solved[name].document()))
    doc = from_json(data)
    assert to_json(doc) == data
    assert dumps(doc) == dumps(solved[name].document())
    assert doc.depth == len(doc.graphs) == len(doc.steps) + 1
    assert all(isinstance(s.q_start, np.ndarray) and s.q_start.shape == (len(doc.robot.joints),) for s in doc.steps)


def test_an_unsolved_plan_carries_its_reason(scripted):
    data = {**scripted, "status": "infeasible", "depth": None, "graphs": [], "steps": [], "final": {}}
    data["reason"] = "the goal is off the table"
    doc = from_json(data)
    assert not doc.solved and doc.reason == "the goal is off the table"
    out = to_json(doc)
    assert list(out)[-1] == "reason" and out == data


def test_write_is_atomic_and_read_gives_the_document_back(scripted, tmp_path):
    path = tmp_path / "plan.json"
    path.write_text("old", encoding="utf-8")
    os.chmod(path, 0o640)
    doc = from_json(scripted)
    write(path, doc)
    assert path.read_text(encoding="utf-8") == dumps(doc)
    assert stat.S_IMODE(path.stat().st_mode) == 0o640  # replacing a file keeps its permissions
    assert [p.name for p in tmp_path.iterdir()] == ["plan.json"]  # no temporary file left behind
    assert to_json(read(path)) == scripted


def test_a_write_into_a_missing_folder_leaves_nothing(scripted, tmp_path):
    with pytest.raises(OSError):
        write(tmp_path / "nowhere" / "plan.json", from_json(scripted))
    assert list(tmp_path.iterdir()) == []


def test_read_names_the_file(scripted, tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({**scripted, "task": None}), encoding="utf-8")
    with pytest.raises(PlanFormatError, match=r"^task: expected a non-empty string, found null \(in .*bad\.json\)$"):
        read(path)
    path.write_text("{not json", encoding="utf-8")
    with pytest.raises(InputError, match="not JSON"):
        read(path)
    with pytest.raises(InputError, match="cannot read the plan"):
        read(tmp_path / "missing.json")


def test_a_step_title_says_what_moves_and_how_far(scripted):
    doc = from_json(scripted)
    assert doc.steps[0].title() == "add Stick.wield on stick with arm.fingertip"
    assert doc.steps[1].title() == "add Block.push_center_px on block with stick.tip: slide 25.0 cm"
    data = copy.deepcopy(scripted)
    data["steps"][1].update(motion="revolute", value=math.radians(20))
    assert from_json(data).steps[1].title().endswith(": turn 20.0 deg")
    data["steps"][1].update(value=0.0)  # a tool set down against the body: the contact moves nothing
    assert from_json(data).steps[1].title().endswith(": touch only, moves nothing")


def test_documents_read_from_json_are_read_only(scripted):
    doc = from_json(scripted)
    with pytest.raises(AttributeError):
        doc.task = "other"  # type: ignore[misc]
    with pytest.raises(ValueError):
        doc.steps[0].poses_start["block"][0, 3] = 1.0


# ---------------------------------------------------------------- bad fields


def _nan_pose() -> list[list[float]]:
    pose = np.eye(4).tolist()
    pose[0][3] = float("nan")
    return pose


def _parent(data: dict[str, Any], path: str) -> tuple[Any, Any]:
    """The container of the field at `path` (dots and [k]) and the field's key in it."""
    *parents, last = re.findall(r"[^.\[\]]+", path)
    node: Any = data
    for key in parents:
        node = node[int(key)] if isinstance(node, list) else node[key]
    return node, int(last) if isinstance(node, list) else last


def _set(path: str, value: Any):
    """A mutation that sets the field at `path` to `value`."""

    def mutate(data: dict[str, Any]) -> None:
        node, key = _parent(data, path)
        node[key] = value

    return mutate


def _delete(path: str):
    """A mutation that deletes the field at `path`."""

    def mutate(data: dict[str, Any]) -> None:
        node, key = _parent(data, path)
        del node[key]

    return mutate


BAD_FIELDS = [
    # (mutation, the message: path first)
    (_set("steps[1].affordance", None), "steps[1].affordance: expected a non-empty string, found null"),
    (_set("steps[0].effector", None), "steps[0].effector: expected a non-empty string, found null"),
    (_set("steps[0].effector", "fingertip"), "steps[0].effector: expected `owner.frame`"),
    (_set("robot", None), "robot: expected a JSON object, found null"),
    (_set("robot.effector", None), "robot.effector: expected a non-empty string, found null"),
    (_set("steps[1].poses_start.block", _nan_pose()), "steps[1].poses_start.block: expected a 4x4 matrix of finite"),
    (_set("final.block", _nan_pose()), "final.block: expected a 4x4 matrix of finite numbers"),
    (_set("steps[1].q_end[2]", float("inf")), "steps[1].q_end: expected a list of finite numbers"),
    (_set("steps[1].value", float("nan")), "steps[1].value: expected a finite number, found NaN"),
    (_set("steps[1].value", -0.1), "steps[1].value: expected an amount >= 0"),
    (_set("steps[1].op", "push"), 'steps[1].op: expected one of add, remove, found "push"'),
    (_set("steps[1].motion", "spiral"), "steps[1].motion: expected one of fixed, prismatic, revolute, free"),
    (_set("graphs[1].edges[0][2]", "glued"), "graphs[1].edges[0][2]: expected one of fixed, prismatic"),
    (_set("graphs[0].edges[0]", ["arm", "world"]), "graphs[0].edges[0]: expected [parent, child, type]"),
    (_set("status", "done"), "status: expected one of solved, infeasible, timeout"),
    (_set("format", "vkg-plan/0"), "format: expected 'vkg-plan/8', found 'vkg-plan/0'"),
    (
        _set("format", "vkg-plan/1"),
        "format: found 'vkg-plan/1', expected 'vkg-plan/8': the plan was written by an older",
    ),
    (_set("steps[0].path[0].phase", "fly"), "steps[0].path[0].phase: expected one of lift, retreat, transit, approach"),
    (_set("steps[0].path[0].times[0]", 0.5), "steps[0].path[0].times: expected seconds from 0, increasing"),
    (_set("steps[0].path[0].joints[0]", [0.0]), "steps[0].path[0].joints[0]: expected 7 joint positions"),
    (_delete("steps[0].path[0].joints[1]"), "steps[0].path[0].joints: expected 2 waypoints (one per time), found 1"),
    (_delete("steps[1].path"), "steps[1].path: missing"),
    (_delete("steps[1].contact"), "steps[1].contact: missing"),
    (_set("steps[1].contact", [[0.0] * 7]), "steps[1].contact: expected [] or 2 or more joint configurations"),
    (_set("steps[1].contact", [[0.0] * 7, [0.0] * 6]), "steps[1].contact[1]: expected 7 joint positions"),
    (_set("steps[1].contact", [[9.0] * 7, [9.0] * 7]), "steps[1].contact[0]: expected the step's q_start"),
    (_set("depth", 2), "depth: is 2 but the plan has 3 graphs"),
    (_set("stats.graphs_expanded", 1.5), "stats.graphs_expanded: expected a count"),
    (_set("stats.solve_time_s", "fast"), "stats.solve_time_s: expected a finite number"),
    (_delete("steps[0].q_end"), "steps[0].q_end: missing"),
    (_delete("final"), "final: missing"),
    (_delete("robot.joints"), "robot.joints: missing"),
    (_delete("stats.task_space_checks"), "stats.task_space_checks: missing"),
    (_set("steps[0].colour", "red"), "steps[0].colour: unknown key"),
    (_set("reason", "why not"), "reason: only a plan that is not solved has a reason"),
    (
        _set("steps[1].poses_end.stick", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        "steps[1].poses_end.stick: expected a 4x4",
    ),
    (
        _set("robot.base", [[1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]),
        "robot.base: expected a rotation",
    ),
    (
        _set("robot.effector_offset", np.diag([1.0, 1.0, 1.0, 2.0]).tolist()),
        "robot.effector_offset: expected a homogeneous",
    ),
    (
        _set("steps[0].q_start", [0.0, 0.1]),
        "steps[0].q_start: expected 7 joint positions (one per robot.joints), found 2",
    ),
    (_set("steps", {}), "steps: expected a list, found {}"),
    (_set("steps[1].poses_start", []), "steps[1].poses_start: expected an object of body name -> 4x4 pose"),
]


@pytest.mark.parametrize(("mutate", "message"), BAD_FIELDS, ids=[m for _, m in BAD_FIELDS])
def test_every_bad_field_is_named_by_its_path(scripted, mutate, message):
    data = copy.deepcopy(scripted)
    mutate(data)
    with pytest.raises(PlanFormatError) as caught:
        from_json(data)
    assert str(caught.value).startswith(message), str(caught.value)
    assert caught.value.path == message.split(":")[0]
    assert isinstance(caught.value, InputError)  # the CLI reports it as an input error (exit 1)


def test_an_unsolved_plan_must_say_why(scripted):
    data = {**scripted, "status": "timeout", "depth": None, "graphs": [], "steps": [], "final": {}}
    with pytest.raises(PlanFormatError, match=r"^reason: missing"):
        from_json(data)
    with pytest.raises(PlanFormatError, match=r"^depth: expected null"):
        from_json({**data, "depth": 3, "reason": "out of time"})


def test_not_an_object_at_all():
    with pytest.raises(PlanFormatError, match="expected a JSON object, found \\[\\]"):
        from_json([])


# ---------------------------------------------------------------- layering


@pytest.mark.parametrize(
    ("module", "forbidden"),
    [
        ("vkgl.formats.plan", ("vkgl.plan", "vkgl.execute", "vkgl.lang")),
        ("vkgl.formats.execution_report", ("vkgl.plan", "vkgl.execute", "vkgl.lang")),
        ("vkgl.execute.closed_loop", ("vkgl.plan", "vkgl.infer", "vkgl.lang.compiler")),
    ],
)
def test_formats_sit_below_the_stages_and_the_executor_never_imports_the_planner(module, forbidden):
    code = f"import sys, {module}; print(' '.join(sorted(sys.modules)))"
    loaded = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO, env={**os.environ}
    ).stdout.split()
    bad = [m for m in loaded if any(m == f or m.startswith(f + ".") for f in forbidden)]
    assert bad == [], f"{module} imports {bad}"


def test_the_format_has_one_definition():
    assert plan_format.PLAN_FORMAT == "vkg-plan/8"
    for path in [*(REPO / "vkgl").rglob("*.py"), REPO / "tests" / "support" / "plan_script.py"]:
        if path.name == "document.py" and path.parent.name == "plan" and path.parent.parent.name == "formats":
            continue
        assert '"vkg-plan/8"' not in path.read_text(encoding="utf-8"), path


def test_documents_are_typed(scripted):
    doc = from_json(scripted)
    assert isinstance(doc, PlanDocument)
    assert doc.robot.joints == tuple(scripted["robot"]["joints"])
    assert doc.graphs[0][0] == ("arm", "world", "free")


@pytest.mark.parametrize("version", ["vkg-plan/3", "vkg-plan/4", "vkg-plan/5", "vkg-plan/6", "vkg-plan/7"])
def test_a_vkg_plan_3_to_7_document_is_read_as_the_current_version(scripted, version):
    doc = from_json({**scripted, "format": version})
    assert to_json(doc) == scripted  # the same fields, written back as vkg-plan/8
    with pytest.raises(PlanFormatError, match=r"format: expected 'vkg-plan/8', found 'vkg-plan/9'"):
        from_json({**scripted, "format": "vkg-plan/9"})


def test_a_vkg_plan_2_document_is_still_read_without_contact_chains(scripted):
    older = {**scripted, "format": "vkg-plan/2", "steps": [dict(s) for s in scripted["steps"]]}
    for step in older["steps"]:
        del step["contact"]
    doc = from_json(older)
    assert all(step.contact is None for step in doc.steps)
    assert to_json(doc)["format"] == "vkg-plan/8"  # written back as the current version
    with pytest.raises(PlanFormatError, match=r"steps\[0\]\.contact: unknown key"):
        from_json({**older, "steps": [{**older["steps"][0], "contact": []}, *older["steps"][1:]]})


def _same(a: Any, b: Any, where: str = "") -> list[str]:
    """Where two documents' fields differ: arrays element for element (bit for bit) with their shapes and write
    flags, everything else by equality."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a_, b_ = np.asarray(a), np.asarray(b)
        same = a_.shape == b_.shape and a_.tobytes() == b_.tobytes() and a_.flags.writeable == b_.flags.writeable
        return [] if same else [where]
    if hasattr(a, "__dataclass_fields__"):
        if type(a) is not type(b):
            return [f"{where}: {type(a).__name__} vs {type(b).__name__}"]
        return [
            d for name in a.__dataclass_fields__ for d in _same(getattr(a, name), getattr(b, name), f"{where}.{name}")
        ]
    if isinstance(a, dict):
        if list(a) != list(b):
            return [where]
        return [d for key in a for d in _same(a[key], b[key], f"{where}.{key}")]
    if isinstance(a, (list, tuple)):
        if type(a) is not type(b) or len(a) != len(b):
            return [where]
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in _same(x, y, f"{where}[{k}]")]
    return [] if a == b and type(a) is type(b) else [f"{where}: {a!r} vs {b!r}"]


@pytest.mark.parametrize("name", [p.stem for p in example_tasks()])
def test_a_plans_document_is_what_its_json_reads_back(solved, name):
    """`Plan.document()` holds its document (no JSON in memory): every field as `from_json(to_json(...))` gives,
    so that executing from memory and from the file is the same."""
    plan = solved[name]
    assert not _same(plan.document(), from_json(plan.to_json()))
    assert plan.document() is plan.document()


def test_a_release_whose_path_carries_the_body_says_where_it_is_set_down() -> None:
    """A tool put back where it was picked up (or a carried body placed) is let go of elsewhere than where the hand
    took it over: the step's words say where (its `poses_start`); a release with no carry says nothing more."""
    from vkgl.formats.plan.document import ArmSegment, PlanStepRecord

    place = np.eye(4)
    place[:3, 3] = (0.3, -0.4, 0.01)
    q = np.zeros(7)
    carry = ArmSegment("transit", np.array([0.0, 1.0]), np.zeros((2, 7)))
    step = PlanStepRecord("remove", "Stick.wield", "stick", "arm.fingertip", "free", 0.0, {"stick": place}, {}, q, q)
    assert step.title() == "remove Stick.wield on stick with arm.fingertip"
    carried = PlanStepRecord(
        "remove", "Stick.wield", "stick", "arm.fingertip", "free", 0.0, {"stick": place}, {}, q, q, path=(carry,)
    )
    assert carried.title() == "remove Stick.wield on stick with arm.fingertip: set down at (0.300, -0.400) m"
