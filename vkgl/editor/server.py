"""`vkgc lsp`: the VKG language server (pygls, JSON-RPC over stdio).

Features:

- diagnostics on open, change and save: exactly `vkgc check`'s (same codes,
  positions, messages; notes appended), for the open file and the modules it
  uses; a change re-checks the open files that use the changed one;
- hover: a body's shape, mass and frames; an affordance's motion, action and
  evidence; a scene body, scene, task, robot, effector or frame; a quantity's
  SI value;
- go to definition across `use`: bodies, robots, scenes, tasks, affordances,
  frames, effectors, scene bodies, and the module of a `use` line;
- completion: keywords, units, body types, scene bodies, affordance names,
  and after `Body.` its frames and affordances;
- formatting: `vkgc fmt` of the buffer (nothing when it does not parse).

Untrusted input: only open documents are looked at (a request about any other
URI is answered with null; nothing is read from disk for it); documents are
keyed as pygls keys them (vkgl/editor/documents.py); a request pygls cannot
decode gets a JSON-RPC error (vkgl/editor/protocol.py); edits are checked once
they pause for SETTLE_SECONDS; a buffer over the 10 MiB source limit gets E507.

The editor extension in editors/vscode/ starts it; any LSP client can.
"""

from __future__ import annotations

import asyncio
import os
from pathlib import Path
from typing import Any

from lsprotocol import types
from pygls.exceptions import FeatureNotificationError
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path
from pygls.workspace import TextDocument

from vkgl.editor.analysis import Analysis, analyze, span_path
from vkgl.editor.completion import candidates
from vkgl.editor.documents import document_key, document_path
from vkgl.editor.hover import quantity_hover, symbol_hover
from vkgl.editor.protocol import VkgProtocol, count_units_fast
from vkgl.editor.symbols import declaration_span, symbol_at
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir.nodes import Span
from vkgl.lang.ir.program import Program
from vkgl.lang.syntax.printer import format_source
from vkgl.lang.syntax.sources import oversized_text

NAME = "vkgc-lsp"
VERSION = "0.1.0"

_KINDS = {
    "keyword": types.CompletionItemKind.Keyword,
    "unit": types.CompletionItemKind.Unit,
    "body": types.CompletionItemKind.Class,
    "robot": types.CompletionItemKind.Class,
    "scene": types.CompletionItemKind.Module,
    "instance": types.CompletionItemKind.Variable,
    "affordance": types.CompletionItemKind.Method,
    "frame": types.CompletionItemKind.Field,
    "region": types.CompletionItemKind.Constant,
}


SETTLE_SECONDS = 0.2
"""Edits are checked once they pause this long: a burst of keystrokes costs one check, not one each."""


class VkgLanguageServer(LanguageServer):
    """The server's state, keyed by document key: the last analysis of each open file, what was published where.

    Only open documents are ever looked at: a request about any other URI is
    answered with null, and nothing is read from disk for it.
    """

    def __init__(self) -> None:
        super().__init__(NAME, VERSION, protocol_cls=VkgProtocol)
        self.analyses: dict[str, Analysis] = {}
        self.programs: dict[str, Program] = {}  # the last program whose root parsed, per open file
        self.published: dict[str, dict[str, list[types.Diagnostic]]] = {}  # root key -> file uri -> diagnostics
        self.pending: set[str] = set()  # documents edited since their last check
        self._timer: asyncio.TimerHandle | None = None

    # ------------------------------------------------------------ documents

    def document(self, uri: str) -> TextDocument | None:
        """The open document `uri` (however the client spells it), or None: never a file read from disk."""
        return self.workspace.text_documents.get(document_key(uri))

    def answerable(self, uri: str) -> TextDocument | None:
        """The open document `uri` if requests about it are answered: not one over the source limit (E507)."""
        document = self.document(uri)
        if document is None or oversized_text(document.source, "buffer") is not None:
            return None
        return document

    def home(self) -> Path:
        """The folder untitled buffers are compiled in: the workspace's root, else the working directory."""
        root = self.workspace.root_path if self.workspace is not None else None
        return Path(root) if root and os.path.isabs(root) else Path.cwd()

    def open_documents(self) -> dict[Path, TextDocument]:
        """The open documents by the resolved path the compiler knows them by."""
        home = self.home()
        return {document_path(d.uri, home): d for d in list(self.workspace.text_documents.values())}

    def overlay(self, opened: dict[Path, TextDocument] | None = None) -> dict[Path, str]:
        """The open buffers by resolved path: what the compiler reads instead of the files."""
        opened = self.open_documents() if opened is None else opened
        return {path: document.source for path, document in opened.items()}

    # ------------------------------------------------------------ analysis

    def edited(self, uri: str) -> None:
        """A document changed: check it (and the files using it) once the edits pause."""
        self.pending.add(document_key(uri))
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # called outside the server's loop (tests): check now
            self.settle()
            return
        if self._timer is not None:
            self._timer.cancel()
        self._timer = loop.call_later(SETTLE_SECONDS, self.settle)

    def settle(self) -> None:
        """Check every document edited since its last check."""
        self._timer = None
        pending, self.pending = self.pending, set()
        for key in sorted(pending):
            try:
                self.refresh(key)
            except Exception as exc:  # outside a handler: report it as pygls reports a failed notification
                self.report_server_error(exc, FeatureNotificationError)

    def refresh(self, uri: str) -> None:
        """Re-check `uri`, then every other open file whose compilation includes it."""
        key = document_key(uri)
        self.pending.discard(key)
        document = self.document(key)
        if document is None:
            return
        changed = document_path(document.uri, self.home())
        self.check(key)
        for other, analysis in list(self.analyses.items()):
            if other != key and changed in analysis.files:
                self.check(other)

    def check(self, uri: str) -> None:
        """Compile one open file and publish its diagnostics."""
        key = document_key(uri)
        document = self.document(key)
        if document is None:
            return
        opened = self.open_documents()
        analysis = analyze(document_path(document.uri, self.home()), self.overlay(opened))
        self.analyses[key] = analysis
        if analysis.program.modules:
            self.programs[key] = analysis.program
        else:
            self.programs.pop(key, None)
        by_file = {
            self.uri_of(file, opened): [self.lsp_diagnostic(d, analysis) for d in found]
            for file, found in analysis.diagnostics_by_file().items()
        }
        self.publish(key, by_file)

    @staticmethod
    def uri_of(file: Path, opened: dict[Path, TextDocument]) -> str:
        """The URI diagnostics for `file` are published under: the client's own for an open document."""
        document = opened.get(file)
        if document is not None:
            return document.uri
        return from_fs_path(str(file)) or file.as_uri()

    def forget(self, uri: str) -> None:
        """A file was closed: drop its analysis and withdraw what it published."""
        key = document_key(uri)
        self.pending.discard(key)
        self.analyses.pop(key, None)
        self.programs.pop(key, None)
        if key in self.published:
            self.publish(key, {})

    def publish(self, root: str, by_file: dict[str, list[types.Diagnostic]]) -> None:
        """Publish the diagnostics of `root`'s compilation, merged with other open files' for shared modules."""
        before = self.published.get(root, {})
        self.published[root] = by_file
        if not by_file:
            del self.published[root]
        for target in set(before) | set(by_file):
            merged: dict[tuple[Any, ...], types.Diagnostic] = {}
            for published in self.published.values():
                for diag in published.get(target, []):
                    merged.setdefault(
                        (
                            diag.code,
                            diag.range.start.line,
                            diag.range.start.character,
                            diag.message,
                        ),
                        diag,
                    )
            self.text_document_publish_diagnostics(
                types.PublishDiagnosticsParams(uri=target, diagnostics=list(merged.values()))
            )

    def lsp_diagnostic(self, diag: Diagnostic, analysis: Analysis) -> types.Diagnostic:
        """A front-end diagnostic as LSP sends it: range, severity, code, `vkgc` as source."""
        message = "\n".join([diag.message, *(f"note: {n}" for n in diag.notes)])
        severity = types.DiagnosticSeverity.Error if diag.is_error else types.DiagnosticSeverity.Warning
        return types.Diagnostic(
            range=self.lsp_range(diag.span, analysis.sources),
            message=message,
            severity=severity,
            code=diag.code,
            source="vkgc",
        )

    def lsp_range(self, span: Span | None, sources: dict[str, str]) -> types.Range:
        """A span (1-based, end exclusive, code points) as an LSP range in the client's units."""
        if span is None:
            return types.Range(
                start=types.Position(line=0, character=0),
                end=types.Position(line=0, character=0),
            )
        lines = self.lines_of(span, sources)
        start = types.Position(line=max(span.line - 1, 0), character=max(span.col - 1, 0))
        end = types.Position(line=max(span.end_line - 1, 0), character=max(span.end_col - 1, 0))
        return self.workspace.position_codec.range_to_client_units(lines, types.Range(start=start, end=end))

    def lines_of(self, span: Span, sources: dict[str, str]) -> list[str]:
        """The lines of the file a span is in: the open buffer, else the compiled source (never the disk)."""
        document = self.open_documents().get(span_path(span))
        if document is not None:
            return list(document.lines)
        return sources.get(span.file, "").splitlines(keepends=True)

    def position(self, document: TextDocument, position: types.Position) -> tuple[str, int, int]:
        """The buffer's text and a client position in code points (line, character)."""
        converted = document.position_codec.position_from_client_units(document.lines, position)
        return document.source, converted.line, converted.character

    def program_path(self, document: TextDocument) -> Path:
        """The resolved path the compiler knows `document` by."""
        return document_path(document.uri, self.home())


server = VkgLanguageServer()


@server.feature(types.INITIALIZE)
def initialize(ls: VkgLanguageServer, params: types.InitializeParams) -> None:
    """Once the workspace exists: count position units with the codecs, not a character at a time."""
    count_units_fast(ls.workspace.position_codec)


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: VkgLanguageServer, params: types.DidOpenTextDocumentParams) -> None:
    """Check a file when it is opened."""
    ls.refresh(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: VkgLanguageServer, params: types.DidChangeTextDocumentParams) -> None:
    """Check a file (and the open files using it) once the edits pause."""
    ls.edited(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_SAVE)
def did_save(ls: VkgLanguageServer, params: types.DidSaveTextDocumentParams) -> None:
    """Check again on save (files on disk may have changed beside the buffer)."""
    ls.refresh(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: VkgLanguageServer, params: types.DidCloseTextDocumentParams) -> None:
    """Forget a closed file."""
    ls.forget(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_HOVER)
def hover(ls: VkgLanguageServer, params: types.HoverParams) -> types.Hover | None:
    """A quantity's SI value, or what the name under the cursor declares (null for a document not open)."""
    document = ls.answerable(params.text_document.uri)
    if document is None:
        return None
    text, line, char = ls.position(document, params.position)
    lines = text.split("\n")
    if line >= len(lines):
        return None
    quantity = quantity_hover(lines[line], char)
    if quantity is not None:
        value, start, end = quantity
        return _hover(value, document, line, start, end)
    key = document_key(document.uri)
    program = ls.programs.get(key)
    if program is None:
        return None
    symbol = symbol_at(program, ls.program_path(document), text, line, char)
    if symbol is None:
        return None
    analysis = ls.analyses.get(key)
    declared = declaration_span(symbol, analysis.sources if analysis else {})
    return _hover(symbol_hover(symbol, declared), document, line, None, None)


def _hover(value: str, document: TextDocument, line: int, start: int | None, end: int | None) -> types.Hover:
    contents = types.MarkupContent(kind=types.MarkupKind.Markdown, value=value)
    if start is None or end is None:
        return types.Hover(contents=contents)
    rng = types.Range(
        start=types.Position(line=line, character=start),
        end=types.Position(line=line, character=end),
    )
    return types.Hover(
        contents=contents,
        range=document.position_codec.range_to_client_units(document.lines, rng),
    )


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
def definition(ls: VkgLanguageServer, params: types.DefinitionParams) -> types.Location | None:
    """Where the name under the cursor is declared, in whichever module of the compilation."""
    document = ls.answerable(params.text_document.uri)
    if document is None:
        return None
    text, line, char = ls.position(document, params.position)
    key = document_key(document.uri)
    program = ls.programs.get(key)
    if program is None:
        return None
    symbol = symbol_at(program, ls.program_path(document), text, line, char)
    if symbol is None:
        return None
    opened = ls.open_documents()
    if symbol.file is not None:
        zero = types.Position(line=0, character=0)
        return types.Location(uri=ls.uri_of(Path(symbol.file), opened), range=types.Range(start=zero, end=zero))
    analysis = ls.analyses.get(key)
    sources = analysis.sources if analysis else {}
    span = declaration_span(symbol, sources)
    if span is None:
        return None
    return types.Location(uri=ls.uri_of(span_path(span), opened), range=ls.lsp_range(span, sources))


@server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["."]))
def completion(ls: VkgLanguageServer, params: types.CompletionParams) -> types.CompletionList | None:
    """Keywords, units and the names in scope (members only after `Body.`)."""
    document = ls.answerable(params.text_document.uri)
    if document is None:
        return None
    text, line, char = ls.position(document, params.position)
    lines = text.split("\n")
    before = lines[line][:char] if line < len(lines) else ""
    items = [
        types.CompletionItem(label=c.label, kind=_KINDS.get(c.kind), detail=c.detail or c.kind)
        for c in candidates(ls.programs.get(document_key(document.uri)), before)
    ]
    return types.CompletionList(is_incomplete=False, items=items)


@server.feature(types.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: VkgLanguageServer, params: types.DocumentFormattingParams) -> list[types.TextEdit] | None:
    """`vkgc fmt` of the buffer as one edit (none when it is already canonical or does not parse)."""
    from vkgl.errors import CompileError

    document = ls.answerable(params.text_document.uri)
    if document is None:
        return None
    text = document.source
    try:
        formatted = format_source(text, str(ls.program_path(document)))
    except CompileError:
        return None
    if formatted == text:
        return []
    lines = text.split("\n")
    end = types.Position(line=len(lines) - 1, character=len(lines[-1]))
    whole = types.Range(start=types.Position(line=0, character=0), end=end)
    return [
        types.TextEdit(
            range=document.position_codec.range_to_client_units(document.lines, whole),
            new_text=formatted,
        )
    ]


def main() -> int:
    """Serve over stdin/stdout until the client says exit."""
    server.start_io()
    return 0
