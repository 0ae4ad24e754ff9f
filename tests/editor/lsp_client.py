"""A small JSON-RPC client that speaks LSP to a server subprocess over stdio (for the round-trip tests)."""

from __future__ import annotations

import json
import queue
import subprocess
import threading
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

Message = dict[str, Any]


class LspClient:
    """Starts `command`, frames messages with Content-Length, answers server requests with null."""

    def __init__(self, command: list[str], cwd: Path, env: dict[str, str], log: IO[bytes]) -> None:
        self.proc = subprocess.Popen(
            command,
            cwd=cwd,
            env=env,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=log,
        )
        self.inbox: queue.Queue[Message | None] = queue.Queue()
        self.seen: list[Message] = []  # notifications received so far, in order
        self.next_id = 0
        threading.Thread(target=self._read_loop, daemon=True).start()

    def _read_loop(self) -> None:
        stream = self.proc.stdout
        assert stream is not None
        while True:
            length = None
            while True:
                line = stream.readline()
                if not line:
                    self.inbox.put(None)
                    return
                if line in (b"\r\n", b"\n"):
                    break
                name, _, value = line.decode("ascii").partition(":")
                if name.strip().lower() == "content-length":
                    length = int(value.strip())
            assert length is not None, "a message without Content-Length"
            self.inbox.put(json.loads(stream.read(length)))

    def _send(self, message: Message) -> None:
        body = json.dumps({"jsonrpc": "2.0", **message}).encode("utf-8")
        assert self.proc.stdin is not None
        self.proc.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.proc.stdin.flush()

    def _next(self, timeout: float) -> Message:
        message = self.inbox.get(timeout=timeout)
        if message is None:
            raise ConnectionError(f"the server exited (code {self.proc.poll()})")
        if "method" in message and "id" in message:  # a request from the server
            self._send({"id": message["id"], "result": None})
        elif "method" in message:
            self.seen.append(message)
        return message

    def notify(self, method: str, params: Any) -> None:
        """Send a notification."""
        self._send({"method": method, "params": params})

    def request(self, method: str, params: Any, timeout: float = 30.0) -> Any:
        """Send a request and return its result (raise on an error response)."""
        self.next_id += 1
        ident = self.next_id
        self._send({"id": ident, "method": method, "params": params})
        while True:
            message = self._next(timeout)
            if message.get("id") == ident and "method" not in message:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result")

    def wait_for(self, method: str, match: Callable[[Any], bool], timeout: float = 30.0) -> Any:
        """The params of the first notification `method` (already seen or coming) that `match`es."""
        for message in self.seen:
            if message["method"] == method and match(message["params"]):
                self.seen.remove(message)
                return message["params"]
        while True:
            message = self._next(timeout)
            if message.get("method") == method and match(message["params"]):
                self.seen.remove(message)
                return message["params"]

    def close(self) -> int:
        """shutdown + exit; the server's exit code."""
        try:
            self.request("shutdown", None, timeout=10)
            self.notify("exit", None)
            return self.proc.wait(timeout=10)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()
