"""`vkgc learn --ray`: the trials run on a local Ray instance and the modules are byte-identical to the pool's.

Ray is a hard requirement of this test (installed by .ci/run through the `ray`
extra): without it the import in the test fails it instead of skipping. It is imported there, not at the top:
importing Ray takes about a second, and every pytest-xdist worker imports every test module to collect it.

Both runs are on this machine, so the bytes compare determinism, not CPUs. On a cluster whose nodes
have other CPUs the trials may differ in their last bits; the modules are printed rounded, which absorbs
that (tests/infer/test_learn.py, `test_committed_stdlib_is_what_learn_makes`, says why).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from vkgl import cli
from vkgl.sim import explore as explore_module

BODY = """# {name}: a block pushed at two points of one face, briefly: a fast `vkgc learn`.
body {name} {{
    shape box (10, 20, 5) cm
    mass 0.5 kg
    friction 0.5
    explore pushes {{
        contacts on faces {face} steps 2
        force normal 1 N
        duration 1 s
    }}
}}
"""


@pytest.fixture
def bodies(tmp_path: Path) -> Path:
    folder = tmp_path / "bodies"
    folder.mkdir()
    (folder / "slab.vkg").write_text(BODY.format(name="Slab", face="+x"), encoding="utf-8")
    (folder / "tiny.vkg").write_text(BODY.format(name="Tiny", face="-x"), encoding="utf-8")
    return folder


def test_learn_on_ray_writes_the_same_modules_as_the_process_pool(
    bodies: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    import ray

    pool, on_ray = tmp_path / "pool", tmp_path / "ray"
    # one job each: the bytes compare the runners, not the number of workers (each Ray worker imports DART anew)
    assert cli.main(["learn", str(bodies), "-o", str(pool), "--jobs", "1"]) == 0

    def no_pool(*args: object) -> None:
        raise AssertionError("--ray ran trials in the local process pool")

    monkeypatch.setattr(explore_module, "_run_all", no_pool)
    assert not ray.is_initialized()
    assert (
        cli.main(
            [
                "learn",
                str(bodies / "slab.vkg"),
                str(bodies / "tiny.vkg"),
                "-o",
                str(on_ray),
                "--jobs",
                "1",
                "--ray",
            ]
        )
        == 0
    )
    assert not ray.is_initialized()  # the instance it started is shut down
    written = sorted(p.name for p in pool.iterdir())
    assert written == ["slab.vkg", "tiny.vkg"] == sorted(p.name for p in on_ray.iterdir())
    for name in written:
        assert (on_ray / name).read_bytes() == (pool / name).read_bytes()
    assert "affordances Slab {" in (pool / "slab.vkg").read_text(encoding="utf-8")
    assert capsys.readouterr().out.count(": generated") == 4


def test_body_with_several_files_is_refused(bodies: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["learn", str(bodies), "--body", "Slab"]) == 1
    assert "--body Slab: names a body of one file, but 2 files were given" in capsys.readouterr().err


def test_a_folder_without_body_files_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["learn", str(tmp_path)]) == 1
    assert "a folder without .vkg body files" in capsys.readouterr().err
