"""The JSON-RPC protocol of `vkgc lsp`: pygls's, except that every malformed request gets an answer.

pygls turns each incoming message into lsprotocol types while it decodes the
JSON. When that fails (a position with `line: -1`, a string where a number
belongs, a missing field), it logs the error and drops the message, so the
client waits forever for the answer to its request. Here such a request is
answered with the JSON-RPC error pygls raised (InvalidParams, -32602), and a
malformed notification is dropped with a log line (it has no one to answer).

Likewise a change to a document that is not open (pygls raised KeyError and
showed the user "Error in server"), or one whose range pygls cannot apply, is
logged and dropped; the document is checked again all the same.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from lsprotocol import types
from lsprotocol.types import ResponseError
from pygls.exceptions import JsonRpcException
from pygls.protocol import LanguageServerProtocol
from pygls.protocol.language_server import lsp_method

from vkgl.editor.documents import document_key

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class _Dropped:
    """A message already dealt with while it was decoded (answered with an error, or a bad notification)."""

    jsonrpc: str
    method: str = ""


class VkgProtocol(LanguageServerProtocol):
    """pygls's language-server protocol; a request it cannot decode is answered with an error, never ignored."""

    def structure_message(self, data: dict[str, Any]) -> Any:
        """Decode one message; a malformed one is answered (requests) or logged (notifications) here."""
        try:
            return super().structure_message(data)
        except JsonRpcException as exc:
            if not isinstance(data, dict) or "jsonrpc" not in data:
                raise
            ident = data.get("id")
            if "method" in data and isinstance(ident, int | str) and not isinstance(ident, bool):
                self._send_response(ident, error=_response_error(exc))
            else:
                log.warning("dropped a malformed %s notification", data.get("method", "?"))
            return _Dropped(jsonrpc=self.VERSION, method=str(data.get("method", "")))

    def handle_message(self, message: Any) -> None:
        """Dispatch a decoded message; one already answered while decoding is not dispatched again."""
        if isinstance(message, _Dropped):
            return
        super().handle_message(message)

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams) -> Iterator[Any]:
        """Apply the changes to an open document (pygls's way), then call the server's handler; a change to a
        document that is not open is dropped, and one pygls cannot apply is logged."""
        if document_key(params.text_document.uri) not in self.workspace.text_documents:
            log.warning("dropped a change to a document that is not open")
            return
        try:
            for change in params.content_changes:
                self.workspace.update_text_document(params.text_document, change)
        except (IndexError, ValueError, TypeError) as exc:
            log.warning("could not apply a change: %s", exc)
        handler = self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)
        if handler is not None:
            yield handler, (params,), None


class _CountedUnits:
    """A pygls unit counter whose `num_units` encodes the string instead of walking it a character at a time
    (pygls's walk takes seconds on a line of megabytes, on every edit and request that touches it)."""

    def __init__(self, slow: Any, encoding: str, width: int) -> None:
        self._slow = slow
        self._encoding = encoding
        self._width = width

    def code_units_for_char(self, char: str) -> int:
        return int(self._slow.code_units_for_char(char))

    def num_units(self, chars: str) -> int:
        return len(chars.encode(self._encoding, "surrogatepass")) // self._width

    def column_from_utf32(self, line: str, column: int) -> int:
        return self.num_units(line[:column])

    def __getattr__(self, name: str) -> Any:
        return getattr(self._slow, name)


def count_units_fast(codec: Any) -> None:
    """Make `codec` (a pygls PositionCodec) count UTF-16 and UTF-8 units with the codecs (same numbers)."""
    encoding = codec.encoding or types.PositionEncodingKind.Utf16
    if encoding == types.PositionEncodingKind.Utf16 and not isinstance(codec.impl, _CountedUnits):
        codec.impl = _CountedUnits(codec.impl, "utf-16-le", 2)
    elif encoding == types.PositionEncodingKind.Utf8 and not isinstance(codec.impl, _CountedUnits):
        codec.impl = _CountedUnits(codec.impl, "utf-8", 1)


def _response_error(exc: JsonRpcException) -> ResponseError:
    cause = exc.__cause__
    detail = str(cause).splitlines()[0] if cause is not None and str(cause) else exc.message
    return ResponseError(code=exc.code, message=f"{exc.message}: {detail}" if detail != exc.message else detail)
