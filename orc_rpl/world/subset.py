"""The YAML that world files use, read line by line into the nodes libyaml makes; anything else is left to libyaml.

The subset: block mappings of plain keys (one `key:` per line, a deeper block under a key with no value), block
sequences of `- value` entries (indented under their key or level with it), values that are plain scalars or
one-line flow collections (`[...]`, `{k: v, ...}`) of plain scalars, comments and blank lines; ASCII text without
control characters (tabs and carriage returns among them). The nodes are libyaml's classes with libyaml's tags, styles and marks (a block collection
ends where the next token starts, an empty value is a null scalar just after its colon). On the first line outside
the subset `compose_subset` returns None and libyaml composes the whole text, so its errors are reported as before.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from yaml.nodes import MappingNode, ScalarNode, SequenceNode

_STR, _SEQ, _MAP = "tag:yaml.org,2002:str", "tag:yaml.org,2002:seq", "tag:yaml.org,2002:map"
_NULL = "tag:yaml.org,2002:null"

#: `  key:` at the start of a line: its indentation and its plain key
_KEY = re.compile(r"( *)([A-Za-z0-9_][A-Za-z0-9_.\-]*):(?= |$)")
#: a plain scalar in a flow collection: up to `,` `[` `]` `{` `}`, `: ` or ` #` (trailing blanks dropped after)
_FLOW_PLAIN = re.compile(r"[^,\[\]{}:#\s](?:[^,\[\]{}:#]|:(?=[^ ,\[\]{}])|(?<! )#)*")
#: characters a plain scalar may not start with (YAML indicators), and those that may not start one if a blank follows
_INDICATORS = frozenset("[]{},#&*!|>'\"%@`")
_BEFORE_BLANK = frozenset("-?:")
#: characters libyaml refuses or reads differently (control characters, tabs, carriage returns): its reading then
_CONTROL = re.compile(r"[\x00-\x09\x0b-\x1f\x7f]")


class Mark:
    """Where a node starts or ends: 0-based line and column and the character offset, as libyaml's marks give them."""

    __slots__ = ("line", "column", "index")

    def __init__(self, line: int, column: int, index: int) -> None:
        self.line, self.column, self.index = line, column, index

    def __repr__(self) -> str:
        return f"Mark(line={self.line}, column={self.column})"


class _Outside(Exception):
    """The text leaves the subset: libyaml reads it."""


def _plain_ok(value: str) -> bool:
    """A plain scalar that starts as YAML allows and holds nothing that would end it early."""
    first = value[0]
    if first in _INDICATORS or (first in _BEFORE_BLANK and (len(value) == 1 or value[1] == " ")):
        return False
    return ": " not in value and not value.endswith(":")


class _Frame:
    """An open block collection: its indentation, its node, and for a mapping the key still waiting for its value."""

    __slots__ = ("indent", "node", "indentless", "key", "colon")

    def __init__(self, indent: int, node: MappingNode | SequenceNode, indentless: bool = False) -> None:
        self.indent, self.node, self.indentless = indent, node, indentless
        self.key: ScalarNode | None = None
        self.colon: Mark | None = None


def compose_subset(text: str, tag_of: Callable[[str], str]) -> MappingNode | None:
    """The node tree of a world file's text, or None when the text is outside the subset (libyaml then reads it).

    `tag_of` gives a plain scalar's tag (YAML 1.2 resolution, as the libyaml loader uses).
    """
    if not text.isascii() or _CONTROL.search(text) is not None:
        return None
    try:
        return _Composer(text, tag_of).compose()
    except (_Outside, IndexError):
        return None


class _Composer:
    def __init__(self, text: str, tag_of: Callable[[str], str]) -> None:
        self.text, self.tag_of = text, tag_of
        self.stack: list[_Frame] = []

    def compose(self) -> MappingNode | None:
        text, stack = self.text, self.stack
        root: MappingNode | None = None
        start = 0
        for number, line in enumerate(text.split("\n")):
            content = line.lstrip(" ")
            if not content or content[0] == "#":
                start += len(line) + 1
                continue
            indent = len(line) - len(content)
            if content[0] == "-" and (len(content) == 1 or content[1] == " "):
                self.entry(line, number, start, indent)
            else:
                found = _KEY.match(line)
                if found is None:
                    raise _Outside
                if root is None:
                    if indent:
                        raise _Outside
                    root = MappingNode(_MAP, [], Mark(number, 0, start), None, flow_style=False)
                    stack.append(_Frame(0, root))
                self.key_line(line, number, start, indent, found)
            start += len(line) + 1
        if root is None:
            return None
        # The end of the text, as libyaml ends collections there: those indented deeper than the text's last column
        # where it stops (a last line without a line break), then the rest at the start of a line after it.
        line, column = text.count("\n"), len(text) - text.rfind("\n") - 1
        self.close_to(column, Mark(line, column, len(text)), sequences_level=False)
        self.close_all(Mark(line + (column > 0), 0, len(text)))
        return root

    # ---- lines
    def key_line(self, line: str, number: int, start: int, indent: int, found: re.Match[str]) -> None:
        stack = self.stack
        here = Mark(number, indent, start + indent)
        top = stack[-1]
        if top.key is not None and indent > top.indent and not top.indentless:
            node = MappingNode(_MAP, [], here, None, flow_style=False)
            self.give(top, node)
            stack.append(_Frame(indent, node))
        else:
            self.close_to(indent, here, sequences_level=True)
            top = stack[-1] if stack else None
            if top is None or type(top.node) is not MappingNode or top.indent != indent:
                raise _Outside
            if top.key is not None:
                self.give(top, self.null(top))
        frame = stack[-1]
        name = found.group(2)
        key_end = found.end(2)
        frame.key = ScalarNode(self.tag_of(name), name, here, Mark(number, key_end, start + key_end), "")
        frame.colon = Mark(number, key_end + 1, start + key_end + 1)
        value = self.value(line, number, start, key_end + 1)
        if value is not None:
            self.give(frame, value)

    def entry(self, line: str, number: int, start: int, indent: int) -> None:
        stack = self.stack
        here = Mark(number, indent, start + indent)
        top = stack[-1] if stack else None
        if top is None:
            raise _Outside
        if top.key is not None and indent >= top.indent and not top.indentless:
            node = SequenceNode(_SEQ, [], here, None, flow_style=False)
            self.give(top, node)
            stack.append(_Frame(indent, node, indentless=indent == top.indent))
        else:
            self.close_to(indent, here, sequences_level=False)
            top = stack[-1] if stack else None
            if top is None or type(top.node) is not SequenceNode or top.indent != indent:
                raise _Outside
        value = self.value(line, number, start, indent + 1)
        if value is None:
            raise _Outside  # `-` alone, or a block under it
        stack[-1].node.value.append(value)

    def value(self, line: str, number: int, start: int, column: int) -> ScalarNode | SequenceNode | MappingNode | None:
        """The value written on the line from `column` on (after `key:` or `-`), None when there is none."""
        rest = line[column:]
        if rest and rest[0] != " ":
            raise _Outside
        stripped = rest.lstrip(" ")
        if not stripped or stripped[0] == "#":
            return None
        at = len(line) - len(stripped)
        if stripped[0] in "[{":
            node, end = self.flow(line, number, start, at)
            tail = line[end:]
            if tail.strip(" ") and not tail.lstrip(" ").startswith("#") or tail[:1] == "#":
                raise _Outside
            return node
        cut = stripped.find(" #")
        plain = (stripped if cut < 0 else stripped[:cut]).rstrip(" ")
        if not _plain_ok(plain):
            raise _Outside
        return ScalarNode(self.tag_of(plain), plain, Mark(number, at, start + at), Mark(number, at + len(plain), start + at + len(plain)), "")

    def flow(self, line: str, number: int, start: int, at: int) -> tuple[SequenceNode | MappingNode, int]:
        """The flow collection opening at column `at`, and the column after its closing bracket."""
        opening = line[at]
        closing = "]" if opening == "[" else "}"
        items: list = []
        p = at + 1
        while line[p] == " ":
            p += 1
        if line[p] == closing:
            p += 1
        else:
            while True:
                item, p = self.flow_item(line, number, start, p)
                if opening == "{":
                    if line[p] != ":" or line[p + 1] != " " or type(item) is not ScalarNode:
                        raise _Outside
                    p += 2
                    while line[p] == " ":
                        p += 1
                    value, p = self.flow_item(line, number, start, p)
                    items.append((item, value))
                else:
                    items.append(item)
                while line[p] == " ":
                    p += 1
                if line[p] == closing:
                    p += 1
                    break
                if line[p] != ",":
                    raise _Outside
                p += 1
                while line[p] == " ":
                    p += 1
                if line[p] in ",]}":
                    raise _Outside  # an empty entry or a trailing comma
        kind = SequenceNode if opening == "[" else MappingNode
        return kind(_SEQ if opening == "[" else _MAP, items, Mark(number, at, start + at), Mark(number, p, start + p),
                    flow_style=True), p

    def flow_item(self, line: str, number: int, start: int, p: int) -> tuple[ScalarNode | SequenceNode | MappingNode, int]:
        if line[p] in "[{":
            return self.flow(line, number, start, p)
        found = _FLOW_PLAIN.match(line, p)
        if found is None:
            raise _Outside
        plain = found.group().rstrip(" ")
        if not _plain_ok(plain):
            raise _Outside
        end = p + len(plain)
        return ScalarNode(self.tag_of(plain), plain, Mark(number, p, start + p), Mark(number, end, start + end), ""), end

    # ---- the stack of open block collections
    def null(self, frame: _Frame) -> ScalarNode:
        return ScalarNode(_NULL, "", frame.colon, frame.colon, "")

    def give(self, frame: _Frame, value: ScalarNode | SequenceNode | MappingNode) -> None:
        frame.node.value.append((frame.key, value))
        frame.key = None

    def close_to(self, indent: int, here: Mark, sequences_level: bool) -> None:
        """Close the collections deeper than `indent` (and, before a key, a sequence level with it) at `here`."""
        stack = self.stack
        while stack:
            top = stack[-1]
            if top.indent > indent or (sequences_level and top.indent == indent and type(top.node) is SequenceNode):
                if top.key is not None:
                    self.give(top, self.null(top))
                top.node.end_mark = here
                stack.pop()
            else:
                return

    def close_all(self, end: Mark) -> None:
        while self.stack:
            top = self.stack.pop()
            if top.key is not None:
                self.give(top, self.null(top))
            top.node.end_mark = end
