"""Lark's contextual lexer with its common case in one regular expression: the same tokens, fewer Python steps per token."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedToken
from lark.lexer import ContextualLexer


class FastContextualLexer:
    """Lexes with the root lexer's regex, blanks skipped inside it, and keeps a token when the parser's state accepts it.

    The contextual lexer would give the same token then: its state lexer tries a subset of the root lexer's terminals
    in the same order, so the first terminal that matches, if the state accepts it, is the first of the subset too.
    Any other token (a reserved word where only a name fits, a character no terminal takes) is lexed by Lark's own
    contextual lexer, errors included, so messages stay the same.
    """

    def __init__(self, inner: ContextualLexer) -> None:
        self.inner = inner
        root = inner.root_lexer
        scanner = root.scanner                      # builds the scanner and the keyword callbacks
        (pattern,) = scanner._mres                  # one alternation of every terminal, in Lark's order
        self.regex = root.re.compile(r"[ \t]*(?:" + pattern.pattern + ")", pattern.flags)
        # Lark's "unless" callbacks turn a NAME that spells a keyword into that keyword: here one dict per terminal.
        self.keywords = {type_: {t.pattern.value: t.name for t in unless.scanner.terminals}
                         for type_, unless in root.callback.items()}
        self.newline_types = root.newline_types
        self.ignore_types = root.ignore_types

    def lex(self, lexer_state: Any, parser_state: Any) -> Iterator[Token]:
        text_slice = lexer_state.text
        text, end = text_slice.text, text_slice.end
        line_ctr = lexer_state.line_ctr
        match, keywords, newline_types, ignore_types = self.regex.match, self.keywords, self.newline_types, self.ignore_types
        states = parser_state.parse_conf.parse_table.states
        while line_ctr.char_pos < end:
            found = match(text, line_ctr.char_pos, end)
            type_ = found.lastgroup if found is not None else None
            if type_ is None or type_ in ignore_types:
                yield from self._one_lark_token(lexer_state, parser_state)
                continue
            start = found.start(type_)
            value = found.group(type_)
            line, column = line_ctr.line, start - line_ctr.line_start_pos + 1
            spelled = keywords.get(type_)
            if spelled is not None:
                type_ = spelled.get(value, type_)
            if type_ not in states[parser_state.position]:
                yield from self._one_lark_token(lexer_state, parser_state)
                continue
            token = Token(type_, value, start, line, column)
            line_ctr.char_pos = start
            line_ctr.feed(value, type_ in newline_types)
            token.end_line, token.end_column, token.end_pos = line_ctr.line, line_ctr.column, line_ctr.char_pos
            lexer_state.last_token = token
            yield token

    def _one_lark_token(self, lexer_state: Any, parser_state: Any) -> Iterator[Token]:
        """One token as Lark's contextual lexer makes it (the end of the text: none)."""
        inner = self.inner
        try:
            yield inner.lexers[parser_state.position].next_token(lexer_state, parser_state)
        except EOFError:
            return
        except UnexpectedCharacters as error:  # as ContextualLexer.lex reports it
            try:
                last_token = lexer_state.last_token
                token = inner.root_lexer.next_token(lexer_state, parser_state)
                raise UnexpectedToken(token, error.allowed, state=parser_state, token_history=[last_token],
                                      terminals_by_name=inner.root_lexer.terminals_by_name) from None
            except UnexpectedCharacters:
                raise error from None


def speed_up(lark: Lark) -> Lark:
    """The parser with its contextual lexer replaced by the fast one (same tokens, same errors)."""
    frontend = lark.parser
    holder = frontend.lexer if not isinstance(frontend.lexer, ContextualLexer) else frontend  # behind a postlexer, or not
    inner = getattr(holder, "lexer", None)
    if isinstance(inner, ContextualLexer) and len(inner.root_lexer.scanner._mres) == 1:
        holder.lexer = FastContextualLexer(inner)
    return lark
