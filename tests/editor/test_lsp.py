"""A real LSP round trip: `python -m vkgl.cli lsp` in a subprocess, spoken to over stdio with JSON-RPC.

One server serves the whole module (it starts in about a second). The project
is a copy of the tabletop scene and a task beside it, in a temporary folder.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from lsp_client import LspClient

REPO = Path(__file__).resolve().parents[2]
TASK = (REPO / "examples" / "tasks" / "a_push.vkg").read_text(encoding="utf-8")
BAD = TASK.replace("within 1 cm, 3deg", "within 1 deg, 3deg")  # E201: a length expected
UGLY = "body   Crate{shape box (30,30,20) cm\nmass 2 kg   # heavy\n}\n"


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("lsp")
    (root / "scenes").mkdir()
    (root / "tasks").mkdir()
    shutil.copy(REPO / "examples" / "scenes" / "tabletop.vkg", root / "scenes" / "tabletop.vkg")
    (root / "tasks" / "bad.vkg").write_text(BAD, encoding="utf-8")
    (root / "crate.vkg").write_text(UGLY, encoding="utf-8")
    return root


@pytest.fixture(scope="module")
def server(project: Path) -> Iterator[LspClient]:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    with open(project / "server.log", "wb") as log:
        client = LspClient([sys.executable, "-m", "vkgl.cli", "lsp"], project, env, log)
        result = client.request(
            "initialize",
            {"processId": os.getpid(), "rootUri": project.as_uri(), "capabilities": {}},
        )
        client.capabilities = result["capabilities"]  # type: ignore[attr-defined]
        client.notify("initialized", {})
        yield client
        assert client.close() == 0


def uri(project: Path, name: str) -> str:
    return (project / name).resolve().as_uri()


def open_file(server: LspClient, project: Path, name: str, text: str | None = None) -> list[dict[str, Any]]:
    """didOpen `name` (with `text`, default its content on disk); the diagnostics published for it."""
    path = project / name
    text = path.read_text(encoding="utf-8") if text is None else text
    server.notify(
        "textDocument/didOpen",
        {
            "textDocument": {
                "uri": uri(project, name),
                "languageId": "vkg",
                "version": 1,
                "text": text,
            }
        },
    )
    return diagnostics_of(server, project, name)


def diagnostics_of(server: LspClient, project: Path, name: str) -> list[dict[str, Any]]:
    params = server.wait_for("textDocument/publishDiagnostics", lambda p: p["uri"] == uri(project, name))
    return params["diagnostics"]


def at(server: LspClient, method: str, project: Path, name: str, line: int, character: int) -> Any:
    return server.request(
        method,
        {
            "textDocument": {"uri": uri(project, name)},
            "position": {"line": line, "character": character},
        },
    )


def vkgc(project: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    return subprocess.run(
        [sys.executable, "-m", "vkgl.cli", *args],
        check=False,
        cwd=project,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )


def test_the_server_announces_its_features(server: LspClient) -> None:
    capabilities = server.capabilities  # type: ignore[attr-defined]
    for feature in (
        "hoverProvider",
        "definitionProvider",
        "completionProvider",
        "documentFormattingProvider",
    ):
        assert capabilities.get(feature), feature


def test_did_open_publishes_exactly_vkgc_checks_diagnostics(server: LspClient, project: Path) -> None:
    published = open_file(server, project, "tasks/bad.vkg")
    checked = vkgc(project, "check", "tasks/bad.vkg")
    expected = re.findall(
        r"^tasks/bad\.vkg:(\d+):(\d+): (error|warning)\[(\w+)\]: (.*)$",
        checked.stdout,
        re.MULTILINE,
    )
    assert checked.returncode == 1 and len(expected) == 1
    got = [
        (
            str(d["range"]["start"]["line"] + 1),
            str(d["range"]["start"]["character"] + 1),
            "error" if d["severity"] == 1 else "warning",
            d["code"],
            d["message"].split("\n")[0],
        )
        for d in published
    ]
    assert got == expected
    assert expected[0][3] == "E201" and published[0]["source"] == "vkgc"
    assert published[0]["range"]["end"] == {
        "line": 13,
        "character": 50,
    }  # under `1 deg`


def test_a_change_is_checked_without_saving(server: LspClient, project: Path) -> None:
    name = "tasks/bad.vkg"
    change = {
        "textDocument": {"uri": uri(project, name), "version": 2},
        "contentChanges": [{"text": TASK}],
    }
    server.notify("textDocument/didChange", change)
    assert diagnostics_of(server, project, name) == []
    broken = {
        "textDocument": {"uri": uri(project, name), "version": 3},
        "contentChanges": [{"text": BAD}],
    }
    server.notify("textDocument/didChange", broken)
    assert [d["code"] for d in diagnostics_of(server, project, name)] == ["E201"]
    assert (project / name).read_text(encoding="utf-8") == BAD  # the file itself was never touched


def test_hover_shows_a_bodys_shape_mass_and_frames(server: LspClient, project: Path) -> None:
    open_file(server, project, "scenes/tabletop.vkg")
    line = (
        (project / "scenes/tabletop.vkg")
        .read_text()
        .split("\n")
        .index("    block : Block on table at (0.45, 0) m yaw 0deg")
    )
    text = at(server, "textDocument/hover", project, "scenes/tabletop.vkg", line, 13)["contents"]["value"]
    assert (
        "**body** `Block`" in text
        and "box (10, 20, 5) cm" in text
        and "0.5 kg" in text
        and "com = (0, 0, 0) cm" in text
    )


def test_hover_shows_a_quantitys_si_value(server: LspClient, project: Path) -> None:
    hover = at(server, "textDocument/hover", project, "tasks/bad.vkg", 13, 46)  # on `within 1 deg`'s 1
    assert hover["contents"]["value"] == "`1 deg` = 0.0174533 rad (angle)"
    assert hover["range"]["start"] == {"line": 13, "character": 45}


def test_hover_shows_an_affordances_motion_action_and_evidence(
    server: LspClient,
) -> None:
    path = REPO / "stdlib" / "affordances" / "block.vkg"
    text = path.read_text(encoding="utf-8")
    server.notify(
        "textDocument/didOpen",
        {
            "textDocument": {
                "uri": path.as_uri(),
                "languageId": "vkg",
                "version": 1,
                "text": text,
            }
        },
    )
    line = text.split("\n").index("    affordance push_center_px {")
    hover = server.request(
        "textDocument/hover",
        {
            "textDocument": {"uri": path.as_uri()},
            "position": {"line": line, "character": 20},
        },
    )
    value = hover["contents"]["value"]
    assert "`Block.push_center_px`" in value and "motion `prismatic along (1, 0, 0)" in value
    assert "action `fixed at (-5, 0, 0) cm" in value and re.search(r"evidence: \d+ trials", value)


def test_definition_across_use(server: LspClient, project: Path) -> None:
    scene = (project / "scenes/tabletop.vkg").resolve().as_uri()
    found = at(server, "textDocument/definition", project, "tasks/bad.vkg", 12, 12)  # `scene tabletop`
    assert found["uri"] == scene and found["range"]["start"] == {
        "line": 12,
        "character": 6,
    }
    found = at(server, "textDocument/definition", project, "tasks/bad.vkg", 13, 10)  # `goal block`
    assert found["uri"] == scene and found["range"]["start"] == {
        "line": 15,
        "character": 4,
    }
    found = at(server, "textDocument/definition", project, "scenes/tabletop.vkg", 15, 13)  # `block : Block`
    assert found["uri"] == (REPO / "stdlib/bodies/block.vkg").as_uri()
    body_line = (REPO / "stdlib/bodies/block.vkg").read_text(encoding="utf-8").split("\n").index("body Block {")
    assert found["range"]["start"] == {"line": body_line, "character": 5}
    found = at(server, "textDocument/definition", project, "tasks/bad.vkg", 6, 25)  # `use stdlib.affordances.block`
    assert found["uri"] == (REPO / "stdlib/affordances/block.vkg").as_uri()


def test_definition_of_a_tool_frame(server: LspClient) -> None:
    path = REPO / "stdlib" / "tools.vkg"
    text = path.read_text(encoding="utf-8")
    server.notify(
        "textDocument/didOpen",
        {
            "textDocument": {
                "uri": path.as_uri(),
                "languageId": "vkg",
                "version": 1,
                "text": text,
            }
        },
    )
    line = text.split("\n").index("    Stick.tip ~ fingertip")
    found = server.request(
        "textDocument/definition",
        {
            "textDocument": {"uri": path.as_uri()},
            "position": {"line": line, "character": 11},
        },
    )
    stick = REPO / "stdlib/bodies/stick.vkg"
    assert found["uri"] == stick.as_uri()
    tip_line = stick.read_text().split("\n")[found["range"]["start"]["line"]]
    assert tip_line.startswith("    frame tip =") and found["range"]["start"]["character"] == 10


def test_completion_offers_keywords_units_bodies_scene_bodies_and_affordances(server: LspClient, project: Path) -> None:
    result = at(server, "textDocument/completion", project, "tasks/bad.vkg", 13, 9)  # after `goal `
    labels = {item["label"] for item in result["items"]}
    assert {
        "goal",
        "within",
        "cm",
        "deg",
        "Block",
        "Stick",
        "block",
        "stick",
        "tabletop",
        "push_center_px",
    } <= labels
    result = at(server, "textDocument/completion", project, "tasks/bad.vkg", 13, 47)  # after `within 1 d`
    assert {item["label"] for item in result["items"]} == {
        "m",
        "cm",
        "mm",
        "deg",
        "rad",
        "kg",
        "g",
        "N",
        "s",
        "ms",
        "N*s/m",
        "N*m*s/rad",
        "N*m",
    }


def test_formatting_is_vkgc_fmt(server: LspClient, project: Path) -> None:
    open_file(server, project, "crate.vkg")
    edits = server.request(
        "textDocument/formatting",
        {
            "textDocument": {"uri": uri(project, "crate.vkg")},
            "options": {"tabSize": 4, "insertSpaces": True},
        },
    )
    assert vkgc(project, "fmt", "crate.vkg").returncode == 0
    formatted = (project / "crate.vkg").read_text(encoding="utf-8")
    assert formatted != UGLY
    assert len(edits) == 1 and edits[0]["newText"] == formatted
    assert edits[0]["range"] == {
        "start": {"line": 0, "character": 0},
        "end": {"line": 3, "character": 0},
    }
