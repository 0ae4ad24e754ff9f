"""The planner's hulls are Qhull's, whether computed or read back from the cache folder (vkgl.plan.problem.hulls)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull, QhullError

from vkgl.plan.problem import hulls
from vkgl.plan.problem.hulls import hull_vertices, kept_width, outline_corners


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("VKGL_CACHE_DIR", str(tmp_path))
    return tmp_path


def _points(seed: int, count: int) -> np.ndarray:
    return np.random.default_rng(seed).normal(size=(count, 3))


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=0, max_value=2**32 - 1), st.integers(min_value=4, max_value=60))
def test_a_hull_is_qhulls_computed_and_read_back(seed: int, count: int) -> None:
    points = _points(seed, count)
    expected = ConvexHull(points).vertices
    computed, kept = hull_vertices(points), hull_vertices(points)  # the second from the cache folder
    assert np.array_equal(computed, expected) and computed.dtype == expected.dtype
    assert np.array_equal(kept, expected) and kept.dtype == expected.dtype


def test_a_hull_is_kept_in_one_file_named_by_its_points(cache: Path) -> None:
    points = _points(1, 30)
    hull_vertices(points)
    files = list(cache.glob("hull-*.json"))
    assert len(files) == 1
    data = json.loads(files[0].read_text(encoding="utf-8"))
    assert data["format"] == hulls.CACHE_FORMAT and data["vertices"] == ConvexHull(points).vertices.tolist()
    hull_vertices(points + 1.0)  # other points, another file
    assert len(list(cache.glob("hull-*.json"))) == 2


@pytest.mark.parametrize(
    "content",
    ["", "not json", "[[[[[[", '{"format": "vkg-hull-cache/1"}', "WRONG-KEY", "OUT-OF-RANGE", "NOT-INTS", "EMPTY"],
)
def test_an_unusable_cache_file_is_ignored_and_written_again(cache: Path, content: str) -> None:
    points = _points(2, 20)
    hull_vertices(points)
    (path,) = cache.glob("hull-*.json")
    data = json.loads(path.read_text(encoding="utf-8"))
    changed = {
        "WRONG-KEY": {**data, "key": "0" * 64},
        "OUT-OF-RANGE": {**data, "vertices": [0, 1, 2, 20]},
        "NOT-INTS": {**data, "vertices": [0, 1.0, True, 3]},
        "EMPTY": {**data, "vertices": []},
    }
    path.write_text(json.dumps(changed[content]) if content in changed else content, encoding="utf-8")
    assert np.array_equal(hull_vertices(points), ConvexHull(points).vertices)
    assert json.loads(path.read_text(encoding="utf-8")) == data


def test_without_a_cache_folder_the_hull_is_computed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("VKGL_CACHE_DIR", "off")
    points = _points(3, 25)
    assert np.array_equal(hull_vertices(points), ConvexHull(points).vertices)


def _outline(vertices: np.ndarray) -> np.ndarray:
    """What the planner took as an outline before the cache: Qhull's corners of the unique points."""
    unique = np.unique(vertices, axis=0)
    try:
        return unique[ConvexHull(unique).vertices]
    except (QhullError, ValueError):
        return unique


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=0, max_value=2**32 - 1), st.integers(min_value=4, max_value=40))
def test_an_outline_is_qhulls_corners_of_the_unique_points_computed_and_read_back(seed: int, count: int) -> None:
    points = np.round(_points(seed, count), 1)  # rounded: some points repeat
    points = np.vstack([points, points[: count // 2]])
    expected = _outline(points)
    computed, kept = outline_corners(points), outline_corners(points)  # the second from the cache folder
    assert np.array_equal(computed, expected) and computed.dtype == expected.dtype
    assert np.array_equal(kept, expected) and kept.shape == expected.shape


def test_flat_points_raise_as_qhull_does_and_are_a_whole_outline(cache: Path) -> None:
    flat = np.c_[_points(4, 10)[:, :2], np.zeros(10)]
    with pytest.raises(QhullError):
        hull_vertices(flat)
    assert np.array_equal(outline_corners(flat), np.unique(flat, axis=0))
    assert np.array_equal(outline_corners(flat[:2]), np.unique(flat[:2], axis=0))  # too few for Qhull
    assert list(cache.glob("hull-*.json")) == []  # only hulls that exist are kept
    box = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 2.0) for z in (0.0, 3.0)] + [[0.5, 1.0, 1.5]])
    assert np.array_equal(outline_corners(box), box[:8])
    assert np.array_equal(outline_corners(box), box[:8])  # read back
    assert len(list(cache.glob("hull-*.json"))) == 1


def test_a_tools_width_is_measured_once_and_read_back(cache: Path) -> None:
    points = _points(3, 12).ravel()
    calls: list[int] = []

    def measure() -> float:
        calls.append(1)
        return 0.0213

    assert kept_width(points, measure) == 0.0213
    assert kept_width(points, measure) == 0.0213  # read back from the cache folder
    assert calls == [1]
    assert kept_width(points + 0.5, measure) == 0.0213 and calls == [1, 1]  # another tool or grasp: measured
