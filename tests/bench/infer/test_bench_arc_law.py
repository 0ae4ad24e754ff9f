"""bench/infer/bench_arc_law.py's reading of a held-out push in the law's own terms: at the contact's travel."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[3] / "bench" / "infer"


@pytest.fixture(scope="module")
def bench() -> ModuleType:
    sys.path.insert(0, str(BENCH))
    try:
        spec = importlib.util.spec_from_file_location("bench_arc_law", BENCH / "bench_arc_law.py")
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module
    finally:
        sys.path.remove(str(BENCH))


def _turned(pivot: np.ndarray, turn: float) -> np.ndarray:
    """The pose (x, y, yaw) of a body turned by `turn` (rad) about `pivot` (its start frame)."""
    c, s = math.cos(turn), math.sin(turn)
    return np.append(pivot - np.array([[c, -s], [s, c]]) @ pivot, turn)


def test_a_point_turned_about_a_pivot_travels_its_arc(bench: ModuleType) -> None:
    pivot, point = np.array([0.04, -0.105]), np.array([-0.06, 0.033])
    turn = -math.radians(53.0)
    assert bench.contact_travel(_turned(pivot, turn), point) == pytest.approx(
        abs(turn) * float(np.linalg.norm(point - pivot)), rel=1e-9
    )
    assert bench.contact_travel(np.zeros(3), point) == 0.0
    assert bench.contact_travel(np.array([0.1, 0.0, 0.0]), point) == pytest.approx(0.1)  # a slide: the chord


def test_a_held_out_push_is_read_where_its_contact_has_travelled_as_far_as_the_laws(bench: ModuleType) -> None:
    """Like CubeM 3.3 cm off its centre (bench_arc_law, 2026-11-28: 7.16 deg at the centre's 10 cm, 3.44 deg at the
    contact's travel): the law's pivot (4.0, -10.5) cm, DART's 1.6 cm farther across, so per travel of the contact
    DART turns 7 % slower. Read where both centres have moved 10 cm, the law's faster turn counts twice (its nearer
    pivot also moves the centre less per degree); read where the contact has travelled as far as the law's (what
    sigma, and the planner's margin, are scaled by), only the rate's error: 7 % of the law's 53 deg."""
    point = np.array([-0.06, 0.033])
    law_pivot, dart_pivot = np.array([0.04, -0.105]), np.array([0.04, -0.121])
    law = _turned(law_pivot, -math.radians(53.1))
    law_travel = bench.contact_travel(law, point)
    track = np.array([_turned(dart_pivot, -turn) for turn in np.linspace(0.0, 1.5, 3001)])
    own = bench.at_contact_travel(track, point, law_travel)
    assert bench.contact_travel(own, point) == pytest.approx(law_travel, abs=2e-4)
    slower = 1.0 - float(np.linalg.norm(point - law_pivot) / np.linalg.norm(point - dart_pivot))
    at_travel = abs(math.degrees(law[2] - own[2]))
    assert at_travel == pytest.approx(slower * 53.1, abs=0.1)
    centre = np.linalg.norm(track[:, :2], axis=1)
    at_chord = abs(math.degrees(law[2] - track[int(np.searchsorted(centre, np.linalg.norm(law[:2])))][2]))
    assert at_chord > 1.5 * at_travel
    assert np.array_equal(bench.at_contact_travel(track, point, 10.0), track[-1])  # never that far: the last pose
