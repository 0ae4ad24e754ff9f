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

The editor extension in editors/vscode/ starts it; any LSP client can.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

from vkgl.editor.analysis import Analysis, analyze, span_path
from vkgl.editor.completion import candidates
from vkgl.editor.hover import quantity_hover, symbol_hover
from vkgl.editor.symbols import declaration_span, symbol_at
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir.nodes import Span
from vkgl.lang.ir.program import Program
from vkgl.lang.syntax.printer import format_source

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


class VkgLanguageServer(LanguageServer):
    """The server's state: the last analysis of each open file and what was published where."""

    def __init__(self) -> None:
        super().__init__(NAME, VERSION)
        self.analyses: dict[str, Analysis] = {}
        self.programs: dict[str, Program] = {}  # the last program whose root parsed, per open file
        self.published: dict[str, dict[str, list[types.Diagnostic]]] = {}  # root uri -> file uri -> diagnostics

    # ------------------------------------------------------------ analysis

    def overlay(self) -> dict[Path, str]:
        """The open buffers by resolved path: what the compiler reads instead of the files."""
        buffers: dict[Path, str] = {}
        for uri, document in self.workspace.text_documents.items():
            path = to_fs_path(uri)
            if path is not None:
                buffers[Path(path).resolve()] = document.source
        return buffers

    def refresh(self, uri: str) -> None:
        """Re-check `uri`, then every other open file whose compilation includes it."""
        path = to_fs_path(uri)
        if path is None:
            return
        changed = Path(path).resolve()
        self.check(uri)
        for other, analysis in list(self.analyses.items()):
            if other != uri and changed in analysis.files:
                self.check(other)

    def check(self, uri: str) -> None:
        """Compile one open file and publish its diagnostics."""
        path = to_fs_path(uri)
        if path is None or uri not in self.workspace.text_documents:
            return
        analysis = analyze(path, self.overlay())
        self.analyses[uri] = analysis
        if analysis.program.modules:
            self.programs[uri] = analysis.program
        by_file = {
            from_fs_path(str(file)) or str(file): [self.lsp_diagnostic(d, analysis) for d in found]
            for file, found in analysis.diagnostics_by_file().items()
        }
        self.publish(uri, by_file)

    def forget(self, uri: str) -> None:
        """A file was closed: drop its analysis and withdraw what it published."""
        self.analyses.pop(uri, None)
        self.programs.pop(uri, None)
        self.publish(uri, {})

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
        """The lines of the file a span is in: the open buffer, the compiled source, or the file."""
        uri = from_fs_path(str(span_path(span)))
        if uri is not None and uri in self.workspace.text_documents:
            return list(self.workspace.get_text_document(uri).lines)
        text = sources.get(span.file)
        if text is None:
            try:
                text = span_path(span).read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                text = ""
        return text.splitlines(keepends=True)

    def position(self, uri: str, position: types.Position) -> tuple[str, int, int]:
        """The buffer's text and a client position in code points (line, character)."""
        document = self.workspace.get_text_document(uri)
        converted = document.position_codec.position_from_client_units(document.lines, position)
        return document.source, converted.line, converted.character


server = VkgLanguageServer()


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: VkgLanguageServer, params: types.DidOpenTextDocumentParams) -> None:
    """Check a file when it is opened."""
    ls.refresh(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: VkgLanguageServer, params: types.DidChangeTextDocumentParams) -> None:
    """Check a file (and the open files using it) on every change."""
    ls.refresh(params.text_document.uri)


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
    """A quantity's SI value, or what the name under the cursor declares."""
    uri = params.text_document.uri
    text, line, char = ls.position(uri, params.position)
    lines = text.split("\n")
    if line >= len(lines):
        return None
    quantity = quantity_hover(lines[line], char)
    if quantity is not None:
        value, start, end = quantity
        return _hover(value, ls, uri, line, start, end)
    program = ls.programs.get(uri)
    path = to_fs_path(uri)
    if program is None or path is None:
        return None
    symbol = symbol_at(program, Path(path).resolve(), text, line, char)
    if symbol is None:
        return None
    analysis = ls.analyses.get(uri)
    declared = declaration_span(symbol, analysis.sources if analysis else {})
    return _hover(symbol_hover(symbol, declared), ls, uri, line, None, None)


def _hover(
    value: str,
    ls: VkgLanguageServer,
    uri: str,
    line: int,
    start: int | None,
    end: int | None,
) -> types.Hover:
    contents = types.MarkupContent(kind=types.MarkupKind.Markdown, value=value)
    if start is None or end is None:
        return types.Hover(contents=contents)
    document = ls.workspace.get_text_document(uri)
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
    uri = params.text_document.uri
    text, line, char = ls.position(uri, params.position)
    program = ls.programs.get(uri)
    path = to_fs_path(uri)
    if program is None or path is None:
        return None
    symbol = symbol_at(program, Path(path).resolve(), text, line, char)
    if symbol is None:
        return None
    if symbol.file is not None:
        zero = types.Position(line=0, character=0)
        return types.Location(
            uri=from_fs_path(str(symbol.file)) or "",
            range=types.Range(start=zero, end=zero),
        )
    analysis = ls.analyses.get(uri)
    sources = analysis.sources if analysis else {}
    span = declaration_span(symbol, sources)
    if span is None:
        return None
    return types.Location(uri=from_fs_path(str(span_path(span))) or "", range=ls.lsp_range(span, sources))


@server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["."]))
def completion(ls: VkgLanguageServer, params: types.CompletionParams) -> types.CompletionList:
    """Keywords, units and the names in scope (members only after `Body.`)."""
    uri = params.text_document.uri
    text, line, char = ls.position(uri, params.position)
    lines = text.split("\n")
    before = lines[line][:char] if line < len(lines) else ""
    items = [
        types.CompletionItem(label=c.label, kind=_KINDS.get(c.kind), detail=c.detail or c.kind)
        for c in candidates(ls.programs.get(uri), before)
    ]
    return types.CompletionList(is_incomplete=False, items=items)


@server.feature(types.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: VkgLanguageServer, params: types.DocumentFormattingParams) -> list[types.TextEdit] | None:
    """`vkgc fmt` of the buffer as one edit (none when it is already canonical or does not parse)."""
    from vkgl.errors import CompileError

    uri = params.text_document.uri
    document = ls.workspace.get_text_document(uri)
    text = document.source
    try:
        formatted = format_source(text, to_fs_path(uri) or uri)
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
