"""The language server (pygls over stdio): diagnostics as the user types, completion, hover, definition, outline, formatting."""

from __future__ import annotations

import functools
import logging
from pathlib import Path
from typing import Any, Callable, TypeVar

from lsprotocol import types as T
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path
from pygls.workspace import TextDocument
from pygls.workspace.position_codec import ServerTextPosition, ServerTextRange

from orc_rpl import __version__
from orc_rpl.application.registry import Registry, default_registry
from orc_rpl.errors import Diagnostic, OrcError
from orc_rpl.lsp.analysis import Analysis, analyse
from orc_rpl.lsp.completion import complete
from orc_rpl.lsp.hover import hover_text
from orc_rpl.lsp.index import ProgramIndex
from orc_rpl.lsp.navigation import Outline, definition_of, outline
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.files import canonical_text

log = logging.getLogger("orc_rpl.lsp")
R = TypeVar("R")


class OrcLanguageServer(LanguageServer):
    """pygls' server with the registry and the last analysis of every open document."""

    def __init__(self) -> None:
        super().__init__("orc-rpl", __version__)
        self.registry: Registry = _registry()
        self.analyses: dict[str, Analysis] = {}
        self.indexes: dict[str, ProgramIndex] = {}     #: the last index of a text that parsed (completion while typing)


def _registry() -> Registry:
    """The registry with every installed feature; a broken third-party feature is logged and left out."""
    try:
        return default_registry()
    except OrcError as error:
        log.warning("orc lsp: %s; only the built-in features are known", error)
        return default_registry(extra_features=False)


def guarded(default: Any) -> Callable[[Callable[..., R]], Callable[..., R]]:
    """An error in a feature is logged (stderr and the client's log) and answered with `default`: the server goes on."""
    def wrap(handler: Callable[..., R]) -> Callable[..., R]:
        @functools.wraps(handler)
        def run(server: OrcLanguageServer, params: Any) -> R:
            try:
                return handler(server, params)
            except Exception as error:  # never let one request take the server down
                log.exception("orc lsp: %s failed", handler.__name__)
                server.window_log_message(T.LogMessageParams(T.MessageType.Error,
                                                             f"orc lsp: {handler.__name__} failed: {type(error).__name__}: {error}"))
                return default
        return run
    return wrap


def document_path(document: TextDocument) -> str:
    """The file path of a document (its URI's path; the suffix decides the syntax)."""
    return document.path or to_fs_path(document.uri) or document.uri


def span_range(document: TextDocument | None, span: n.Span) -> T.Range:
    """A 1-based span (end exclusive, 0 for one character) as an LSP range in the client's units."""
    line0, column0 = max(span.line - 1, 0), max(span.column - 1, 0)
    end_line0 = span.end_line - 1 if span.end_line else line0
    end_column0 = span.end_column - 1 if span.end_column else column0 + 1
    if end_line0 < line0 or (end_line0 == line0 and end_column0 <= column0):
        end_line0, end_column0 = line0, column0 + 1
    server = ServerTextRange(ServerTextPosition(line0, column0), ServerTextPosition(end_line0, end_column0))
    if document is None:
        return T.Range(T.Position(line0, column0), T.Position(end_line0, end_column0))
    return document.range_to_client_units(server)


def lsp_diagnostic(document: TextDocument, diagnostic: Diagnostic) -> T.Diagnostic:
    loc = diagnostic.location
    message = diagnostic.message + (f"\nhint: {diagnostic.hint}" if diagnostic.hint else "")
    severity = T.DiagnosticSeverity.Warning if diagnostic.severity == "warning" else T.DiagnosticSeverity.Error
    return T.Diagnostic(span_range(document, n.Span(loc.line, loc.column, loc.end_line, loc.end_column)), message,
                        severity=severity, source="orc")


def refresh(server: OrcLanguageServer, uri: str) -> None:
    """Analyse a document's current text and publish every diagnostic it has (an empty list clears them)."""
    document = server.workspace.get_text_document(uri)
    analysis = analyse(document.source, document_path(document), server.registry)
    server.analyses[uri] = analysis
    program = analysis.program or analysis.salvaged
    if program is not None:
        server.indexes[uri] = ProgramIndex(program)
    diagnostics = [lsp_diagnostic(document, d) for d in analysis.diagnostics]
    server.text_document_publish_diagnostics(T.PublishDiagnosticsParams(uri, diagnostics, version=document.version))


def _cursor(server: OrcLanguageServer, uri: str, position: T.Position) -> tuple[TextDocument, Analysis, int, int]:
    """The document, its analysis and the 0-based cursor in code points."""
    document = server.workspace.get_text_document(uri)
    if uri not in server.analyses or server.analyses[uri].text != document.source:
        refresh(server, uri)
    where = document.position_from_client_units(position)
    return document, server.analyses[uri], where.line, where.character


def did_open(ls: OrcLanguageServer, params: T.DidOpenTextDocumentParams) -> None:
    refresh(ls, params.text_document.uri)


def did_change(ls: OrcLanguageServer, params: T.DidChangeTextDocumentParams) -> None:
    refresh(ls, params.text_document.uri)


def did_save(ls: OrcLanguageServer, params: T.DidSaveTextDocumentParams) -> None:
    refresh(ls, params.text_document.uri)  # the world file beside it may have changed


def did_close(ls: OrcLanguageServer, params: T.DidCloseTextDocumentParams) -> None:
    uri = params.text_document.uri
    ls.analyses.pop(uri, None)
    ls.indexes.pop(uri, None)
    ls.text_document_publish_diagnostics(T.PublishDiagnosticsParams(uri, []))


def completion(ls: OrcLanguageServer, params: T.CompletionParams) -> T.CompletionList | None:
    uri = params.text_document.uri
    document, analysis, line0, character = _cursor(ls, uri, params.position)
    context = params.context
    after_space = (context is not None and context.trigger_kind == T.CompletionTriggerKind.TriggerCharacter
                   and context.trigger_character == " ")
    items = complete([line.rstrip("\r\n") for line in document.lines], line0, character,
                     ls.registry, ls.indexes.get(uri), analysis.world, analysis.offline, after_space)
    return T.CompletionList(is_incomplete=False, items=items)


def hover(ls: OrcLanguageServer, params: T.HoverParams) -> T.Hover | None:
    uri = params.text_document.uri
    _, analysis, line0, character = _cursor(ls, uri, params.position)
    index = ls.indexes.get(uri) if analysis.program is not None else None
    text = hover_text(analysis, index, ls.registry, line0, character)
    return T.Hover(T.MarkupContent(T.MarkupKind.Markdown, text)) if text else None


def definition(ls: OrcLanguageServer, params: T.DefinitionParams) -> T.Location | None:
    uri = params.text_document.uri
    document, analysis, line0, character = _cursor(ls, uri, params.position)
    index = ls.indexes.get(uri)
    if analysis.program is None or index is None:
        return None
    place = definition_of(analysis, index, line0 + 1, character + 1)
    if place is None:
        return None
    if Path(place.path) == Path(analysis.path):
        return T.Location(uri, span_range(document, place.span))
    return T.Location(from_fs_path(str(Path(place.path).resolve())) or place.path, span_range(None, place.span))


def _symbol(document: TextDocument, entry: Outline) -> T.DocumentSymbol:
    d = entry.definition
    statement_span = d.statement.span if d.statement.span.line else d.span
    whole = span_range(document, statement_span)
    name = span_range(document, d.span)
    if not (whole.start.line <= name.start.line <= whole.end.line):
        whole = name
    return T.DocumentSymbol(d.name, entry.symbol_kind, whole, name, detail=d.kind,
                            children=[_symbol(document, child) for child in entry.children] or None)


def document_symbol(ls: OrcLanguageServer, params: T.DocumentSymbolParams) -> list[T.DocumentSymbol] | None:
    uri = params.text_document.uri
    document, analysis, _, _ = _cursor(ls, uri, T.Position(0, 0))
    index = ls.indexes.get(uri)
    if analysis.program is None or index is None:
        return None
    return [_symbol(document, entry) for entry in outline(index)]


def formatting(ls: OrcLanguageServer, params: T.DocumentFormattingParams) -> list[T.TextEdit] | None:
    """The whole text replaced by what `orc fmt` prints; nothing while the text has syntax errors."""
    uri = params.text_document.uri
    document, analysis, _, _ = _cursor(ls, uri, T.Position(0, 0))
    if analysis.program is None:
        ls.window_log_message(T.LogMessageParams(T.MessageType.Info, "orc lsp: not formatted: the text has syntax errors"))
        return None
    try:
        canonical = canonical_text(analysis.program, analysis.path)
    except OrcError as error:  # an on-line name the off-line syntax cannot spell
        ls.window_log_message(T.LogMessageParams(T.MessageType.Info, f"orc lsp: not formatted: {error}"))
        return None
    if canonical == document.source:
        return []
    lines = document.lines
    end = T.Position(len(lines), 0)
    return [T.TextEdit(T.Range(T.Position(0, 0), end), canonical)]


def make_server() -> OrcLanguageServer:
    """A server with every feature registered, each guarded so that an error is logged and the server goes on."""
    ls = OrcLanguageServer()
    ls.feature(T.TEXT_DOCUMENT_DID_OPEN)(guarded(None)(did_open))
    ls.feature(T.TEXT_DOCUMENT_DID_CHANGE)(guarded(None)(did_change))
    ls.feature(T.TEXT_DOCUMENT_DID_SAVE)(guarded(None)(did_save))
    ls.feature(T.TEXT_DOCUMENT_DID_CLOSE)(guarded(None)(did_close))
    ls.feature(T.TEXT_DOCUMENT_COMPLETION, T.CompletionOptions(trigger_characters=[".", " "]))(guarded(None)(completion))
    ls.feature(T.TEXT_DOCUMENT_HOVER)(guarded(None)(hover))
    ls.feature(T.TEXT_DOCUMENT_DEFINITION)(guarded(None)(definition))
    ls.feature(T.TEXT_DOCUMENT_DOCUMENT_SYMBOL)(guarded(None)(document_symbol))
    ls.feature(T.TEXT_DOCUMENT_FORMATTING)(guarded(None)(formatting))
    return ls


def serve() -> None:
    """Serve one editor over standard input and output until it exits."""
    logging.basicConfig(level=logging.WARNING, format="%(message)s")  # stderr: the editor's log of the server
    make_server().start_io()
