"""Import resolution (docs/language.md, "Modules and imports"): where `use` finds modules, cycles, one namespace."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from vkgl.errors import CompileError
from vkgl.lang.compiler import check_files, compile_file
from vkgl.lang.resolve import import_roots
from vkgl.resources import stdlib_dir


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def _body(name: str, mass_kg: float) -> str:
    return f"body {name} {{\n    shape box (10, 10, 10) cm\n    mass {mass_kg} kg\n}}\n"


@pytest.fixture
def tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.delenv("VKG_PATH", raising=False)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _mass(program_file: Path, body: str) -> float:
    return compile_file(program_file).bodies[body].mass.value


def test_dotted_use_looks_in_the_importing_files_directory_first(tmp: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    main = _write(tmp / "project" / "main.vkg", "use parts.crate\n")
    _write(tmp / "project" / "parts" / "crate.vkg", _body("Crate", 1))
    _write(tmp / "elsewhere" / "parts" / "crate.vkg", _body("Crate", 2))
    monkeypatch.setenv("VKG_PATH", str(tmp / "elsewhere"))
    assert _mass(main, "Crate") == 1.0


def test_vkg_path_is_searched_in_order_after_the_files_directory(tmp: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    main = _write(tmp / "project" / "main.vkg", "use parts.crate\n")
    _write(tmp / "first" / "parts" / "crate.vkg", _body("Crate", 2))
    _write(tmp / "second" / "parts" / "crate.vkg", _body("Crate", 3))
    monkeypatch.setenv("VKG_PATH", os.pathsep.join([str(tmp / "first"), str(tmp / "second")]))
    assert _mass(main, "Crate") == 2.0
    monkeypatch.setenv("VKG_PATH", os.pathsep.join([str(tmp / "second"), str(tmp / "first")]))
    assert _mass(main, "Crate") == 3.0


def test_the_installed_stdlib_comes_last_and_is_the_only_stdlib(tmp: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    main = _write(tmp / "project" / "main.vkg", "use stdlib.bodies.block\nuse parts.crate\n")
    _write(tmp / "mine" / "parts" / "crate.vkg", _body("Crate", 1))
    _write(tmp / "mine" / "stdlib" / "bodies" / "block.vkg", _body("Block", 7))
    _write(tmp / "project" / "stdlib" / "bodies" / "block.vkg", _body("Block", 8))
    monkeypatch.setenv("VKG_PATH", str(tmp / "mine"))
    assert _mass(main, "Block") == 0.5  # the installed stdlib's Block: no local stdlib/ is read
    assert import_roots(str(main)) == [main.parent.resolve(), (tmp / "mine").resolve(), stdlib_dir().resolve().parent]
    assert import_roots(str(main), "stdlib.bodies.block") == [stdlib_dir().resolve().parent]


def test_a_copy_of_the_installed_stdlib_beside_a_file_is_no_warning(tmp: Path) -> None:
    """A source checkout after `pip install .`: its `stdlib/` is a byte-for-byte copy of the installed one."""
    installed = stdlib_dir() / "tools.vkg"
    _write(tmp / "stdlib" / "tools.vkg", installed.read_text(encoding="utf-8"))
    main = _write(tmp / "my_task.vkg", "use stdlib.tools\n")
    diagnostics, _ = check_files([str(main)])
    assert [d.code for d in diagnostics] == []


def test_string_use_is_relative_to_the_importing_file_not_the_working_directory(
    tmp: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _write(tmp / "lib" / "crate.vkg", _body("Crate", 4))
    main = _write(tmp / "project" / "tasks" / "main.vkg", 'use "../../lib/crate.vkg"\n')
    monkeypatch.chdir(tmp / "project")
    assert _mass(main, "Crate") == 4.0


def test_a_missing_path_is_reported_relative_to_the_importer(tmp: Path) -> None:
    _write(tmp / "scenes" / "tabletop.vkg", "")
    main = _write(tmp / "tasks" / "main.vkg", 'use "../scenes/tabletp.vkg"\n')
    diagnostics, _ = check_files([str(main)])
    assert [d.code for d in diagnostics] == ["E501"]
    assert "`../scenes/tabletp.vkg`" in diagnostics[0].message and "tasks" in diagnostics[0].message
    assert diagnostics[0].notes == ("did you mean `tabletop.vkg`?",)


def test_an_import_cycle_prints_the_cycle(tmp: Path) -> None:
    a = _write(tmp / "a.vkg", 'use "b.vkg"\n')
    _write(tmp / "b.vkg", "use c\n")
    _write(tmp / "c.vkg", 'use "a.vkg"\n')
    diagnostics, _ = check_files([str(a)])
    assert [d.code for d in diagnostics] == ["E502"]
    assert diagnostics[0].message == "import cycle: a.vkg -> b.vkg -> c.vkg -> a.vkg"
    assert diagnostics[0].span.file == "c.vkg" and diagnostics[0].span.line == 1


def test_a_module_that_uses_itself_is_a_cycle(tmp: Path) -> None:
    a = _write(tmp / "a.vkg", "use a\n" + _body("Crate", 1))
    diagnostics, _ = check_files([str(a)])
    assert [(d.code, d.message) for d in diagnostics] == [("E502", "import cycle: a.vkg -> a.vkg")]


def test_a_diamond_of_imports_loads_the_shared_module_once(tmp: Path) -> None:
    _write(tmp / "shared.vkg", _body("Crate", 1))
    _write(tmp / "left.vkg", "use shared\n")
    _write(tmp / "right.vkg", 'use "shared.vkg"\n')  # same file by path: still the same module
    main = _write(tmp / "main.vkg", "use left\nuse right\n")
    program = compile_file(main)
    assert list(program.bodies) == ["Crate"]
    assert sorted(program.modules) == ["left.vkg", "main.vkg", "right.vkg", "shared.vkg"]


def test_one_namespace_a_duplicate_names_both_places(tmp: Path) -> None:
    _write(tmp / "one.vkg", _body("Crate", 1))
    _write(tmp / "two.vkg", "\n" + _body("Crate", 2))
    main = _write(tmp / "main.vkg", "use one\nuse two\n")
    with pytest.raises(CompileError) as caught:
        compile_file(main)
    [diag] = caught.value.diagnostics
    assert diag.code == "E302" and diag.message == "`Crate` is declared twice"
    assert str(diag.span) == "two.vkg:2:6"
    assert diag.notes == ("first declared at one.vkg:1:6",)


def test_names_of_every_imported_module_are_visible(tmp: Path) -> None:
    """Transitive imports share the namespace: main sees the body its import imported."""
    _write(tmp / "bodies.vkg", _body("Crate", 1))
    _write(tmp / "scene.vkg", "use bodies\nuse stdlib.robots.panda\n")
    main = _write(
        tmp / "main.vkg",
        "use scene\nscene s {\n    table size (1, 1) m at (0, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
        "    crate : Crate on table at (0.4, 0) m\n}\n",
    )
    assert compile_file(main).scenes["s"].bodies[0].type.name == "Crate"


def test_a_missing_module_lists_where_it_looked(tmp: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp / "extra").mkdir()
    monkeypatch.setenv("VKG_PATH", str(tmp / "extra"))
    main = _write(tmp / "main.vkg", "use parts.crate\n")
    [diag] = check_files([str(main)])[0]
    assert diag.code == "E501"
    assert diag.message.startswith("cannot find module `parts.crate`; looked in: ./ (this file's directory), ")
    assert "extra/ (VKG_PATH)" in diag.message and "(the installed stdlib's parent)" in diag.message
