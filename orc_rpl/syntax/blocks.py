"""Block structure of on-line text, line by line: finds block keywords that close nothing or are never closed."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

#: Opening keyword -> the keyword that closes it.
CLOSERS = {
    "IF": "ENDIF",
    "WHILE": "ENDWHILE",
    "FOR": "ENDFOR",
    "CASE": "ENDCASE",
    "FRAME": "ENDFRAME",
    "TRY": "ENDTRY",
    "PROC": "ENDPROC",
    "FUNC": "ENDFUNC",
}
OPENER_OF = {closer: opener for opener, closer in CLOSERS.items()}
#: Keywords in the middle of a block, and the blocks they may stand in.
MIDDLES = {"ELSIF": ("IF",), "ELSE": ("IF", "CASE"), "ON": ("TRY",)}

#: A neutral header of each kind, used to keep the structure when a header line has a syntax error.
NEUTRAL_HEADERS = {
    "IF": "IF TRUE THEN",
    "WHILE": "WHILE FALSE DO",
    "FOR": "FOR orc_ FROM 1 TO 1 DO",
    "CASE": "CASE 0 OF",
    "FRAME": "FRAME world",
    "TRY": "TRY",
    "PROC": "PROC orc_",
    "FUNC": "FUNC orc_()",
    "ELSIF": "ELSIF TRUE THEN",
    "ELSE": "ELSE",
    "ON": "ON orc_ :",
}

_FIRST_WORD = re.compile(r"[ \t]*([A-Z]+)\b")
_FRAME_BLOCK = re.compile(r"[ \t]*FRAME[ \t]+[A-Za-z_][A-Za-z0-9_]*[ \t]*(--.*)?$")


@dataclass
class BlockProblem:
    """A block keyword out of place, with the 1-based line and column of the keyword."""

    line: int
    column: int
    length: int
    message: str
    hint: str = ""


@dataclass
class _Open:
    keyword: str
    line: int
    column: int
    middles: list[int] = field(default_factory=list)


def block_keyword(line_text: str) -> tuple[str, int] | None:
    """The block keyword a line starts with and its 1-based column, or None."""
    match = _FIRST_WORD.match(line_text)
    if match is None:
        return None
    word = match.group(1)
    if word == "FRAME" and not _FRAME_BLOCK.match(line_text):
        return None  # `FRAME name = ...` is a declaration
    if word in CLOSERS or word in OPENER_OF or word in MIDDLES:
        return word, match.start(1) + 1
    return None


def check_blocks(lines: list[str]) -> tuple[list[BlockProblem], set[int]]:
    """Problems in the block structure, and the (1-based) lines to blank so the rest can still be parsed."""
    problems: list[BlockProblem] = []
    blank: set[int] = set()
    stack: list[_Open] = []

    def abandon(block: _Open) -> None:
        blank.add(block.line)
        blank.update(block.middles)

    for number, text in enumerate(lines, start=1):
        found = block_keyword(text)
        if found is None:
            continue
        word, column = found
        if word in CLOSERS:
            stack.append(_Open(word, number, column))
        elif word in MIDDLES:
            if stack and stack[-1].keyword in MIDDLES[word]:
                stack[-1].middles.append(number)
            else:
                owners = " or ".join(MIDDLES[word])
                where = f"inside {stack[-1].keyword} (line {stack[-1].line})" if stack else "outside every block"
                problems.append(BlockProblem(number, column, len(word), f"'{word}' stands {where}; it belongs to {owners}"))
                blank.add(number)
        else:
            opener = OPENER_OF[word]
            if not stack:
                problems.append(BlockProblem(number, column, len(word), f"'{word}' closes nothing: no {opener} block is open"))
                blank.add(number)
            elif stack[-1].keyword == opener:
                stack.pop()
            elif any(block.keyword == opener for block in stack):
                inner = stack[-1]
                problems.append(
                    BlockProblem(
                        number, column, len(word),
                        f"'{word}' found while {inner.keyword} (line {inner.line}) is still open",
                        hint=f"close the {inner.keyword} of line {inner.line} with {CLOSERS[inner.keyword]} first",
                    )
                )
                while stack[-1].keyword != opener:
                    abandon(stack.pop())
                stack.pop()
            else:
                inner = stack[-1]
                problems.append(
                    BlockProblem(
                        number, column, len(word),
                        f"'{word}' closes nothing: the innermost open block is {inner.keyword} (line {inner.line})",
                        hint=f"did you mean {CLOSERS[inner.keyword]}?",
                    )
                )
                blank.add(number)
    for block in reversed(stack):
        problems.append(
            BlockProblem(
                block.line, block.column, len(block.keyword),
                f"{block.keyword} is never closed: expected {CLOSERS[block.keyword]} before the end of the file",
            )
        )
        abandon(block)
    problems.sort(key=lambda p: (p.line, p.column))
    return problems, blank
