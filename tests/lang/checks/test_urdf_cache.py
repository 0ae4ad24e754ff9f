"""DART's verdict on a URDF is remembered between processes (vkgl/lang/checks/urdf.py), and only when it holds.

The first check of a robot asks DART; a later one with the same URDF (same bytes, same place, same
meshes, same DART) asks the cache. A URDF DART rejects is asked again every time, and anything the load
depends on that changes asks DART again.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from vkgl.lang.checks import urdf
from vkgl.resources import CACHE_ENV, CACHE_OFF, stdlib_dir

PANDA = stdlib_dir() / "robots" / "panda.urdf"
TWO_LINKS = """<?xml version="1.0"?>
<robot name="two">
  <link name="base"/>
  <link name="tip">{visual}</link>
  <joint name="j" type="revolute">
    <parent link="base"/><child link="tip"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""
MESH = '<visual><geometry><mesh filename="{name}"/></geometry></visual>'
FACET = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex {x} 0 0\nvertex 0 0.1 0\nendloop\nendfacet\n"


def _stl(x: float) -> str:
    """An ASCII STL of two triangles DART (assimp) reads; `x` makes another one."""
    return f"solid part\n{FACET.format(x=x)}{FACET.format(x=x / 2)}endsolid part\n"


@pytest.fixture
def dart_loads(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The paths DART was asked to load (the cache in `tmp_path / "cache"`)."""
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "cache"))
    urdf.urdf_links.cache_clear()
    asked: list[str] = []
    real = urdf._load_in_dart

    def counted(path: str) -> str | None:
        asked.append(path)
        return real(path)

    monkeypatch.setattr(urdf, "_load_in_dart", counted)
    return asked


def _verdict(path: Path) -> str | None:
    urdf.urdf_links.cache_clear()  # as a new process would
    links, problem = urdf.urdf_links(str(path))
    assert links
    return problem


def test_a_urdf_dart_loaded_is_not_loaded_again(dart_loads: list[str]) -> None:
    assert _verdict(PANDA) is None
    assert _verdict(PANDA) is None
    assert dart_loads == [str(PANDA)]


def test_a_changed_urdf_or_mesh_is_loaded_again(dart_loads: list[str], tmp_path: Path) -> None:
    robot = tmp_path / "two.urdf"
    mesh = tmp_path / "part.stl"
    mesh.write_text(_stl(0.1))
    robot.write_text(TWO_LINKS.format(visual=MESH.format(name="part.stl")))
    assert _verdict(robot) is None
    assert _verdict(robot) is None
    assert len(dart_loads) == 1
    mesh.write_text(_stl(0.2))
    assert _verdict(robot) is None
    robot.write_text(TWO_LINKS.format(visual=""))
    assert _verdict(robot) is None
    assert len(dart_loads) == 3
    mesh.unlink()  # the URDF names it no more: the cached verdict holds
    assert _verdict(robot) is None
    assert len(dart_loads) == 3


def test_a_urdf_dart_rejects_is_asked_every_time(dart_loads: list[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(urdf, "_load_in_dart", lambda path: dart_loads.append(path) or "DART cannot load it")
    assert _verdict(PANDA) == "DART cannot load it"
    assert _verdict(PANDA) == "DART cannot load it"
    assert len(dart_loads) == 2


def test_package_uris_and_a_cache_turned_off_keep_nothing(
    dart_loads: list[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot = tmp_path / "two.urdf"
    robot.write_text(TWO_LINKS.format(visual=MESH.format(name="package://arm/part.stl")))
    _verdict(robot)
    _verdict(robot)
    monkeypatch.setenv(CACHE_ENV, CACHE_OFF)
    _verdict(PANDA)
    _verdict(PANDA)
    assert len(dart_loads) == 4
    assert not (tmp_path / "cache").exists() or not list((tmp_path / "cache").glob("urdf-*"))
