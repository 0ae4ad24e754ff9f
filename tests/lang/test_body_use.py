"""`vkgc infer` finds the module its output will `use` for the body before inferring, or stops saying which
`--use` to pass (`vkgl.lang.body_use`): a module that would not compile is never written."""

from __future__ import annotations

from pathlib import Path

import pytest
from synthetic import block_pushes

from vkgl.cli import main
from vkgl.errors import InputError
from vkgl.lang.body_use import check_body_use

_CRATE = "body Crate {\n    shape box (10, 20, 5) cm\n    mass 0.5 kg\n}\n"


@pytest.fixture
def crate_trials(tmp_path: Path) -> Path:
    trials = block_pushes()
    trials.body = "Crate"
    path = tmp_path / "crate.npz"
    trials.save(path)
    return path


def test_the_default_use_of_a_body_the_stdlib_lacks_stops_before_writing(tmp_path, crate_trials, capsys) -> None:
    out = tmp_path / "lib" / "affordances" / "crate.vkg"
    out.parent.mkdir(parents=True)
    assert main(["infer", str(crate_trials), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(
        "vkgc: error: the trials are of `Crate`, and the default `--use stdlib.bodies.crate` names no module "
        "(cannot find module `stdlib.bodies.crate`;"
    )
    assert "pass `--use` the module that declares `body Crate`" in err and "`--use ../bodies/crate.vkg`" in err
    assert not out.exists()


def test_a_body_file_in_the_stdlib_layout_is_named_and_its_use_works(tmp_path, crate_trials, capsys) -> None:
    (tmp_path / "lib" / "bodies").mkdir(parents=True)
    (tmp_path / "lib" / "bodies" / "crate.vkg").write_text(_CRATE)
    out = tmp_path / "lib" / "affordances" / "crate.vkg"
    out.parent.mkdir()
    assert main(["infer", str(crate_trials), "-o", str(out)]) == 1
    assert "lib/bodies/crate.vkg` declares it: pass `--use ../bodies/crate.vkg`" in capsys.readouterr().err
    assert main(["infer", str(crate_trials), "-o", str(out), "--use", "../bodies/crate.vkg"]) == 0
    assert main(["check", str(out)]) == 0


def test_a_given_use_that_declares_another_body_or_is_missing_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "crate.vkg"
    with pytest.raises(InputError, match=r"`--use stdlib.bodies.block` declares no body `Crate` \(its bodies: `Block`"):
        check_body_use("stdlib.bodies.block", "Crate", out, given=True)
    (tmp_path / "mylib" / "bodies").mkdir(parents=True)
    (tmp_path / "mylib" / "bodies" / "crate.vkg").write_text(_CRATE)
    with pytest.raises(InputError, match=r"did you mean `mylib.bodies.crate`\?"):
        check_body_use("mylib.bodies.crat", "Crate", out, given=True)
    check_body_use("mylib.bodies.crate", "Crate", out, given=True)  # found beside the output: no error


def test_a_body_file_beside_the_output_is_named_as_a_path_from_there(tmp_path: Path) -> None:
    (tmp_path / "crate.vkg").write_text(_CRATE)
    with pytest.raises(InputError, match=r"crate.vkg` declares it: pass `--use crate.vkg`"):
        check_body_use("stdlib.bodies.crate", "Crate", tmp_path / "crate_affordances.vkg", given=False)
