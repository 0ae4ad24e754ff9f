"""`tips above` from a dataset: per face, the highest explored height below the lowest one that tipped."""

from __future__ import annotations

import numpy as np
import pytest

from vkgl.errors import InputError
from vkgl.formats.trials import Trials
from vkgl.infer.faces.tipping import safe_heights, tipping_ir
from vkgl.infer.library import infer_library
from vkgl.lang.ir.geometry import pushed_face
from vkgl.lang.ir.nodes import AffordanceSet, Module, Ref
from vkgl.lang.syntax.printer import print_module

REST = 0.06  # m: the body origin's height over the table at the start (a 12 cm carton)
TIP = "the body tipped over (tilted 5.3 deg, more than 5 deg)"


def dataset(pushes: list[tuple[str, float, str]]) -> Trials:
    """One trial per (face, height over the table, reason); `ok` unless a reason is given."""
    inward = {"+x": (-1, 0, 0), "-x": (1, 0, 0), "+y": (0, -1, 0), "-y": (0, 1, 0), "+z": (0, 0, -1)}
    n = len(pushes)
    T_ow = np.tile(np.eye(4), (n, 2, 1, 1))
    T_ow[:, :, 2, 3] = REST
    contact = np.array([[0.0, 0.0, height - REST] for _, height, _ in pushes])
    return Trials(
        body="Carton",
        t=np.tile([0.0, 0.02], (n, 1)),
        T_ro=np.tile(np.eye(4), (n, 2, 1, 1)),
        T_ow=T_ow,
        contact=contact,
        force=np.array([inward[face] for face, _, _ in pushes], dtype=float),
        ok=np.array([reason == "" for _, _, reason in pushes]),
        reason=np.array([reason for _, _, reason in pushes]),
    )


def test_the_safe_height_is_the_highest_upright_one_below_the_lowest_tip() -> None:
    trials = dataset([("+x", 0.02, ""), ("+x", 0.06, TIP), ("+x", 0.10, TIP), ("+x", 0.11, "")])
    assert safe_heights(trials) == {"+x": pytest.approx(0.02)}


def test_a_face_that_tipped_at_every_height_is_safe_nowhere() -> None:
    assert safe_heights(dataset([("-y", 0.02, TIP), ("-y", 0.06, TIP)])) == {"-y": 0.0}


def test_no_clause_when_nothing_tipped_and_failures_say_nothing() -> None:
    failed = "the body left the table (its lowest point rose 1.2 cm)"
    assert tipping_ir(dataset([("+x", 0.02, ""), ("+x", 0.06, failed)])) == []
    assert safe_heights(dataset([("+x", 0.02, failed), ("+x", 0.06, TIP)])) == {"+x": 0.0}


def test_faces_with_the_same_height_share_a_clause_lowest_first() -> None:
    trials = dataset(
        [("-x", 0.02, ""), ("-x", 0.06, TIP), ("+x", 0.02, ""), ("+x", 0.06, TIP), ("+y", 0.06, ""), ("+y", 0.1, TIP)]
    )
    clauses = tipping_ir(trials)
    assert [(round(c.height.value, 6), c.faces) for c in clauses] == [(0.02, ["+x", "-x"]), (0.06, ["+y"])]
    text = print_module(
        Module(path="m.vkg", decls=[AffordanceSet(body=Ref(name="Carton"), affordances=[], tipping=clauses)])
    )
    assert "tips above 2 cm on faces +x, -x\n    tips above 6 cm on faces +y\n" in text


def test_the_pushed_face_comes_from_the_force_and_the_top_is_no_side_face() -> None:
    assert pushed_face(np.array([-1.0, 0.1, 0.0])) == "+x"
    assert pushed_face(np.array([0.0, 1.0, 0.0])) == "-y"
    assert pushed_face(np.array([0.0, 0.0, -1.0])) is None
    assert pushed_face(np.zeros(3)) is None


def test_a_dataset_where_every_push_tipped_is_an_input_error_that_says_so() -> None:
    with pytest.raises(InputError, match=r"every one of the 2 pushes tipped it over.*heights H"):
        infer_library(dataset([("+x", 0.06, TIP), ("+x", 0.1, TIP)]), body_use="c.vkg", header="# test")
