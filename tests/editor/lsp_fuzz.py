"""A fuzz run of `vkgc lsp` over stdio: random edits, positions and URIs; no crash, no hang, memory bounded.

Run on demand (the test suite runs a few hundred messages, test_lsp_fuzz.py):

    PYTHONPATH=$PWD python tests/editor/lsp_fuzz.py --messages 10000 --seed 1

It starts `python -m vkgl.cli lsp` in a temporary project (a copy of the
tabletop scene and a task using it, a body file, a FIFO) and sends `--messages`
messages drawn from a seeded generator: didOpen / didChange / didSave /
didClose of documents under random URIs (the project's files, percent-encoded,
non-ASCII, Windows and `untitled:` ones, files that are not open, `/dev/zero`,
the FIFO, other schemes, a 10 MiB+ buffer now and then), whole-text and
incremental edits (random ranges, also past the end or negative), and hover,
definition, completion and formatting requests at random positions (valid,
past the end, negative, huge, not numbers), plus requests of unknown methods.

It asserts: every request is answered within `--reply-bound` seconds with a
result or with InvalidParams (-32602) / MethodNotFound (-32601), never another
error; the server never shows an error message; its resident memory (sampled
every 50 messages) stays under `--memory-bound` MB; at the end it still checks
a fresh file and exits 0 on shutdown/exit.
"""

from __future__ import annotations

import argparse
import json
import os
import queue
import random
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lsp_client import LspClient  # beside this file: on sys.path when run as a script and under pytest

REPO = Path(__file__).resolve().parents[2]
ALLOWED_ERRORS = {-32602, -32601}  # InvalidParams (a request pygls cannot decode), MethodNotFound
SNIPPETS = [
    "body",
    "scene",
    "task",
    "use",
    "goal",
    "within",
    "open",
    "on table at",
    "at",
    "shape box",
    "mass",
    "joint prismatic axis",
    "limits",
    "cm",
    "deg",
    "m",
    "kg",
    "N*s/m",
    "(",
    ")",
    "{",
    "}",
    ",",
    ":",
    ".",
    "1e-300",
    "1e308",
    "nan",
    "-0",
    "99999999999999999999",
    '"',
    "#",
    "\n",
    "\r\n",
    "\t",
    " ",
    "é",
    "😋",
    "\u2028",
    "\x00",
    "\x1b[31m",
    'use "/etc/passwd"',
    'use "/dev/zero.vkg"',
    "use stdlib.bodies.block",
    'shape mesh "nowhere.stl"',
    "Block",
    "block",
    "tabletop",
    "Stick.tip",
    "~ fingertip",
]
METHODS = ["textDocument/hover", "textDocument/definition", "textDocument/completion"]


@dataclass
class Report:
    """What a run saw."""

    messages: int = 0
    requests: int = 0
    answered_with_error: dict[int, int] = field(default_factory=dict)
    slowest_reply: float = 0.0
    peak_rss_mb: float = 0.0
    seconds: float = 0.0
    failures: list[str] = field(default_factory=list)

    def table(self) -> str:
        """A Markdown table of the run."""
        errors = ", ".join(f"{code}: {n}" for code, n in sorted(self.answered_with_error.items())) or "none"
        rows = [
            ("messages sent", f"{self.messages:,}"),
            ("requests (each answered)", f"{self.requests:,}"),
            ("answered with an error", errors),
            ("slowest reply", f"{self.slowest_reply:.2f} s"),
            ("peak server memory (RSS)", f"{self.peak_rss_mb:.0f} MB"),
            ("wall time", f"{self.seconds:.0f} s"),
            ("failures", str(len(self.failures))),
        ]
        return "\n".join(["| | |", "|---|---|", *(f"| {a} | {b} |" for a, b in rows)])


class Fuzzer:
    """Sends random messages to a server and checks each answer."""

    def __init__(self, client: LspClient, project: Path, seed: int, reply_bound: float, memory_bound: float) -> None:
        self.client = client
        self.project = project
        self.rng = random.Random(seed)
        self.reply_bound = reply_bound
        self.memory_bound = memory_bound
        self.report = Report()
        self.texts: dict[str, str] = {}  # what the fuzzer believes each open document holds
        self.versions: dict[str, int] = {}
        self.bases = [
            (REPO / "examples" / "tasks" / "a_push.vkg").read_text(encoding="utf-8"),
            (REPO / "examples" / "scenes" / "tabletop.vkg").read_text(encoding="utf-8"),
            (REPO / "stdlib" / "bodies" / "drawer.vkg").read_text(encoding="utf-8"),
            "body Crate {\n    shape box (30, 30, 20) cm\n    mass 2 kg\n}\n",
        ]
        self.uris = self._uris()

    def _uris(self) -> list[str]:
        p = self.project
        return [
            (p / "tasks" / "t.vkg").as_uri(),
            (p / "scenes" / "tabletop.vkg").as_uri(),
            (p / "crate.vkg").as_uri(),
            (p / "my tasks" / "t.vkg").as_uri(),  # percent-encoded by as_uri
            (p / "my tasks" / "t.vkg").as_uri().replace("%20", " "),  # the same document, spelt raw
            (p / "café" / "tâche.vkg").as_uri(),
            "file:///c%3A/Users/me/t.vkg",
            "file:///C:/Users/me/t.vkg",
            "untitled:Untitled-1",
            "untitled:Untitled-2",
            (p / "unopened.vkg").as_uri(),
            (p / "pipe.vkg").as_uri(),
            "file:///dev/zero",
            "file:///etc/passwd",
            (p / "missing" / "nothing.vkg").as_uri(),
            "http://example.com/x.vkg",
            "file://host/share/x.vkg",
            "not a uri",
            "",
            "file:///" + "a" * 5000 + ".vkg",
        ]

    # ------------------------------------------------------------ generation

    def text(self) -> str:
        """A base text, mutated a few times (kept under about 40 KB)."""
        text = self.rng.choice(self.bases)
        for _ in range(self.rng.randint(0, 4)):
            text = self.mutate(text)
        return text[:40_000]

    def mutate(self, text: str) -> str:
        rng = self.rng
        at = rng.randint(0, len(text))
        kind = rng.random()
        if kind < 0.5:
            return text[:at] + rng.choice(SNIPPETS) + text[at:]
        if kind < 0.8:
            return text[:at] + text[at + rng.randint(1, 40) :]
        if kind < 0.95:
            return text[:at] + text[at : at + rng.randint(1, 200)] * rng.randint(1, 3) + text[at:]
        return "".join(chr(rng.randint(1, 0x2FFF)) for _ in range(rng.randint(1, 50)))

    def position(self) -> Any:
        rng = self.rng
        kind = rng.random()
        if kind < 0.7:
            return {"line": rng.randint(0, 60), "character": rng.randint(0, 90)}
        if kind < 0.8:
            return {"line": rng.randint(-3, 3), "character": rng.randint(-3, 3)}
        if kind < 0.9:
            return {"line": rng.choice([2**31 - 1, 2**40, 10**6]), "character": rng.choice([0, 2**31 - 1])}
        return rng.choice([{"line": "1", "character": 0}, {"line": 1.5, "character": None}, {}, None, []])

    def change(self, uri: str) -> dict[str, Any]:
        rng = self.rng
        if rng.random() < 0.5 or uri not in self.texts:
            text = self.mutate(self.texts.get(uri) or self.text())[:40_000]
            self.texts[uri] = text
            return {"text": text}
        start, end = self.position(), self.position()
        self.texts.pop(uri, None)  # the fuzzer no longer knows the exact text (pygls applies ranges its way)
        return {"range": {"start": start, "end": end}, "text": rng.choice(SNIPPETS)}

    # ------------------------------------------------------------ sending

    def step(self) -> None:
        rng = self.rng
        uri = rng.choice(self.uris)
        roll = rng.random()
        if roll < 0.12:
            text = "#" * (10 * 1024 * 1024 + 1) if rng.random() < 0.002 else self.text()
            self.texts[uri] = text
            self.versions[uri] = 1
            document = {"uri": uri, "languageId": "vkg", "version": 1, "text": text}
            self.notify("textDocument/didOpen", {"textDocument": document})
        elif roll < 0.45:
            self.versions[uri] = self.versions.get(uri, 1) + 1
            changes = [self.change(uri) for _ in range(rng.randint(1, 3))]
            identifier = {"uri": uri, "version": self.versions[uri]}
            self.notify("textDocument/didChange", {"textDocument": identifier, "contentChanges": changes})
        elif roll < 0.48:
            self.notify("textDocument/didSave", {"textDocument": {"uri": uri}})
        elif roll < 0.52:
            self.texts.pop(uri, None)
            self.notify("textDocument/didClose", {"textDocument": {"uri": uri}})
        elif roll < 0.92:
            params = {"textDocument": {"uri": uri}, "position": self.position()}
            self.request(rng.choice(METHODS), params)
        elif roll < 0.97:
            options = {"tabSize": 4, "insertSpaces": True}
            self.request("textDocument/formatting", {"textDocument": {"uri": uri}, "options": options})
        else:
            self.request(rng.choice(["vkg/nothing", "textDocument/hover", "$/x"]), rng.choice([None, {}, [1]]))

    def notify(self, method: str, params: Any) -> None:
        self.client.notify(method, params)
        self.report.messages += 1

    def request(self, method: str, params: Any) -> None:
        client = self.client
        client.next_id += 1
        ident = client.next_id
        client._send({"id": ident, "method": method, "params": params})
        self.report.messages += 1
        self.report.requests += 1
        start = time.monotonic()
        while True:
            left = self.reply_bound - (time.monotonic() - start)
            try:
                message = client._next(max(left, 0.0))
            except queue.Empty:
                raise AssertionError(
                    f"no reply to {method} {json.dumps(params)[:200]} in {self.reply_bound} s"
                ) from None
            if message.get("id") == ident and "method" not in message:
                break
            self.watch(message)
        self.report.slowest_reply = max(self.report.slowest_reply, time.monotonic() - start)
        error = message.get("error")
        if error is not None:
            code = int(error.get("code", 0))
            self.report.answered_with_error[code] = self.report.answered_with_error.get(code, 0) + 1
            if code not in ALLOWED_ERRORS:
                self.fail(f"{method} {json.dumps(params)[:200]} answered {json.dumps(error)[:400]}")

    def watch(self, message: dict[str, Any]) -> None:
        """A notification from the server: an error shown to the user is a failure."""
        if message.get("method") == "window/showMessage" and message["params"].get("type") == 1:
            self.fail(f"the server showed an error: {message['params'].get('message', '')[:400]}")
            self.dump_documents()
        self.client.seen.clear()  # published diagnostics are not kept

    def dump_documents(self) -> None:
        """Keep the texts the fuzzer knows beside the project (to reproduce a failure with `vkgc check`)."""
        folder = self.project.parent / f"failure-{len(self.report.failures)}"
        folder.mkdir(exist_ok=True)
        for n, (uri, text) in enumerate(sorted(self.texts.items())):
            (folder / f"{n}.vkg").write_text(f"# {uri}\n{text}", encoding="utf-8", errors="surrogatepass")

    def fail(self, what: str) -> None:
        self.report.failures.append(what)

    def sample_memory(self) -> None:
        rss = server_rss_mb(self.client.proc.pid)
        self.report.peak_rss_mb = max(self.report.peak_rss_mb, rss)
        if rss > self.memory_bound:
            raise AssertionError(f"the server holds {rss:.0f} MB, over the bound of {self.memory_bound:.0f} MB")

    def run(self, messages: int) -> Report:
        start = time.monotonic()
        while self.report.messages < messages:
            self.step()
            if self.report.messages % 50 == 0:
                self.sample_memory()
        self.sample_memory()
        self.still_works()
        self.report.seconds = time.monotonic() - start
        return self.report

    def still_works(self) -> None:
        """After the storm, a fresh file is still checked and hovered."""
        uri = (self.project / "after.vkg").as_uri()
        text = "body Crate {\n    shape box (30, 30, 20) cm\n    mass 2 m\n}\n"
        document = {"uri": uri, "languageId": "vkg", "version": 1, "text": text}
        self.client.notify("textDocument/didOpen", {"textDocument": document})
        published = self.client.wait_for(
            "textDocument/publishDiagnostics", lambda p: p["uri"] == uri, timeout=self.reply_bound
        )
        if [d["code"] for d in published["diagnostics"]] != ["E201"]:
            self.fail(f"a fresh file was not checked: {published}")


def server_rss_mb(pid: int) -> float:
    """The resident memory of process `pid` in MB (Linux /proc)."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def make_project(root: Path) -> Path:
    """A small project: the tabletop scene, a task using it, a body, a FIFO, folders with spaces and accents."""
    for folder in ("scenes", "tasks", "my tasks", "café"):
        (root / folder).mkdir(parents=True, exist_ok=True)
    shutil.copy(REPO / "examples" / "scenes" / "tabletop.vkg", root / "scenes" / "tabletop.vkg")
    shutil.copy(REPO / "examples" / "tasks" / "a_push.vkg", root / "tasks" / "t.vkg")
    (root / "crate.vkg").write_text("body Crate {\n    shape box (30, 30, 20) cm\n    mass 2 kg\n}\n")
    (root / "unopened.vkg").write_text("body Secret {\n    shape box (1, 1, 1) cm\n    mass 1 kg\n}\n")
    if not (root / "pipe.vkg").exists():
        os.mkfifo(root / "pipe.vkg")
    return root


def start_server(project: Path, log_path: Path) -> LspClient:
    """`python -m vkgl.cli lsp` in `project`, initialized."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
    log = open(log_path, "wb")  # noqa: SIM115 (closed with the process)
    client = LspClient([sys.executable, "-m", "vkgl.cli", "lsp"], project, env, log)
    client.request("initialize", {"processId": os.getpid(), "rootUri": project.as_uri(), "capabilities": {}})
    client.notify("initialized", {})
    return client


def fuzz(messages: int, seed: int, reply_bound: float, memory_bound: float, folder: Path) -> Report:
    """Run the fuzzer against a fresh server in `folder`; the report (its failures listed, not raised)."""
    project = make_project(folder / "project")
    client = start_server(project, folder / "server.log")
    try:
        report = Fuzzer(client, project, seed, reply_bound, memory_bound).run(messages)
        status = client.close()
    finally:
        if client.proc.poll() is None:
            client.proc.kill()
    if status != 0:
        report.failures.append(f"the server exited {status} on shutdown/exit")
    return report


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--messages", type=int, default=10_000, help="how many messages to send")
    parser.add_argument("--seed", type=int, default=1, help="the random generator's seed")
    parser.add_argument("--reply-bound", type=float, default=30.0, help="seconds a reply may take")
    parser.add_argument("--memory-bound", type=float, default=1000.0, help="MB the server may hold")
    parser.add_argument("--keep", type=Path, help="run in this folder and keep it (the server's log is server.log)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        report = fuzz(args.messages, args.seed, args.reply_bound, args.memory_bound, folder)
    print(report.table())
    for failure in report.failures[:20]:
        print("FAIL:", failure)
    return 1 if report.failures else 0


if __name__ == "__main__":
    sys.exit(main())
