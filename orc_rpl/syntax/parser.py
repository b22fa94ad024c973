"""On-line text -> syntax tree: the Lark parser, its errors translated to `file:line:col` diagnostics, recovery per line."""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable
from functools import lru_cache
from typing import TypeVar

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from orc_rpl.errors import Diagnostic, Location, SourceError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.blocks import NEUTRAL_HEADERS, block_keyword, check_blocks
from orc_rpl.syntax.builder import BuildError, TreeBuilder
from orc_rpl.syntax.fast_lexer import speed_up
from orc_rpl.syntax.grammar_files import grammar_path, parser_cache
from orc_rpl.syntax.bulk import paused_gc
from orc_rpl.syntax.lalr import fast_parse
from orc_rpl.syntax.lexicon import RESERVED, is_reserved
from orc_rpl.syntax.limits import check_nesting

T = TypeVar("T")

#: At most this many syntax errors are reported per file (later ones are usually consequences).
MAX_ERRORS = 50

#: How terminals are named in messages.
_TERMINAL_NAMES = {
    "_NL": "end of line",
    "$END": "end of file",
    "NAME": "a name",
    "NUMBER": "a number",
    "STRING": "a string",
    "MOTION_KW": "a motion keyword",
    "EQUAL": "'='",
    "COMMA": "','",
    "COLON": "':'",
    "DOT": "'.'",
    "LPAR": "'('",
    "RPAR": "')'",
    "LSQB": "'['",
    "RSQB": "']'",
    "COMP_OP": "a comparison",
    "ADD_OP": "'+' or '-'",
    "MUL_OP": "'*' or '/'",
    "_AND": "AND",
    "_OR": "OR",
}
_HIDDEN = {"COMMENT", "CONT"}
_CONTINUATION = re.compile(r"[ \t]*(WITH|VIA|UNTIL)\b")


@lru_cache(maxsize=None)
def _parse_once() -> Callable[[str], n.Program]:
    """The on-line parser's `parse`, on its fast loop (Lark itself for errors)."""
    return fast_parse(_lark())


@lru_cache(maxsize=None)
def _lark() -> Lark:
    """The on-line parser, built once per process (its lexer's common case sped up: same tokens, same errors)."""
    return speed_up(Lark(
        grammar_path("rpl.lark").read_text(encoding="utf-8"),
        parser="lalr",
        lexer="contextual",
        start="program",
        maybe_placeholders=True,
        cache=parser_cache("rpl"),
        transformer=TreeBuilder(),
    ))


def describe_token(token: Token) -> str:
    """A token as a message shows it."""
    if token.type in ("_NL", "$END"):
        return _TERMINAL_NAMES[token.type]
    if token.type == "NAME":
        return f"name '{token}'"
    if token.type == "NUMBER":
        return f"number {token}"
    if token.type == "STRING":
        return f"string {token}"
    if token.type == "CONT":
        return "continuation line"
    return f"'{token}'"


def describe_expected(expected: set[str]) -> str:
    """The expected terminals as words: `TO, ALONG, VIA, WITH or UNTIL`."""
    words = sorted({_TERMINAL_NAMES.get(t, f"'{t.lstrip('_')}'" if t.isupper() else t) for t in expected if t not in _HIDDEN})
    if not words:
        return ""
    if len(words) > 8:
        return "a different word here"
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


def _diagnostic(path: str, error: Exception, lines: list[str]) -> tuple[Diagnostic, int]:
    """The user's message for a Lark or tree-building error, and the line it is on."""
    if isinstance(error, BuildError):
        span = error.span
        loc = Location(path, span.line, span.column, span.end_line, span.end_column)
        return Diagnostic(loc, error.message, error.hint), span.line
    if isinstance(error, UnexpectedToken):
        token = error.token
        line, column = token.line or len(lines), token.column or 1
        if token.type == "$END":
            line, column = len(lines), len(lines[-1]) + 1 if lines else 1
        width = len(str(token)) if token.type not in ("_NL", "$END") else 1
        expected = describe_expected(set(error.expected))
        message = f"unexpected {describe_token(token)}" + (f"; expected {expected}" if expected else "")
        hint = ""
        unknown = _unknown_first_word(lines, line, column)
        if unknown is not None:
            return Diagnostic(Location(path, line, unknown[1], line, unknown[1] + len(unknown[0])), unknown[2]), line
        if token.type == "CONT":
            # Point at the WITH/VIA/UNTIL word that starts the continuation line.
            line, column = token.end_line or line, token.end_column or column
            keyword = lines[line - 1][column - 1:].split()[0] if 0 < line <= len(lines) else "WITH"
            width = len(keyword)
            message = f"a line starting with {keyword} continues only a motion or an INSTALL statement"
        return Diagnostic(Location(path, line, column, line, column + width), message, hint), line
    if isinstance(error, UnexpectedCharacters):
        char = lines[error.line - 1][error.column - 1] if 0 < error.line <= len(lines) and error.column <= len(lines[error.line - 1]) else "?"
        message = f"unexpected character {char!r}"
        if char == '"':
            message = "string is not closed before the end of the line"
        return Diagnostic(Location(path, error.line, error.column, error.line, error.column + 1), message), error.line
    if isinstance(error, UnexpectedEOF):
        line = len(lines)
        return Diagnostic(Location(path, line, 1), "unexpected end of file"), line
    raise error


#: The motion keywords of the language itself, for did-you-mean before any registry is known.
_STANDARD_MOTIONS = ("MOVE", "JMOVE", "LMOVE", "CMOVE")
_FIRST_WORDS = re.compile(r"[ \t]*([A-Z][A-Z0-9_]*)[ \t]+([A-Za-z_][A-Za-z0-9_]*)(?:[ \t]+([A-Z]+))?")


def _unknown_first_word(lines: list[str], line: int, column: int) -> tuple[str, int, str] | None:
    """A misspelt statement word (`MOVEE grinder TO p`): the parse fails at the second word, the mistake is the first.

    Returns the word, its column and the message, or None when the line does not look like that.
    """
    if not 0 < line <= len(lines):
        return None
    found = _FIRST_WORDS.match(lines[line - 1])
    if found is None or found.start(2) + 1 != column or is_reserved(found.group(1)):
        return None
    word = found.group(1)
    if found.group(3) in ("TO", "ALONG", "VIA", "WITH"):
        others = {w for text in lines for w in re.findall(r"\b[A-Z][A-Z0-9_]*MOVE\b", text)}
        guess = difflib.get_close_matches(word, sorted({*_STANDARD_MOTIONS, *others}), n=1, cutoff=0.6)
        return word, found.start(1) + 1, f"unknown motion keyword '{word}'" + (f"; did you mean '{guess[0]}'?" if guess else
                                                                               "; a motion keyword ends in MOVE")
    guess = difflib.get_close_matches(word, sorted(RESERVED), n=1, cutoff=0.75)
    if guess:
        return word, found.start(1) + 1, f"unknown word '{word}'; did you mean '{guess[0]}'?"
    return None


def _neutralize(lines: list[str], number: int) -> None:
    """Make line `number` (1-based) harmless while keeping the block structure and every line number."""
    found = block_keyword(lines[number - 1])
    if found is not None and found[0] in NEUTRAL_HEADERS:
        lines[number - 1] = NEUTRAL_HEADERS[found[0]]
    elif found is not None:
        return  # a closer or middle that the structure check accepted: keep it
    else:
        lines[number - 1] = ""
    following = number
    while following < len(lines) and _CONTINUATION.match(lines[following]):
        lines[following] = ""
        following += 1


def source_lines(text: str) -> list[str]:
    """The lines of a program text as both parsers read it: CRLF as LF (fmt writes LF), tabs as four spaces, no BOM."""
    if "\r" in text:
        text = text.replace("\r\n", "\n")
    if "\t" in text:
        text = text.expandtabs(4)
    if text.startswith("\ufeff"):
        text = text[1:]
    if text and not text.endswith("\n"):
        text += "\n"
    return text.split("\n")[:-1] if text else []


def parse_recovering(
    path: str,
    lines: list[str],
    work: list[str],
    diagnostics: list[Diagnostic],
    parse_once: Callable[[str], T],
    diagnose: Callable[[str, Exception, list[str]], tuple[Diagnostic, int]],
    neutralize: Callable[[list[str], int], None],
) -> T:
    """Parse `work`; after each error, make its line harmless and parse again, so one run reports every bad line.

    `lines` is the text as written (for messages), `work` the copy being repaired, `diagnostics` what is
    already known to be wrong. Raises SourceError with all diagnostics in file order.
    """
    seen_lines: set[int] = set()
    while True:
        source = "\n".join(work) + "\n" if work else ""
        try:
            tree = parse_once(source)
        except (UnexpectedInput, BuildError) as error:
            diagnostic, line = diagnose(path, error, lines)
            if line in seen_lines or len(diagnostics) >= MAX_ERRORS or not 1 <= line <= len(work):
                if line not in seen_lines:
                    diagnostics.append(diagnostic)
                break
            seen_lines.add(line)
            diagnostics.append(diagnostic)
            neutralize(work, line)
            continue
        if diagnostics:
            break
        return tree
    diagnostics.sort(key=lambda d: (d.location.line, d.location.column))
    raise SourceError(diagnostics, "\n".join(lines))


def parse(text: str, path: str = "<input>") -> n.Program:
    """Parse on-line RPL text; raise SourceError with every syntax error found (up to MAX_ERRORS)."""
    lines = source_lines(text)
    problems, to_blank = check_blocks(lines)
    diagnostics = [
        Diagnostic(Location(path, p.line, p.column, p.line, p.column + p.length), p.message, p.hint) for p in problems
    ]
    work = list(lines)
    for number in to_blank:
        work[number - 1] = ""
    with paused_gc():
        program = parse_recovering(path, lines, work, diagnostics, _parse_once(), _diagnostic, _neutralize)
        check_nesting(program, path, lines)
    return program


def parse_statement(text: str, path: str = "<input>") -> n.Statement:
    """Parse one statement as typed at the pendant (a whole block is one statement too)."""
    program = parse(text, path)
    statements = [s for s in program.body if not isinstance(s, (n.Blank, n.Comment))]
    if len(statements) != 1:
        raise SourceError([Diagnostic(Location(path, 1, 1), f"expected one statement, found {len(statements)}")], text)
    return statements[0]
