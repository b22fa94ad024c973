"""Lark's contextual lexer with its common case in one regular expression: the same tokens, fewer Python steps per token."""

from __future__ import annotations

from collections.abc import Callable, Container, Iterator, Mapping
from typing import Any, Protocol

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedToken
from lark.lexer import ContextualLexer


#: What the shared loop asks when the common case does not hold: the next token as Lark lexes it from (position,
#: line, start of the line), None at the end of the text.
Fallback = Callable[[int, int, int], "Token | None"]


class StateStack(Protocol):
    """The parser's states as the shared loop reads them: `[-1]` is the current one."""

    def __getitem__(self, index: int, /) -> int: ...


class FastContextualLexer:
    """Lexes with the root lexer's regex, blanks skipped inside it, and keeps a token when the parser's state accepts it.

    The contextual lexer would give the same token then: its state lexer tries a subset of the root lexer's terminals
    in the same order, so the first terminal that matches, if the state accepts it, is the first of the subset too.
    Any other token (a reserved word where only a name fits, a character no terminal takes) is lexed by Lark's own
    contextual lexer, errors included, so messages stay the same. The loop (`tokens`) is shared with the LALR loop of
    orc_rpl.syntax.lalr, which runs it on its own stack of states.
    """

    def __init__(self, inner: ContextualLexer) -> None:
        self.inner = inner
        root = inner.root_lexer
        scanner = root.scanner                      # builds the scanner and the keyword callbacks
        (pattern,) = scanner._mres                  # one alternation of every terminal, in Lark's order
        self.regex = root.re.compile(r"[ \t]*(?:" + pattern.pattern + ")", pattern.flags)
        # Lark's "unless" callbacks turn a NAME that spells a keyword into that keyword: here one dict per terminal
        # (plain str: Lark's names may be its Token class, whose __eq__ is Python's)
        self.keywords = {str(type_): {str(t.pattern.value): str(t.name) for t in unless.scanner.terminals}
                         for type_, unless in root.callback.items()}
        self.newline_types = root.newline_types
        self.ignore_types = root.ignore_types

    def tokens(self, text: str, pos: int, end: int, line: int, line_start: int, states: StateStack,
               rows: Mapping[int, Container[str]], fallback: Fallback) -> Iterator[Token]:
        """The tokens of text[pos:end] (pos on `line`, which starts at `line_start`), each lexed for the parser state
        `states[-1]` at that moment (the parser moves on between two tokens), kept when `rows[state]` accepts it;
        `fallback` lexes any other."""
        match, keywords = self.regex.match, self.keywords
        newline_types, ignore_types = self.newline_types, self.ignore_types
        make = str.__new__
        while pos < end:
            found = match(text, pos, end)
            kind = found.lastgroup if found is not None else None
            row = rows[states[-1]]
            if kind is not None and kind not in ignore_types:
                start, stop = found.span(kind)
                value = text[start:stop]
                spelled = keywords.get(kind)
                if spelled is not None:
                    kind = spelled.get(value, kind)
            if kind is None or kind in ignore_types or kind not in row:
                token = fallback(pos, line, line_start)
                if token is None:
                    return
                pos, line = token.end_pos, token.end_line
                line_start = pos - token.end_column + 1
                yield token
                continue
            token = make(Token, value)  # Token's own constructor costs two class-method calls a token
            token.type, token.value, token.start_pos = kind, value, start
            token.line, token.column = line, start - line_start + 1
            pos = stop
            if kind in newline_types and "\n" in value:
                line += value.count("\n")
                line_start = start + value.rindex("\n") + 1
            token.end_line, token.end_column, token.end_pos = line, pos - line_start + 1, pos
            yield token

    def lex(self, lexer_state: Any, parser_state: Any) -> Iterator[Token]:
        """ContextualLexer.lex: Lark's parser drives it (the LALR loop of orc_rpl.syntax.lalr hands errors to it)."""
        line_ctr = lexer_state.line_ctr

        def fallback(pos: int, line: int, line_start: int) -> Token | None:
            return self.lark_token_at(lexer_state, parser_state, pos, line, line_start)

        for token in self.tokens(lexer_state.text.text, line_ctr.char_pos, lexer_state.text.end, line_ctr.line,
                                 line_ctr.line_start_pos, _Position(parser_state),
                                 parser_state.parse_conf.parse_table.states, fallback):
            # where Lark's own lexer would be: its errors report the last token, and lex on from the counter
            line_ctr.char_pos, line_ctr.line, line_ctr.column = token.end_pos, token.end_line, token.end_column
            line_ctr.line_start_pos = token.end_pos - token.end_column + 1
            lexer_state.last_token = token
            yield token

    def lark_token_at(self, lexer_state: Any, parser_state: Any, pos: int, line: int, line_start: int) -> Token | None:
        """The token at `pos` (on `line`, which starts at `line_start`) as Lark's contextual lexer makes it for the
        parser's state, its end always set (None at the end of the text); Lark's errors as its lexer raises them."""
        line_ctr = lexer_state.line_ctr
        line_ctr.char_pos, line_ctr.line, line_ctr.line_start_pos = pos, line, line_start
        line_ctr.column = pos - line_start + 1
        token = self._one_lark_token(lexer_state, parser_state)
        if token is not None and token.end_pos is None:
            token.end_pos, token.end_line, token.end_column = line_ctr.char_pos, line_ctr.line, line_ctr.column
        return token

    def _one_lark_token(self, lexer_state: Any, parser_state: Any) -> Token | None:
        """One token as Lark's contextual lexer makes it (the end of the text: None)."""
        inner = self.inner
        try:
            return inner.lexers[parser_state.position].next_token(lexer_state, parser_state)
        except EOFError:
            return None
        except UnexpectedCharacters as error:  # as ContextualLexer.lex reports it
            try:
                last_token = lexer_state.last_token
                token = inner.root_lexer.next_token(lexer_state, parser_state)
                raise UnexpectedToken(token, error.allowed, state=parser_state, token_history=[last_token],
                                      terminals_by_name=inner.root_lexer.terminals_by_name) from None
            except UnexpectedCharacters:
                raise error from None


class _Position:
    """Lark's parser state as `tokens` reads it: `[-1]` is its current state (Lark's parser moves on in between)."""

    __slots__ = ("parser_state",)

    def __init__(self, parser_state: Any) -> None:
        self.parser_state = parser_state

    def __getitem__(self, index: int) -> int:
        return self.parser_state.position  # type: ignore[no-any-return]


def speed_up(lark: Lark) -> Lark:
    """The parser with its contextual lexer replaced by the fast one (same tokens, same errors)."""
    frontend = lark.parser
    holder = frontend.lexer if not isinstance(frontend.lexer, ContextualLexer) else frontend  # behind a postlexer, or not
    inner = getattr(holder, "lexer", None)
    if isinstance(inner, ContextualLexer) and len(inner.root_lexer.scanner._mres) == 1:
        holder.lexer = FastContextualLexer(inner)
    return lark
