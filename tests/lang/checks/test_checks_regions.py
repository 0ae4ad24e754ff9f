"""Regions (vkgl/lang/ir/regions.py, vkgl/lang/checks/geometry/regions.py): boxes and convex polygons, region goals.

A point is inside a region exactly when it is inside every half-plane; the
checker resolves a goal's `in NAME` to the scene's region, and reports swapped
corners (E450) and polygons that are not convex (E451).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from vkgl.errors import CompileError
from vkgl.lang.compiler import compile_source
from vkgl.lang.ir.nodes import Vector
from vkgl.lang.ir.regions import Region, excess, overlap_depth, region_problem
from vkgl.lang.syntax.parser import parse_module
from vkgl.lang.syntax.printer import print_module

ROOT = Path(__file__).resolve().parents[3]
SCENE = """\
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene s {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    region tray = polygon (0.55, -0.16), (0.75, -0.16), (0.8, 0.12), (0.55, 0.12) m
}
"""


def _region(kind: str, *corners: tuple[float, float]) -> Region:
    return Region(kind=kind, corners=[Vector(values=c, unit="m") for c in corners])


def _codes(task: str) -> list[str]:
    with pytest.raises(CompileError) as error:
        compile_source(SCENE + task, base_dir=ROOT)
    return [d.code for d in error.value.diagnostics]


def test_a_named_region_is_copied_into_the_goal() -> None:
    program = compile_source(SCENE + "task t {\n    scene s\n    goal block in tray yaw 0deg\n}\n", base_dir=ROOT)
    (goal,) = program.tasks["t"].goals
    assert goal.region is not None and goal.region.name == "tray" and goal.region.kind == "polygon"
    assert goal.yaw is not None and goal.tolerance()[0] == pytest.approx(0.01)


def test_misused_regions_are_errors() -> None:
    assert _codes("task t {\n    scene s\n    goal block in region (0.8, 0.1) to (0.6, 0.2) m\n}\n") == ["E450"]
    assert _codes("task t {\n    scene s\n    goal block in region polygon (0.6, 0), (0.7, 0) m\n}\n") == ["E451"]
    assert _codes("task t {\n    scene s\n    goal block in sink\n}\n") == ["E301"]
    narrow = "region (0.6, -0.05) to (0.8, 0.05) m"  # 20 x 10 cm: the 10 x 20 cm block fits only turned
    assert _codes(f"task t {{\n    scene s\n    goal block in {narrow} yaw 0deg\n}}\n") == ["E453"]
    compile_source(SCENE + f"task t {{\n    scene s\n    goal block in {narrow}\n}}\n", base_dir=ROOT)


def test_regions_print_as_written_with_one_unit() -> None:
    text = SCENE + "task t {\n    scene s\n    goal block in region (55, -16) to (75, 12) cm within 1 cm\n}\n"
    module = parse_module(text, "t.vkg")
    printed = print_module(module)
    assert "region tray = polygon (0.55, -0.16), (0.75, -0.16), (0.8, 0.12), (0.55, 0.12) m" in printed
    assert "goal block in region (55, -16) to (75, 12) cm within 1 cm" in printed
    assert parse_module(printed, "t.vkg") == module


def test_polygons_in_either_sense_are_the_same_region_and_concave_ones_are_not_regions() -> None:
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    forward, backward = _region("polygon", *square), _region("polygon", *square[::-1])
    assert np.allclose(sorted(map(tuple, forward.halfplanes())), sorted(map(tuple, backward.halfplanes())))
    assert np.all(forward.halfplanes()[:, :2] @ (0.5, 0.5) < forward.halfplanes()[:, 2])  # the centre is inside
    assert region_problem(_region("polygon", (0, 0), (1, 0), (0.5, 0.2), (1, 1), (0, 1))) == "concave"
    assert region_problem(_region("box", (1, 0), (0, 1))) == "swapped"
    assert region_problem(_region("box", (0, 0), (1, 0.0005))) == "flat"
    # a corner written twice (in a row, or the last the first again) leaves an edge with no normal
    assert region_problem(_region("polygon", (0, 0), (1, 0), (1, 0), (1, 1), (0, 1))) == "repeated"
    assert region_problem(_region("polygon", (0, 0), (1, 0), (1, 1), (0, 1), (0, 0))) == "repeated"
    assert forward.centre() == pytest.approx((0.5, 0.5))


@settings(max_examples=60, deadline=None)
@given(
    corners=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0.01, 1), st.floats(0.01, 1)),
    point=st.tuples(st.floats(-2, 2), st.floats(-2, 2)),
)
def test_a_point_is_inside_a_box_exactly_when_its_excess_is_not_positive(corners, point) -> None:
    x0, y0, w, h = corners
    box = _region("box", (x0, y0), (x0 + w, y0 + h))
    inside = x0 <= point[0] <= x0 + w and y0 <= point[1] <= y0 + h
    outside_by = float(excess(box.halfplanes(), np.array([point])).max())
    assert (outside_by <= 1e-12) == inside or abs(outside_by) < 1e-9
    if not inside:  # and the excess is the distance to the box along the farthest axis
        assert outside_by == pytest.approx(max(x0 - point[0], point[0] - x0 - w, y0 - point[1], point[1] - y0 - h))


def test_keep_out_regions_are_resolved_and_a_body_starting_inside_one_it_keeps_out_is_e452() -> None:
    inside_block = "region (0.4, -0.05) to (0.6, 0.05) m"
    assert _codes(f"task t {{\n    scene s\n    goal block at (0.6, 0) m\n    keep out {inside_block}\n}}\n") == [
        "E452"
    ]
    program = compile_source(  # the tray region keeps out a body named only: `block` starts clear of it
        SCENE + "task t {\n    scene s\n    goal block at (0.45, 0.3) m\n    keep block out of tray\n}\n",
        base_dir=ROOT,
    )
    (keep,) = program.tasks["t"].keep_out
    assert keep.region is not None and keep.region.name == "tray" and keep.applies_to("block")
    assert not keep.applies_to("other")
    assert _codes("task t {\n    scene s\n    goal block at (0.6, 0) m\n    keep out sink\n}\n") == ["E301"]


def test_keep_out_prints_as_written() -> None:
    text = SCENE + "task t {\n    scene s\n    goal block at (0.6, 0) m\n    keep out tray\n"
    text += "    keep block out of region (0.1, 0.2) to (0.3, 0.4) m\n}\n"
    module = parse_module(text, "t.vkg")
    printed = print_module(module)
    assert "    keep out tray\n    keep block out of region (0.1, 0.2) to (0.3, 0.4) m\n" in printed
    assert parse_module(printed, "t.vkg") == module


@settings(max_examples=60, deadline=None)
@given(
    shift=st.tuples(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5)),
    turn=st.floats(0, 6.3),
)
def test_the_overlap_depth_of_a_square_and_the_unit_box_is_exact(shift, turn) -> None:
    """A square of side 0.5 turned and moved against the unit box: the depth is positive exactly when some
    point of one lies inside the other (checked on a fine grid of the square), and never more than 0.5."""
    box = _region("box", (0.0, 0.0), (1.0, 1.0)).points()
    c, s = np.cos(turn), np.sin(turn)
    corners = np.array([(-0.25, -0.25), (0.25, -0.25), (0.25, 0.25), (-0.25, 0.25)]) @ [[c, s], [-s, c]] + shift
    depth = overlap_depth(box, corners)
    u, v = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 41))
    grid = corners[0] + np.outer(u.ravel(), corners[1] - corners[0]) + np.outer(v.ravel(), corners[3] - corners[0])
    inside = np.all((grid > 1e-9) & (grid < 1 - 1e-9), axis=1).any()
    if depth > 0.03:
        assert inside
    if depth < -1e-9:
        assert not inside
    assert depth <= 0.5 + 1e-9


@pytest.mark.parametrize(
    ("goal", "code"),
    [
        ("goal block in region (0.6) to (0.8, 0.1) m", "E204"),
        ("goal block in region (-1e308, -1e308) to (1e308, 1e308) m", "E451"),
        ("goal block in region (0.6, 0.2) to (0.8, 0.4) kg", "E201"),
        ("goal block in region polygon (0.6, 0.2), (0.8, 0.3, 0.1), (0.7, 0.5) m", "E204"),
        ("goal block at (0.6, 0) m\n    keep out region polygon (0.6, 0.2), (1e308, 0.3), (0.7, 1e308) m", "E451"),
        ("goal block at (0.6, 0) m\n    keep out region (0.6, 0.2) to (0.8, 0.4)", "E202"),
    ],
)
def test_malformed_regions_are_diagnostics_not_crashes(goal: str, code: str) -> None:
    assert code in _codes(f"task t {{\n    scene s\n    {goal}\n}}\n")


CM = st.integers(-30, 30).map(lambda v: v / 100)


@st.composite
def _convex_region(draw: st.DrawFn) -> Region:
    """A box, or a convex polygon: corners at increasing angles around a centre (on a centimetre grid or not)."""
    if draw(st.booleans()):
        x0, y0 = draw(CM), draw(CM)
        return _region("box", (x0, y0), (x0 + draw(st.integers(1, 40)) / 100, y0 + draw(st.integers(1, 40)) / 100))
    count = draw(st.integers(3, 8))
    angles = sorted(draw(st.lists(st.floats(0, 2 * np.pi, exclude_max=True), min_size=count, max_size=count)))
    radius = draw(st.integers(5, 30)) / 100
    corners = [(round(radius * np.cos(a), 3), round(radius * np.sin(a), 3)) for a in angles]
    assume(len(set(corners)) == count)  # a corner written twice: test_a_corner_written_twice_bounds_nothing
    return _region("polygon", *corners)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(
    _convex_region(),
    st.tuples(st.integers(1, 40), st.integers(1, 40)).map(lambda v: (v[0] / 100, v[1] / 100)),
    st.floats(-np.pi, np.pi) | st.sampled_from([0.0, np.pi / 2]),
    st.integers(1, 5).map(lambda v: v / 100),
)
def test_a_footprint_fits_exactly_when_scipys_linear_program_says_so(
    region: Region, size: tuple[float, float], yaw: float, tolerance: float
) -> None:
    """E453's fit (vkgl.lang.checks.geometry.regions.translation_fits, exact in 2-D) is SciPy's `linprog`'s."""
    from scipy.optimize import linprog

    from vkgl.lang.checks.geometry.regions import translation_fits

    if region_problem(region) is not None:
        return
    corners = np.array([[sx * size[0] / 2, sy * size[1] / 2] for sx in (-1, 1) for sy in (-1, 1)])
    c, s = np.cos(yaw), np.sin(yaw)
    turned = np.array([[c, -s], [s, c]]) @ corners.T
    planes = region.halfplanes()
    reach = (planes[:, :2] @ turned).max(axis=1)

    def lp_fits(slack: float) -> bool:
        rows = planes[:, 2] + slack - reach
        return linprog(np.zeros(2), A_ub=planes[:, :2], b_ub=rows, bounds=[(None, None)] * 2).status == 0

    # HiGHS's own feasibility tolerance (1e-7) decides a footprint that fits to within it (hypothesis found a
    # 5 cm side in a 1 cm box grown by 2 cm on each side, turned 1e-7 rad: 2e-9 m too wide, "optimal" for the
    # LP): the verdicts compared are those a micrometre does not change
    if lp_fits(tolerance - 1e-6):
        assert translation_fits(planes, reach, tolerance)
    elif not lp_fits(tolerance + 1e-6):
        assert not translation_fits(planes, reach, tolerance)


def test_a_corner_written_twice_bounds_nothing() -> None:
    """A polygon with a repeated corner has an edge of no length (a row of NaN): the fit ignores it."""
    from vkgl.lang.checks.geometry.regions import translation_fits

    region = _region("polygon", (0.0, 0.0), (0.2, 0.0), (0.2, 0.0), (0.2, 0.1), (0.0, 0.1))
    with np.errstate(invalid="ignore"):
        planes = region.halfplanes()
    assert translation_fits(planes, np.full(len(planes), 0.05), 0.0)  # a 10 x 10 cm square: it just fits
    assert not translation_fits(planes, np.full(len(planes), 0.06), 0.0)


def test_a_region_goal_must_leave_the_body_room_on_the_table() -> None:
    """The Block (10 x 20 cm) fits in the region, but on the table it must fit in the region's part there: 12 cm
    of a box that passes the table's edge at x = 1.3 m is room (yaw 0deg), 3 cm is not (E423), nor any of a
    region written in millimetres as metres."""
    task = "task t {{\n    scene s\n    goal block in region ({x0}, -0.2) to ({x1}, 0.2) {unit} yaw 0deg\n}}\n"
    compile_source(SCENE + task.format(x0=1.18, x1=1.5, unit="m"), base_dir=ROOT)
    assert _codes(task.format(x0=1.27, x1=1.5, unit="m")) == ["E423"]
    assert _codes(task.format(x0=600, x1=800, unit="m")) == ["E423"]
