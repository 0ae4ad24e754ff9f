"""The import contracts of pyproject.toml, read again over every import: function-local and type-checking ones too.

import-linter (tests/test_tooling.py) sees only module-level imports, so a lower layer could still reach up
through an import inside a function. This test walks every module's syntax tree and applies the same contracts
to every `import` it finds, wherever it is written.
"""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "vkgl"


def _contracts() -> list[dict[str, object]]:
    config = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    return list(config["tool"]["importlinter"]["contracts"])


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(REPO).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def all_imports(path: Path) -> list[tuple[int, str]]:
    """Every module `path` imports, wherever the import statement is (line, dotted name)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.append((node.lineno, node.module))
            found += [(node.lineno, f"{node.module}.{alias.name}") for alias in node.names]
    return found


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _within(name: str, package: str) -> bool:
    return name == package or name.startswith(package + ".")


def _layer_of(name: str, layers: list[list[str]]) -> tuple[int, str] | None:
    for index, members in enumerate(layers):
        for member in members:
            if _within(name, member):
                return index, member
    return None


def layer_violations(layers: list[list[str]], scope: str | None = None) -> list[str]:
    """Imports from a layer to a layer above it, or between two independent members of one layer."""
    found = []
    for importer, path in MODULES.items():
        if scope is not None and not _within(importer, scope):
            continue
        mine = _layer_of(importer, layers)
        if mine is None:
            continue
        for line, imported in all_imports(path):
            if imported not in MODULES:
                continue
            theirs = _layer_of(imported, layers)
            if theirs is None or theirs[1] == mine[1]:
                continue
            if theirs[0] <= mine[0]:
                found.append(f"{path.relative_to(REPO)}:{line}: {importer} imports {imported}")
    return found


def _layers(contract: dict[str, object]) -> list[list[str]]:
    containers = contract.get("containers") or [""]
    assert isinstance(containers, list)
    layers = contract["layers"]
    assert isinstance(layers, list)
    out = []
    for layer in layers:
        members = [m.strip() for m in str(layer).split("|")]
        out.append([f"{c}.{m}" if c else m for c in containers for m in members])
    return out


@pytest.mark.parametrize("contract", _contracts(), ids=lambda c: str(c["name"])[:60])
def test_every_import_keeps_the_contract(contract: dict[str, object]) -> None:
    if contract["type"] == "layers":
        found = layer_violations(_layers(contract))
    else:
        sources = contract["source_modules"]
        forbidden = contract["forbidden_modules"]
        assert isinstance(sources, list) and isinstance(forbidden, list)
        found = [
            f"{path.relative_to(REPO)}:{line}: {importer} imports {imported}"
            for importer, path in MODULES.items()
            if any(_within(importer, s) for s in sources)
            for line, imported in all_imports(path)
            if any(_within(imported, f) for f in forbidden)
        ]
    assert not found, "\n".join(found)


def test_the_walk_sees_an_import_inside_a_function(tmp_path: Path) -> None:
    """The check must catch what import-linter cannot: an import written inside a function body."""
    module = tmp_path / "m.py"
    module.write_text("def f():\n    from vkgl.plan.solve import solve\n    return solve\n", encoding="utf-8")
    assert (2, "vkgl.plan.solve") in all_imports(module)


def crowded_folders(root: Path) -> dict[str, int]:
    """The folders under `root` holding more than a dozen modules (`__init__.py` not counted)."""
    return {
        str(folder.relative_to(root.parent)): n
        for folder in sorted({p.parent for p in root.rglob("*.py")})
        if (n := len([p for p in folder.glob("*.py") if p.name != "__init__.py"])) > 12
    }


@pytest.mark.parametrize("root", ["vkgl", "bench", "tests"])
def test_no_folder_holds_more_than_a_dozen_modules(root: str) -> None:
    crowded = crowded_folders(REPO / root)
    assert not crowded, f"give these folders rooms: {crowded}"


def test_the_crowding_check_sees_a_crowded_folder(tmp_path: Path) -> None:
    for i in range(13):
        (tmp_path / "pkg" / f"m{i}.py").parent.mkdir(exist_ok=True)
        (tmp_path / "pkg" / f"m{i}.py").write_text("")
    assert crowded_folders(tmp_path / "pkg") == {"pkg": 13}


# Folders of tests that are not a package's mirror: shared helpers, golden cases, the benches' own tests, and whole
# tasks solved and carried out in DART (scenarios: the pipeline end to end, no one package's).
NOT_MIRRORS = {"support", "golden", "lib", "bench", "learned", "scenarios", "__pycache__"}


def mirror_folders_without_package(tests: Path, package: Path) -> list[str]:
    """The test folders under `tests` with no package folder of the same path under `package`."""
    return [
        str(folder.relative_to(tests))
        for folder in sorted(p for p in tests.rglob("*") if p.is_dir())
        if not NOT_MIRRORS & set(folder.relative_to(tests).parts) and not (package / folder.relative_to(tests)).is_dir()
    ]


def test_every_test_folder_mirrors_a_package_folder() -> None:
    """Tests mirror the package: tests/plan/search/ tests vkgl/plan/search/, so a reader finds them by name."""
    strays = mirror_folders_without_package(REPO / "tests", PACKAGE)
    assert not strays, f"these test folders name no package folder: {strays}"


def test_the_mirror_check_sees_a_stray_folder(tmp_path: Path) -> None:
    (tmp_path / "tests" / "plan" / "nowhere").mkdir(parents=True)
    (tmp_path / "pkg" / "plan").mkdir(parents=True)
    assert mirror_folders_without_package(tmp_path / "tests", tmp_path / "pkg") == ["plan/nowhere"]
