"""Off-line text (`.orl`) -> the one syntax tree: Lark LALR with the contextual lexer, indentation from a line plan, errors as diagnostics."""

from __future__ import annotations

import re
from collections.abc import Callable
from functools import lru_cache

from lark import Lark
from lark.exceptions import UnexpectedInput, UnexpectedToken

from orc_rpl.errors import Diagnostic, Location, SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.grammar_files import grammar_path, parser_cache
from orc_rpl.syntax.fast_lexer import speed_up
from orc_rpl.syntax.bulk import paused_gc
from orc_rpl.syntax.lalr import fast_parse
from orc_rpl.syntax.limits import check_nesting
from orc_rpl.syntax.offline_builder import OFFLINE_KEYWORDS, OfflineTreeBuilder, check_names
from orc_rpl.syntax.offline_lexer import OfflinePostLexer, code_part, plan_indentation
from orc_rpl.syntax.parser import _diagnostic, parse_recovering, source_lines

_HEADER_WORD = re.compile(r"([ \t]*)(elif|else|except)(?![A-Za-z0-9_])")
_CONTINUATION = re.compile(r"[ \t]*(with|via|until)(?![A-Za-z0-9_])")

#: Off-line spellings of terminals in messages (the rest as on-line).
_OFFLINE_NAMES = {"_INDENT": "an indented block", "_DEDENT": "the end of the block", "MOVETO": "moveto",
                  "COLON": "':'", "RANGE": "'..'"}


@lru_cache(maxsize=None)
def _parse_once() -> Callable[[str], n.Program]:
    """The off-line parser's `parse`, on its fast loop (Lark itself for errors)."""
    return fast_parse(_lark()[0])


@lru_cache(maxsize=None)
def _lark() -> tuple[Lark, OfflinePostLexer]:
    """The off-line parser and its postlexer, built once per process."""
    postlexer = OfflinePostLexer()
    lark = speed_up(Lark(
        grammar_path("orl.lark").read_text(encoding="utf-8"),
        parser="lalr",
        lexer="contextual",
        start="program",
        maybe_placeholders=True,
        cache=parser_cache("orl"),
        postlex=postlexer,
        transformer=OfflineTreeBuilder(),
    ))
    return lark, postlexer


def _offline_diagnostic(path: str, error: Exception, lines: list[str]) -> tuple[Diagnostic, int]:
    """The on-line translation of Lark's errors, with the off-line words and the indentation tokens named."""
    if isinstance(error, UnexpectedToken) and error.token.type in ("_INDENT", "_DEDENT"):
        token = error.token
        line = (token.line or 1) + (1 if token.type == "_INDENT" else 0)
        line = min(max(line, 1), max(len(lines), 1))
        text = lines[line - 1] if lines else ""
        column = len(text) - len(text.lstrip(" \t")) + 1
        message = "unexpected indentation" if token.type == "_INDENT" else "a block ends here, but the statement above is not complete"
        return Diagnostic(Location(path, line, column, line, column + 1), message), line
    diagnostic, line = _diagnostic(path, error, lines)
    middle = _HEADER_WORD.match(lines[line - 1]) if 0 < line <= len(lines) else None
    if middle is not None and isinstance(error, UnexpectedInput):
        word = middle.group(2)
        owner = {"elif": "an if", "else": "an if or a case", "except": "a try"}[word]
        column = len(middle.group(1)) + 1
        return Diagnostic(Location(path, line, column, line, column + len(word)),
                          f"'{word}' must follow the block of {owner} at its indentation"), line
    message = diagnostic.message
    for terminal, word in _OFFLINE_NAMES.items():
        message = message.replace(f"'{terminal}'", word)
    message = message.replace("continues only a motion or an INSTALL statement", "continues only a motion or an install statement")
    diagnostic.message = message
    return diagnostic, line


def _neutralize(lines: list[str], number: int) -> None:
    """Make line `number` harmless while keeping its indentation, the blocks and every line number."""
    text = lines[number - 1]
    indent = text[: len(text) - len(text.lstrip(" \t"))]
    code = code_part(text)
    header = _HEADER_WORD.match(text)
    if header is not None:
        lines[number - 1] = indent + {"elif": "elif true:", "else": "else:", "except": "except orc_:"}[header.group(2)]
    elif code.rstrip().endswith(":"):
        lines[number - 1] = indent + "if true:"
    else:
        lines[number - 1] = indent + "stop"
    following = number
    while following < len(lines) and _CONTINUATION.match(lines[following]):
        lines[following] = ""
        following += 1


def parse_offline(text: str, path: str = "<input>") -> n.Program:
    """Parse off-line (`.orl`) text; raise SourceError with every syntax error found (up to MAX_ERRORS)."""
    lines = source_lines(text)
    plan = plan_indentation(lines)
    diagnostics = [Diagnostic(Location(path, p.line, p.column, p.line, p.column + 1), p.message, p.hint) for p in plan.problems]
    if diagnostics:
        raise SourceError(diagnostics, "\n".join(lines))
    postlexer, parse_text = _lark()[1], _parse_once()
    first_source = "\n".join(lines) + "\n" if lines else ""

    def parse_once(source: str) -> n.Program:
        # The first pass parses the text as planned above; a repaired text (after an error) is planned again.
        postlexer.plan = plan if source == first_source else plan_indentation(source.split("\n")[:-1] if source else [])
        tree = parse_text(source)
        if not postlexer.names.isdisjoint(OFFLINE_KEYWORDS):  # only then can a keyword stand as a name in the tree
            check_names(tree)
        return tree

    with paused_gc():
        program = parse_recovering(path, lines, list(lines), diagnostics, parse_once, _offline_diagnostic, _neutralize)
        check_nesting(program, path, lines)
    return program

