"""A real editor's side of `orc lsp`: pygls' LanguageClient running `python -m orc_rpl lsp` over a stdio pipe."""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path
from typing import Any

from lsprotocol import types as T
from pygls.lsp.client import LanguageClient
from pygls.uris import from_fs_path

#: Long enough for a busy machine to start Python and load the registry; a hang guard, not a timing assertion.
HANG_GUARD_S = 120.0


class Editor:
    """Opens documents in a running server, collects the diagnostics it publishes and asks for features."""

    def __init__(self) -> None:
        self.client = LanguageClient("orc-rpl-tests", "1")
        self.published: dict[str, asyncio.Queue[list[T.Diagnostic]]] = {}
        self.logs: list[str] = []
        self.versions: dict[str, int] = {}

        @self.client.feature(T.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def on_diagnostics(params: T.PublishDiagnosticsParams) -> None:
            self.queue(params.uri).put_nowait(list(params.diagnostics))

        @self.client.feature(T.WINDOW_LOG_MESSAGE)
        def on_log(params: T.LogMessageParams) -> None:
            self.logs.append(params.message)

    def queue(self, uri: str) -> asyncio.Queue[list[T.Diagnostic]]:
        return self.published.setdefault(uri, asyncio.Queue())

    async def __aenter__(self) -> Editor:
        await self.client.start_io(sys.executable, "-m", "orc_rpl", "lsp")
        await asyncio.wait_for(self.client.initialize_async(T.InitializeParams(capabilities=T.ClientCapabilities())), HANG_GUARD_S)
        self.client.initialized(T.InitializedParams())
        return self

    async def __aexit__(self, *exc: Any) -> None:
        await asyncio.wait_for(self.client.shutdown_async(None), HANG_GUARD_S)
        self.client.exit(None)
        await asyncio.wait_for(self.client.stop(), HANG_GUARD_S)

    async def open(self, path: Path, text: str | None = None) -> tuple[str, list[T.Diagnostic]]:
        """Open a file (its text on disk unless given) and wait for its diagnostics."""
        uri = from_fs_path(str(path))
        assert uri is not None
        self.versions[uri] = 1
        language = "orl" if path.suffix == ".orl" else "rpl"
        text = path.read_text() if text is None else text
        self.client.text_document_did_open(T.DidOpenTextDocumentParams(T.TextDocumentItem(uri, language, 1, text)))
        return uri, await self.diagnostics(uri)

    async def change(self, uri: str, text: str) -> list[T.Diagnostic]:
        """Replace the whole text, as an editor does on each keystroke with full sync, and wait for the diagnostics."""
        self.versions[uri] += 1
        self.client.text_document_did_change(T.DidChangeTextDocumentParams(
            T.VersionedTextDocumentIdentifier(self.versions[uri], uri), [T.TextDocumentContentChangeWholeDocument(text)]))
        return await self.diagnostics(uri)

    async def diagnostics(self, uri: str) -> list[T.Diagnostic]:
        return await asyncio.wait_for(self.queue(uri).get(), HANG_GUARD_S)

    async def completion(self, uri: str, line0: int, character: int) -> list[T.CompletionItem]:
        result = await asyncio.wait_for(self.client.text_document_completion_async(
            T.CompletionParams(T.TextDocumentIdentifier(uri), T.Position(line0, character))), HANG_GUARD_S)
        return list(result.items if isinstance(result, T.CompletionList) else result or [])

    async def hover(self, uri: str, line0: int, character: int) -> str | None:
        result = await asyncio.wait_for(self.client.text_document_hover_async(
            T.HoverParams(T.TextDocumentIdentifier(uri), T.Position(line0, character))), HANG_GUARD_S)
        return None if result is None else result.contents.value  # type: ignore[union-attr]

    async def definition(self, uri: str, line0: int, character: int) -> Any:
        return await asyncio.wait_for(self.client.text_document_definition_async(
            T.DefinitionParams(T.TextDocumentIdentifier(uri), T.Position(line0, character))), HANG_GUARD_S)

    async def symbols(self, uri: str) -> Any:
        return await asyncio.wait_for(self.client.text_document_document_symbol_async(
            T.DocumentSymbolParams(T.TextDocumentIdentifier(uri))), HANG_GUARD_S)

    async def formatting(self, uri: str) -> list[T.TextEdit] | None:
        return await asyncio.wait_for(self.client.text_document_formatting_async(
            T.DocumentFormattingParams(T.TextDocumentIdentifier(uri), T.FormattingOptions(4, True))), HANG_GUARD_S)
