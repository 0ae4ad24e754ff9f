"""Bad exploration input: a clear error that says where (file:line:col) and what to change, never a traceback.

Bad policies are diagnostics of the front end (vkgl/lang/checks/explore.py), reported when the
program compiles; the explorer trusts checked IR.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import pytest
import trimesh
from sim_bodies import FILE, block, push_policy, q, v

from vkgl.errors import CompileError, InputError, SimulationError
from vkgl.lang.compiler import compile_source
from vkgl.lang.ir.nodes import Body, MeshShape
from vkgl.sim.explore import explore

SRC = "policy.vkg"
BLOCK = """\
body Block {
    shape box (10, 20, 5) cm
    mass 0.5 kg
    explore pushes {
        contacts on faces +x, -x steps 9
        force normal 1 N
        duration 2 s
    }
}
"""
STICK = """\
body Stick {
    shape box (40, 2, 2) cm
    mass 0.1 kg
    frame handle = (-15, 0, 0) cm
    frame tip = (20, 0, 0) cm
    explore wield {
        grasp handle
        force directions 3 x 3 x 3  1 N
        duration 1 s
    }
}
"""


def compile_error(text: str) -> CompileError:
    """The one error `vkgc` reports for a bad policy, when the program compiles (before any simulation)."""
    with pytest.raises(CompileError) as info:
        compile_source(text, SRC)
    assert len(info.value.diagnostics) == 1, info.value.diagnostics
    return info.value


def test_a_body_without_explore_block_is_an_input_error_at_its_name() -> None:
    with pytest.raises(InputError) as info:
        explore(block().model_copy(update={"explores": []}), jobs=1)
    assert str(info.value).startswith(f"{FILE}:7:6: body `Block` has no `explore` block")
    assert "explore pushes {" in str(info.value)  # says what to add


def test_the_underside_cannot_be_pushed() -> None:
    error = compile_error(BLOCK.replace("+x, -x", "+x, -z"))
    assert str(error).startswith(f"{SRC}:5:31: error[E414]: face -z of `Block` is its underside")


def test_an_unknown_grasp_frame_is_reported_at_its_name() -> None:
    error = compile_error(STICK.replace("grasp handle", "grasp grip"))
    assert str(error).startswith(f"{SRC}:7:15: error[E303]: body `Stick` has no frame `grip`")


@pytest.mark.parametrize("text", [BLOCK.replace("normal 1 N", "normal 0 N"), STICK.replace("3  1 N", "3  0 N")])
def test_a_zero_force_is_reported_at_the_force(text: str) -> None:
    assert "error[E411]: the force must be positive, got `0 N`" in str(compile_error(text))


def test_a_zero_duration_is_reported_at_the_duration() -> None:
    error = compile_error(BLOCK.replace("duration 2 s", "duration 0 s"))
    assert str(error).startswith(f"{SRC}:7:18: error[E411]: the duration must be positive")


def test_zero_steps_and_an_all_zero_direction_grid_are_reported() -> None:
    assert "error[E411]: `steps` must be at least 1" in str(compile_error(BLOCK.replace("steps 9", "steps 0")))
    error = compile_error(STICK.replace("3 x 3 x 3", "1 x 1 x 1"))
    assert "error[E404]" in str(error) and "only the zero direction" in str(error)


def test_a_policy_must_be_a_push_or_a_grasp() -> None:
    neither = compile_error(BLOCK.replace("        contacts on faces +x, -x steps 9\n", ""))
    assert "error[E407]" in str(neither) and "`contacts on faces +x, -x steps 9` or `grasp FRAME`" in str(neither)
    both = compile_error(
        BLOCK.replace("steps 9\n", "steps 9\n        grasp com\n").replace(
            "mass 0.5 kg", "mass 0.5 kg\n    frame com = (0, 0, 0) cm"
        )
    )
    assert "error[E413]" in str(both) and "has both `contacts` and `grasp`" in str(both)
    wrong_force = compile_error(STICK.replace("force directions 3 x 3 x 3  1 N", "force normal 1 N"))
    assert "error[E413]" in str(wrong_force) and "`force directions I x J x K Q`" in str(wrong_force)


@pytest.mark.parametrize("statement", ["force normal 1 N", "duration 2 s"])
def test_a_policy_without_force_or_duration_is_reported(statement: str) -> None:
    error = compile_error(BLOCK.replace(f"        {statement}\n", ""))
    assert f"error[E407]: explore `pushes` has no `{statement.split()[0]}`" in str(error)


def mesh_body(path: Path, duration: float = 0.2) -> Body:
    return Body(
        name="Part",
        shape=MeshShape(path=str(path), resolved=str(path)),
        mass=q(0.2, "kg"),
        explores=[push_policy(["+x"], 1, 1.0, duration)],
    )


def test_a_mesh_dart_cannot_read_is_an_error_naming_the_file(tmp_path: Path) -> None:
    stl = tmp_path / "part.stl"
    trimesh.creation.box(extents=[0.05, 0.05, 0.05]).export(stl)
    archive = tmp_path / "part.zip"  # trimesh reads meshes inside archives; DART's importer does not
    with zipfile.ZipFile(archive, "w") as zf:
        zf.write(stl, "part.stl")
    with pytest.raises(SimulationError, match=r"part\.zip: DART cannot load this mesh"):
        explore(mesh_body(archive), jobs=1)


def test_a_mesh_nobody_can_read_is_an_error_naming_the_file(tmp_path: Path) -> None:
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nf 1 2 3\n")
    with pytest.raises(InputError, match=r"broken\.obj"):
        explore(mesh_body(broken), jobs=1)


def test_a_mesh_body_explores(tmp_path: Path) -> None:
    stl = tmp_path / "can.stl"
    # an octagonal can, not a box: 8 sections, not 24, whose bottom's contacts with the table made the 0.5 s
    # trial 7 CPU-s of DART instead of 3 (it slides the same 2.4 cm)
    trimesh.creation.cylinder(radius=0.04, height=0.1, sections=8).export(stl)
    trials = explore(mesh_body(stl, duration=0.5), jobs=1)
    assert trials.ok.all()
    assert trials.T_ow[0, trials.samples(0) - 1, 0, 3] < -0.01  # pushed along -x, square on the face
    assert trials.T_ow[0, 0, 2, 3] == pytest.approx(0.05, abs=1e-6)  # it started resting on the table


def test_handmade_spans_are_those_of_a_source_file() -> None:
    # Guards the helpers above: the spans they give are what a parser would attach.
    body = block()
    assert str(body.name_span) == f"{FILE}:7:6" and str(body.explores[0].contacts.span) == f"{FILE}:11:5"
    assert v(1, 2, 3).values == (1.0, 2.0, 3.0)


def test_a_contact_point_over_a_gap_in_the_body_is_reported() -> None:
    text = """\
body Legs {
    shape union {
        box (5, 5, 5) cm at (0, -10, 0) cm
        box (5, 5, 5) cm at (0, 10, 0) cm
    }
    mass 0.2 kg
    explore pushes {
        contacts on faces +x steps 3
        force normal 1 N
        duration 1 s
    }
}
"""
    error = compile_error(text)
    assert str(error).startswith(f"{SRC}:8:27: error[E415]: face +x of `Legs` has no surface at contact point 2 of 3")
    wide = text.replace("box (5, 5, 5)", "box (5, 10, 5)").replace("steps 3", "steps 2")  # points at y = +-7.5 cm
    assert compile_source(wide, SRC).body("Legs").explores[0].contacts.steps == 2


HANDLE = """\
body Drawer {
    shape union {
        box (30, 40, 10) cm at (0, 0, 0) cm
        box (3, 1, 1) cm at (16.5, -6.5, 0) cm
        box (3, 1, 1) cm at (16.5, 6.5, 0) cm
        box (1, 14, 1) cm at (18.5, 0, 0) cm
    }
    mass 2 kg
    frame handle = (18, 0, 0) cm
    joint prismatic axis (1, 0, 0) limits (0, 30) cm
    explore pull {
        contacts at handle
        force normal 1 N
        duration 4 s
    }
}
"""


def test_contacts_at_a_frame_push_at_its_origin_along_its_x_axis() -> None:
    from vkgl.lang.syntax.printer import print_module
    from vkgl.sim.policy import plan_trials

    drawer = compile_source(HANDLE, SRC).body("Drawer")
    (ref,) = drawer.explores[0].contacts.frames
    assert ref.name == "handle" and str(ref.span) == f"{SRC}:12:21"
    assert "        contacts at handle\n" in print_module(compile_source(HANDLE, SRC).root)
    specs = plan_trials(drawer)  # from the closed end of the slide, then from the open end
    assert [s.joint_start for s in specs] == [0.0, pytest.approx(0.30)]
    for spec in specs:
        assert spec.kind == "push" and spec.label.startswith("pull at handle, from its ")
        assert spec.contact == pytest.approx([0.18, 0, 0]) and spec.direction == pytest.approx([1, 0, 0])


@pytest.mark.parametrize(
    ("frame", "says"),
    [
        ("(17, 0, 0) cm", "the fingertip meets the body 1.0 cm beyond it"),  # short of the bar
        ("(19, 0, 0) cm", "1 cm behind it, where the fingertip comes from, is inside the body"),  # the bar's far side
        ("(18, 0, 0) cm yaw 180deg", "1 cm behind it, where the fingertip comes from, is inside the body"),  # reversed
        ("(18, 10, 0) cm", "the fingertip meets nothing"),  # beside the bar, not behind it
    ],
)
def test_a_contact_frame_off_the_surface_is_reported_at_its_name(frame: str, says: str) -> None:
    error = compile_error(HANDLE.replace("(18, 0, 0) cm", frame))
    assert str(error).startswith(f"{SRC}:12:21: error[E415]: contact frame `handle` of `Drawer` is not on its surface")
    assert says in str(error)


def test_an_unknown_contact_frame_and_a_force_of_directions_are_reported() -> None:
    error = compile_error(HANDLE.replace("contacts at handle", "contacts at handel"))
    assert str(error).startswith(f"{SRC}:12:21: error[E303]: body `Drawer` has no frame `handel`")
    assert "did you mean `handle`?" in error.diagnostics[0].notes[0]
    error = compile_error(HANDLE.replace("force normal 1 N", "force directions 3 x 1 x 1  1 N"))
    assert "error[E413]" in str(error) and "`force normal Q` (along the frame's x axis)" in str(error)
