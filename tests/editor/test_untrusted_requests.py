"""The language server under untrusted requests (issue 25): only open documents are read, every request answered.

A request about a document that is not open is answered with null and reads
nothing (a FIFO would hang it, `/dev/zero` would fill memory, a traceback would
reveal whether a path exists). A request pygls cannot decode (a position with
`line: -1`) gets a JSON-RPC error instead of no answer. Documents are keyed as
pygls keys them, so percent-encoded, non-ASCII, Windows and `untitled:` URIs get
their diagnostics; a buffer over the CLI's 10 MiB cap is refused with E507; a
burst of edits is checked once.
"""

from __future__ import annotations

import os
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from lsp_client import LspClient

REPO = Path(__file__).resolve().parents[2]
CRATE = "body Crate {\n    shape box (30, 30, 20) cm\n    mass 2 kg\n}\n"
BROKEN = CRATE.replace("mass 2 kg", "mass 2 m")  # E201: a mass expected
SHEET = 'body Sheet {\n    shape mesh "sheet.stl"\n    mass 0.2 kg\n}\n'
FLAT_SCENE = (
    'use stdlib.robots.panda\nuse "sheet.vkg"\n\nscene flat {\n    table size (1, 1) m at (0, 0, 0) m\n'
    "    robot arm : Panda at (-0.5, 0, 0) m\n    sheet : Sheet on table at (0.3, 0) m\n}\n"
)
REQUESTS = ("textDocument/hover", "textDocument/definition", "textDocument/completion")


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("untrusted")
    (root / "on_disk.vkg").write_text(CRATE, encoding="utf-8")
    os.mkfifo(root / "pipe.vkg")
    shutil.copy(REPO / "tests" / "lang" / "golden" / "lib" / "one_triangle.stl", root / "sheet.stl")
    (root / "sheet.vkg").write_text(SHEET, encoding="utf-8")
    return root


@pytest.fixture(scope="module")
def server(project: Path) -> Iterator[LspClient]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
    with open(project / "server.log", "wb") as log:
        client = LspClient([sys.executable, "-m", "vkgl.cli", "lsp"], project, env, log)
        client.request("initialize", {"processId": os.getpid(), "rootUri": project.as_uri(), "capabilities": {}})
        client.notify("initialized", {})
        yield client
        assert client.close() == 0


def open_text(server: LspClient, uri: str, text: str) -> list[dict[str, Any]]:
    """didOpen `uri` with `text`; the diagnostics published under exactly that URI."""
    document = {"uri": uri, "languageId": "vkg", "version": 1, "text": text}
    server.notify("textDocument/didOpen", {"textDocument": document})
    return server.wait_for("textDocument/publishDiagnostics", lambda p: p["uri"] == uri)["diagnostics"]


def ask(server: LspClient, method: str, uri: str, line: int = 1, character: int = 12) -> Any:
    params = {"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}
    return server.request(method, params, timeout=20)


@pytest.mark.parametrize("name", ["on_disk.vkg", "missing.vkg", "pipe.vkg", "/dev/zero"])
def test_requests_about_documents_not_open_are_null_and_read_nothing(
    server: LspClient, project: Path, name: str
) -> None:
    uri = Path(name).as_uri() if name.startswith("/") else (project / name).as_uri()
    for method in REQUESTS:
        assert ask(server, method, uri) is None, method
    formatting = {"textDocument": {"uri": uri}, "options": {"tabSize": 4, "insertSpaces": True}}
    assert server.request("textDocument/formatting", formatting, timeout=20) is None


@pytest.mark.parametrize(("line", "character"), [(-1, 0), (0, -1), (2**40, 0)])
def test_a_request_with_an_invalid_position_is_answered_with_an_error(
    server: LspClient, project: Path, line: int, character: int
) -> None:
    uri = (project / "positions.vkg").as_uri()
    open_text(server, uri, CRATE)
    with pytest.raises(RuntimeError, match="-32602"):
        ask(server, "textDocument/hover", uri, line, character)
    assert ask(server, "textDocument/hover", uri, 1, 24)["contents"]["value"].startswith("`(30, 30, 20) cm`")


def test_a_position_past_the_end_is_null(server: LspClient, project: Path) -> None:
    uri = (project / "past_end.vkg").as_uri()
    open_text(server, uri, CRATE)
    assert ask(server, "textDocument/hover", uri, 400, 3) is None
    assert ask(server, "textDocument/definition", uri, 2, 4000) is None


@pytest.mark.parametrize(
    "uri",
    [
        "file:///tmp/my%20tasks/t.vkg",
        "file:///tmp/caf%C3%A9/t%C3%A2che.vkg",
        "file:///c%3A/Users/me/t.vkg",
        "file:///C:/Users/me/t.vkg",
        "untitled:Untitled-1",
    ],
)
def test_every_kind_of_uri_gets_its_diagnostics(server: LspClient, uri: str) -> None:
    published = open_text(server, uri, BROKEN)
    assert [d["code"] for d in published] == ["E201"]
    assert ask(server, "textDocument/hover", uri, 1, 24)["contents"]["value"].startswith("`(30, 30, 20) cm`")
    server.notify("textDocument/didClose", {"textDocument": {"uri": uri}})
    assert server.wait_for("textDocument/publishDiagnostics", lambda p: p["uri"] == uri)["diagnostics"] == []


def test_a_buffer_over_the_source_limit_is_refused_with_e507(server: LspClient, project: Path) -> None:
    from vkgl.lang.syntax.sources import MAX_SOURCE_BYTES

    uri = (project / "huge.vkg").as_uri()
    published = open_text(server, uri, "#" * (MAX_SOURCE_BYTES + 1))
    assert [d["code"] for d in published] == ["E507"]
    assert "10 MiB" in published[0]["message"]
    for method in REQUESTS:  # answered at once with null, not after pygls walks 10 MiB of text
        assert ask(server, method, uri, 0, 5) is None
    server.notify("textDocument/didClose", {"textDocument": {"uri": uri}})


def test_a_burst_of_edits_is_checked_once(server: LspClient, project: Path) -> None:
    uri = (project / "typing.vkg").as_uri()
    assert open_text(server, uri, CRATE) == []
    for version in range(2, 22):
        text = BROKEN if version == 21 else CRATE.replace("2 kg", f"{version} kg")
        change = {"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]}
        server.notify("textDocument/didChange", change)
    final = server.wait_for("textDocument/publishDiagnostics", lambda p: p["uri"] == uri and p["diagnostics"] != [])
    assert [d["code"] for d in final["diagnostics"]] == ["E201"]
    checked_between = [m for m in server.seen if m["params"].get("uri") == uri]
    assert len(checked_between) <= 5  # not one check per keystroke (20 before); a stalled machine may split it


def test_a_flat_mesh_is_published_as_e503_in_the_module_that_names_it(server: LspClient, project: Path) -> None:
    scene = (project / "flat_scene.vkg").as_uri()
    assert open_text(server, scene, FLAT_SCENE) == []
    sheet = (project / "sheet.vkg").as_uri()
    published = server.wait_for("textDocument/publishDiagnostics", lambda p: p["uri"] == sheet)
    assert [d["code"] for d in published["diagnostics"]] == ["E503"]
