"""Bad exploration input: a clear error that says where (file:line:col) and what to change, never a traceback."""

from __future__ import annotations

import zipfile
from pathlib import Path

import pytest
import trimesh
from sim_bodies import FILE, block, push_policy, q, stick, v, with_policy

from vkgl.errors import CompileError, InputError, SimulationError
from vkgl.lang.ir import Body, MeshShape
from vkgl.sim.explore import explore


def explore_error(body: Body) -> CompileError:
    with pytest.raises(CompileError) as info:
        explore(body, jobs=1)
    assert len(info.value.diagnostics) == 1
    return info.value


def test_a_body_without_explore_block_is_reported_at_its_name() -> None:
    error = explore_error(block().model_copy(update={"explores": []}))
    assert str(error).startswith(f"{FILE}:7:6: error[E701]: body `Block` has no `explore` block")
    assert "explore pushes {" in str(error)  # says what to add


@pytest.mark.parametrize("face, words", [("+w", "there is no face `+w`"), ("-z", "underside, which lies on the table")])
def test_a_face_that_cannot_be_pushed_is_reported_at_the_contacts(face: str, words: str) -> None:
    error = explore_error(with_policy(block(), faces=["+x", face]))
    assert str(error).startswith(f"{FILE}:11:5: error[E703]: ")
    assert words in str(error)


def test_an_unknown_grasp_frame_is_reported_at_its_name() -> None:
    error = explore_error(stick(grasp="grip"))
    assert str(error).startswith(f"{FILE}:11:9: error[E705]: body `Stick` has no frame `grip` to grasp")
    assert "its frames: handle, tip" in str(error)


@pytest.mark.parametrize("body", [with_policy(block(), magnitude=0.0), with_policy(stick(), magnitude=0.0)])
def test_a_zero_force_is_reported_at_the_force(body: Body) -> None:
    error = explore_error(body)
    assert "error[E706]: the force of explore" in str(error) and "a zero force moves nothing" in str(error)
    assert str(error).startswith(f"{FILE}:12:5:")


def test_a_zero_duration_is_reported_at_the_duration() -> None:
    error = explore_error(with_policy(block(), duration=0.0))
    assert str(error).startswith(f"{FILE}:13:5: error[E707]: the duration of explore `pushes` must be positive")


def test_zero_steps_and_an_all_zero_direction_grid_are_reported() -> None:
    assert "error[E704]" in str(explore_error(with_policy(block(), steps=0)))
    assert "only the zero direction" in str(explore_error(with_policy(stick(), grid=(1, 1, 1))))


def test_a_policy_with_neither_contacts_nor_grasp_is_reported() -> None:
    policy = block().explores[0].model_copy(update={"contacts": None})
    error = explore_error(block().model_copy(update={"explores": [policy]}))
    assert "error[E702]" in str(error) and "`contacts on faces ... steps K` or `grasp FRAME`" in str(error)


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
    trimesh.creation.cylinder(radius=0.04, height=0.1, sections=24).export(stl)
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
    from vkgl.lang.ir import BoxShape, Pose, ShapePart, UnionShape

    legs = UnionShape(
        parts=[ShapePart(shape=BoxShape(size=v(0.05, 0.05, 0.05)), pose=Pose(position=v(0, y, 0))) for y in (-0.1, 0.1)]
    )
    body = block().model_copy(update={"shape": legs, "explores": [push_policy(["+x"], 3, 1.0, 0.1)]})
    error = explore_error(body)
    assert str(error).startswith(f"{FILE}:11:5: error[E708]: face +x of `Block` has no surface at contact point 2 of 3")
