"""The language server under typing (issue 25, item 5): memory per keystroke and hover latency after a burst.

Run on demand: `PYTHONPATH=$PWD python bench/lang/bench_lsp.py`. Starts `vkgc lsp`
over stdio (tests/editor/lsp_client.py) and measures:

- memory: a 48 KB document edited 80 times, each edit waited for (its
  diagnostics published, so every edit is checked: no coalescing helps); the
  server's resident memory before and after (the parse cache was keyed by whole
  texts: 197 to 769 MB before);
- latency: 20 keystrokes sent at once to a 239 KB document, then a hover; the
  time until the hover's answer (34 s before: every keystroke was checked first).
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tests" / "editor"))

from lsp_client import LspClient  # noqa: E402
from lsp_fuzz import server_rss_mb  # noqa: E402


def bodies(count: int) -> str:
    """`count` bodies of about 60 bytes each."""
    return "".join(f"body B{i} {{\n    shape box (1, 2, 3) cm\n    mass 1 kg\n}}\n" for i in range(count))


def start(folder: Path) -> LspClient:
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    client = LspClient([sys.executable, "-m", "vkgl.cli", "lsp"], folder, env, open(folder / "log", "wb"))  # noqa: SIM115
    client.request("initialize", {"processId": os.getpid(), "rootUri": folder.as_uri(), "capabilities": {}})
    client.notify("initialized", {})
    return client


def change(client: LspClient, uri: str, version: int, text: str) -> None:
    params = {"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]}
    client.notify("textDocument/didChange", params)


def published(client: LspClient, uri: str) -> None:
    client.wait_for("textDocument/publishDiagnostics", lambda p: p["uri"] == uri, timeout=300)
    client.seen.clear()


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        client = start(folder)
        pid = client.proc.pid
        uri = (folder / "typing.vkg").as_uri()
        text = bodies(48_000 // 60)
        document = {"uri": uri, "languageId": "vkg", "version": 1, "text": text}
        client.notify("textDocument/didOpen", {"textDocument": document})
        published(client, uri)
        before = server_rss_mb(pid)
        start_time = time.perf_counter()
        halfway = 0.0
        for version in range(2, 82):
            text = text + "#"
            change(client, uri, version, text)
            published(client, uri)
            if version == 41:
                halfway = server_rss_mb(pid)
        after = server_rss_mb(pid)
        typing_seconds = time.perf_counter() - start_time

        big_uri = (folder / "big.vkg").as_uri()
        big = bodies(239_000 // 60)
        document = {"uri": big_uri, "languageId": "vkg", "version": 1, "text": big}
        client.notify("textDocument/didOpen", {"textDocument": document})
        published(client, big_uri)
        started = time.perf_counter()
        for version in range(2, 22):
            big = big + "#"
            change(client, big_uri, version, big)
        hover = client.request(
            "textDocument/hover",
            {"textDocument": {"uri": big_uri}, "position": {"line": 1, "character": 22}},
            timeout=300,
        )
        latency = time.perf_counter() - started
        published(client, big_uri)
        checked = time.perf_counter() - started
        client.request("shutdown", None, timeout=120)
        client.notify("exit", None)
        client.proc.wait(timeout=120)  # a loaded machine may take a while to free the analyses
    print("| measurement | value |")
    print("|---|---|")
    print(f"| server memory, 48 KB document, before 80 checked edits | {before:.0f} MB |")
    print(f"| server memory after 40 of them | {halfway:.0f} MB |")
    print(f"| server memory after 80 (the parse cache is full: it holds 512 K characters) | {after:.0f} MB |")
    print(f"| 80 checked edits of the 48 KB document | {typing_seconds:.1f} s |")
    print(f"| hover after 20 keystrokes at once on a 239 KB document | {latency:.2f} s |")
    print(f"| ... and its diagnostics (one check of the last text) | {checked:.2f} s |")
    assert hover is not None


if __name__ == "__main__":
    main()
