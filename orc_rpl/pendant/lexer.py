"""A Pygments lexer for on-line RPL (`.rpl`), used by the pendant and registered as a Pygments plugin."""

from __future__ import annotations

from pygments.lexer import RegexLexer, bygroups, words
from pygments.token import Comment, Keyword, Name, Number, Operator, Punctuation, String, Text, Whitespace

from orc_rpl.syntax.lexicon import PREDEFINED_NAMES, RESERVED

#: Units a number may carry right after it (docs/language.md).
_UNIT = r"(?:mm/s2|m/s2|deg/s2|rad/s2|mm/s|m/s|deg/s|rad/s|mps|mm|cm|m|deg|rad|ms|s|Nm|N|kg|%)"
_DECLARATIONS = ("TOOL", "POS", "PATH", "VAR", "CONST", "ENUM", "INSTALL")
_CONSTANTS = ("TRUE", "FALSE")
_OPERATORS = ("AND", "OR", "NOT")


class RplLexer(RegexLexer):
    """On-line RPL: motion keywords (any upper-case word ending in MOVE), reserved words, numbers with units,
    `--` comments; a leading `:` word is a pendant command."""

    name = "RPL"
    aliases = ["rpl", "orc-rpl"]
    filenames = ["*.rpl"]
    mimetypes = ["text/x-rpl"]
    url = "https://github.com/orc-rpl/orc_rpl"

    tokens = {
        "root": [
            (r"\n", Whitespace),
            (r"[ \t]+", Whitespace),
            (r"--.*?$", Comment.Single),
            (r"^(:)([a-z!]+)", bygroups(Punctuation, Keyword.Pseudo)),
            (r'"(\\\\|\\"|[^"\n])*"', String.Double),
            (r"(\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)(" + _UNIT + r")?(?![A-Za-z0-9_])",
             bygroups(Number, Keyword.Type)),
            (r"\b(?:[A-Z][A-Z0-9_]*)?MOVE\b", Keyword.Reserved),
            (words(_DECLARATIONS, suffix=r"\b"), Keyword.Declaration),
            (words(_CONSTANTS, suffix=r"\b"), Keyword.Constant),
            (words(_OPERATORS, suffix=r"\b"), Operator.Word),
            (words(tuple(sorted(RESERVED - set(_DECLARATIONS) - set(_CONSTANTS) - set(_OPERATORS))), suffix=r"\b"),
             Keyword),
            (words(tuple(sorted(PREDEFINED_NAMES)), suffix=r"\b"), Name.Builtin),
            (r"[A-Za-z_][A-Za-z0-9_]*", Name),
            (r"<>|<=|>=|[=<>+\-*/]", Operator),
            (r"[()\[\],.:]", Punctuation),
            (r".", Text),
        ],
    }
