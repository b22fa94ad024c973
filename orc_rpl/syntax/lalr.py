"""Lark's LALR tables and tree-building callbacks driven by one tight loop: the same parse with fewer Python steps per token.

Lark's own loop spends most of its time in bookkeeping that a valid program never needs (a method call, eight
attribute lookups and a Rule hash per token and per reduction, a Token built through two class methods). This loop
runs on the same parse table, with each state's actions turned into one dict (an int: shift to that state; a tuple:
reduce by that many values with that callback), and lexes with `fast_lexer`'s loop on its own stack of states.
Anything it does not handle itself, a syntax error above all, is handed to Lark, which parses the text again from
the start: errors and their messages come from Lark, exactly as before.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial
from itertools import chain
from typing import Any

from lark import Lark, Token
from lark.exceptions import LarkError
from lark.lexer import LexerState, LineCounter, TextSlice
from lark.parsers.lalr_analysis import Shift

from orc_rpl.syntax.fast_lexer import FastContextualLexer


#: The end of the token stream, as the parser is fed it (errors there are Lark's to report).
_END = (Token("$END", ""),)


class _Unusual(Exception):
    """Something only Lark's own parser handles (a syntax error, above all): parse the text with it."""


class _Spliced:
    """The value of one of Lark's inlined rules (`_name`, and the `__x_star_N` of every repetition): its parent's
    filter splices `.children` into its own, so nothing else of a parse tree node is ever read."""

    __slots__ = ("children",)

    def __init__(self, children: list[Any]) -> None:
        self.children = children


def _spliced(rule: Any, callback: Callable[[list[Any]], Any]) -> Callable[[list[Any]], Any]:
    """The callback of a rule, with Lark's default tree (four calls deep) replaced by _Spliced for inlined rules."""
    if not str(rule.origin.name).startswith("_"):
        return callback
    if isinstance(callback, partial) and getattr(callback.func, "__name__", "") == "default_callback":
        return _Spliced
    inner = getattr(callback, "node_builder", None)
    if isinstance(inner, partial) and getattr(inner.func, "__name__", "") == "default_callback":
        callback.node_builder = _Spliced  # type: ignore[attr-defined]  # Lark's own filter, now building the light node
    return callback


class _ParserPosition:
    """What Lark's one-token lexers ask of the parser: its current state."""

    __slots__ = ("position",)

    def __init__(self, position: int) -> None:
        self.position = position


class FastLalr:
    """Parses with a Lark LALR parser's own tables, callbacks, lexer and post-lexer; `parse(text)` as `lark.parse`."""

    def __init__(self, lark: Lark, start: str = "program") -> None:
        frontend = lark.parser
        connector = frontend.lexer
        self.postlexer = getattr(connector, "postlexer", None)
        lexer = getattr(connector, "lexer", connector)
        if not isinstance(lexer, FastContextualLexer):
            raise TypeError("FastLalr needs the parser sped up by fast_lexer.speed_up")
        self.lark, self.lexer = lark, lexer
        inner = frontend.parser.parser
        table, callbacks = inner.parse_table, inner.callbacks
        if any(isinstance(key, str) for key in callbacks):
            raise TypeError("FastLalr does not run terminal callbacks")
        self.start_state, self.end_state = table.start_states[start], table.end_states[start]
        # Lark names symbols with its Token class (a str with an __eq__ of its own): plain str keys hash and compare in C
        self.actions: dict[int, dict[str, Any]] = {
            state: {str(symbol): (arg if action is Shift else (len(arg.expansion), _spliced(arg, callbacks[arg]), str(arg.origin.name)))
                    for symbol, (action, arg) in row.items()}
            for state, row in table.states.items()
        }

    def parse(self, text: str) -> Any:
        """The callbacks' result for the whole text; Lark's exception (or result) when this loop cannot go on."""
        try:
            return self._parse(text)
        except _Unusual:
            return self.lark.parse(text)

    def _parse(self, text: str) -> Any:
        actions, end_state = self.actions, self.end_state
        states = [self.start_state]
        values: list[Any] = []
        tokens = self._lex(text, states)
        if self.postlexer is not None:
            tokens = self.postlexer.process(tokens)
        state = self.start_state   # states[-1], kept in a local too: the lexer reads the list, the loop the local
        for token in chain(tokens, _END):
            kind = token.type
            while True:
                action = actions[state].get(kind)
                if action is None:
                    raise _Unusual
                if action.__class__ is int:
                    if kind == "$END":
                        raise _Unusual
                    states.append(action)
                    values.append(token)
                    state = action
                    break
                size, callback, origin = action
                if size:
                    children = values[-size:]
                    del states[-size:]
                    del values[-size:]
                else:
                    children = []
                values.append(callback(children))
                state = actions[states[-1]][origin]
                states.append(state)
                if state == end_state and kind == "$END":
                    return values[-1]
        raise _Unusual

    def _lex(self, text: str, states: list[int]) -> Iterator[Token]:
        """The tokens of `text` as Lark's contextual lexer gives them, each for the parser state it is lexed in."""
        return self.lexer.tokens(text, 0, len(text), 1, 0, states, self.actions,
                                 lambda pos, line, line_start: self._one_lark_token(text, pos, line, line_start, states[-1]))

    def _one_lark_token(self, text: str, pos: int, line: int, line_start: int, state: int) -> Token | None:
        """The next token as Lark's lexer for this parser state makes it (None at the end of the text)."""
        lexer_state = LexerState(TextSlice(text, 0, len(text)), LineCounter("\n"))
        try:
            return self.lexer.lark_token_at(lexer_state, _ParserPosition(state), pos, line, line_start)
        except LarkError:
            raise _Unusual from None


def fast_parse(lark: Lark) -> Callable[[str], Any]:
    """`lark.parse`, through FastLalr when the parser allows it."""
    try:
        return FastLalr(lark).parse
    except TypeError:
        return lark.parse
