"""World-file text and its YAML node tree: positions of every node, for messages and for exact text edits."""

from __future__ import annotations

import bisect
import difflib
import re
import warnings
from dataclasses import dataclass, field

from ruamel.yaml import YAML
from ruamel.yaml import nodes as _rt_nodes
from ruamel.yaml.error import MarkedYAMLError
from ruamel.yaml.reader import ReaderError
from ruamel.yaml.resolver import implicit_resolvers as _RT_IMPLICIT

from orc_rpl.errors import Diagnostic, Location, SourceError

try:  # libyaml through PyYAML composes a large world about twenty times faster than ruamel's pure-Python parser
    import yaml as _libyaml
    from yaml.cyaml import CParser as _CParser
except (ImportError, AttributeError):  # PyYAML without libyaml: ruamel alone
    _libyaml = None

#: Where an anchor or an alias could start (after a blank, a flow indicator or at a line start); a text without one
#: has none (a `*` inside a word, as in a comment `ARM*holder`, is not one).
_MAYBE_ANCHOR = re.compile(r"(?:^|[\s\[\]{},:-])[&*][^\s,\[\]{}]", re.MULTILINE)

#: A top-level `robot:` or `world:` key at the start of a line.
_WORLD_KEY = re.compile(r"^(robot|world)\s*:", re.MULTILINE)

#: Deepest nesting of flow collections (`[[[...]]]`) or indentation levels a world or sidecar may have;
#: ruamel composes recursively and would exhaust Python's stack long before a real file gets near this.
MAX_YAML_NESTING = 50


def too_deep(text: str) -> tuple[int, int] | None:
    """1-based (line, column) where flow brackets or indentation nest deeper than MAX_YAML_NESTING, or None."""
    for line_number, line in enumerate(text.splitlines(), start=1):
        indent = len(line) - len(line.lstrip(" -"))
        if indent > 2 * MAX_YAML_NESTING:
            return line_number, indent + 1
    depth, line_number, line_start, quote = 0, 1, 0, ""
    for match in _STRUCTURE.finditer(text):  # only the characters that matter, found by the regex engine
        char = match.group()
        if char == "\n":
            line_number, line_start, quote = line_number + 1, match.end(), ""
        elif quote:
            quote = "" if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char == "#":
            quote = "\n"  # a comment runs to the end of the line
        elif char in "[{":
            depth += 1
            if depth > MAX_YAML_NESTING:
                return line_number, match.end() - line_start
        else:
            depth = max(0, depth - 1)
    return None


#: The characters too_deep looks at.
_STRUCTURE = re.compile(r"[\n'\"#\[\]{}]")


__all__ = ["MAX_YAML_NESTING", "MappingNode", "too_deep", "Node", "ScalarNode", "SequenceNode", "SourceText", "did_you_mean", "find"]


class _NodeKind(type):
    """`isinstance` by the concrete class of either parser's node: a set lookup (an ABC's registry walk is slower)."""

    classes: frozenset[type]

    def __instancecheck__(cls, obj: object) -> bool:
        return type(obj) in cls.classes


def _both(name: str) -> frozenset[type]:
    """The node class of that name in ruamel and, when it is there, in PyYAML."""
    return frozenset({getattr(_rt_nodes, name), *([getattr(_libyaml.nodes, name)] if _libyaml is not None else [])})


class Node(metaclass=_NodeKind):
    """A YAML node as either parser makes it: `value`, `tag`, `style`, `flow_style`, `start_mark`, `end_mark`."""

    classes = _both("ScalarNode") | _both("SequenceNode") | _both("MappingNode")


class ScalarNode(metaclass=_NodeKind):
    """A scalar node."""

    classes = _both("ScalarNode")


class SequenceNode(metaclass=_NodeKind):
    """A sequence node."""

    classes = _both("SequenceNode")


class MappingNode(metaclass=_NodeKind):
    """A mapping node: `value` is a list of (key, value) node pairs."""

    classes = _both("MappingNode")


if _libyaml is not None:
    class _Yaml12Loader(_CParser, _libyaml.resolver.BaseResolver):  # type: ignore[misc, name-defined]
        """libyaml's parser with the YAML 1.2 tags ruamel gives (`yes` is a string, `010` is ten), so both agree."""

        yaml_implicit_resolvers: dict = {}

        def __init__(self, text: str) -> None:
            _CParser.__init__(self, text)
            _libyaml.resolver.BaseResolver.__init__(self)

    #: first character -> (tag, compiled pattern), YAML 1.2 as ruamel resolves it (ruamel's patterns are lazy proxies)
    _IMPLICIT: dict[str, list[tuple[str, re.Pattern[str]]]] = {}
    for _versions, _tag, _regexp, _first in _RT_IMPLICIT:
        if (1, 2) in _versions:
            for _char in _first:
                _IMPLICIT.setdefault(_char, []).append((_tag, re.compile(_regexp.pattern, _regexp.flags)))

    _SCALAR, _SEQUENCE = _libyaml.nodes.ScalarNode, _libyaml.nodes.SequenceNode
    _STR, _SEQ, _MAP = (_libyaml.resolver.BaseResolver.DEFAULT_SCALAR_TAG, _libyaml.resolver.BaseResolver.DEFAULT_SEQUENCE_TAG,
                        _libyaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG)
    _TAGS: dict[str, str] = {}   #: plain scalar text -> its tag (world files repeat the same numbers thousands of times)

    def _resolve(self, kind: type, value: str, implicit: tuple[bool, bool]) -> str:  # type: ignore[no-untyped-def]
        """The node's tag: implicit scalars by the YAML 1.2 patterns, everything else by its kind (no path resolvers)."""
        if kind is _SCALAR:
            if not implicit[0]:
                return _STR
            tag = _TAGS.get(value)
            if tag is None:
                tag = next((t for t, pattern in _IMPLICIT.get(value[:1], ()) if pattern.match(value)), _STR)
                if len(_TAGS) < 65536:
                    _TAGS[value] = tag
            return tag
        return _SEQ if kind is _SEQUENCE else _MAP

    _Yaml12Loader.resolve = _resolve  # type: ignore[method-assign]


@dataclass(frozen=True)
class SourceText:
    """The exact text of a world file, its name, and the offsets of its lines."""

    text: str
    path: str
    _starts: tuple[int, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        starts = [0]
        for line in self.text.splitlines(keepends=True):
            starts.append(starts[-1] + len(line))
        object.__setattr__(self, "_starts", tuple(starts))

    @property
    def newline(self) -> str:
        """The line ending the file uses, so inserted lines match it."""
        return "\r\n" if "\r\n" in self.text else "\n"

    def index(self, line0: int, column0: int) -> int:
        """Character offset of a 0-based line and column (as ruamel marks count them)."""
        if line0 >= len(self._starts) - 1:
            return len(self.text)
        return self._starts[line0] + column0

    def line_end(self, line0: int) -> int:
        """Offset just after the line break of a 0-based line (end of text for the last line)."""
        return self._starts[min(line0 + 1, len(self._starts) - 1)]

    def line(self, line0: int) -> str:
        """A 0-based line without its line break."""
        lines = self.text.splitlines()
        return lines[line0] if 0 <= line0 < len(lines) else ""

    def location(self, node: Node) -> Location:
        """The span of a node: its first line and column, and where it ends on that line."""
        start, end = node.start_mark, node.end_mark
        end_column = end.column + 1 if end.line == start.line else 0
        return Location(self.path, start.line + 1, start.column + 1, 0, end_column)

    def diagnostic(self, node: Node | None, message: str, hint: str = "") -> Diagnostic:
        """A diagnostic at a node (at the top of the file when there is none)."""
        loc = self.location(node) if node is not None else Location(self.path, 1, 1)
        return Diagnostic(loc, message, hint, source_line=self.line(loc.line - 1))

    def error(self, node: Node | None, message: str, hint: str = "") -> SourceError:
        """A SourceError with one diagnostic at a node."""
        return SourceError([self.diagnostic(node, message, hint)], self.text)

    def compose(self) -> Node | None:
        """The YAML node tree; a syntax error becomes a SourceError at ruamel's mark.

        libyaml composes when it can: a text without anchors or aliases (refused with ruamel's positions)
        that it parses without error (errors are reported with ruamel's words, as always).
        """
        deep = too_deep(self.text)
        if deep is not None:
            raise SourceError([Diagnostic(Location(self.path, deep[0], deep[1]),
                                          f"nested too deeply (more than {MAX_YAML_NESTING} levels)")],
                              self.text if self.looks_like_world() else None)
        if _libyaml is not None and _MAYBE_ANCHOR.search(self.text) is None:
            loader = _Yaml12Loader(self.text)
            try:
                return loader.get_single_node()
            except _libyaml.YAMLError:
                pass  # ruamel reports it
            finally:
                loader.dispose()
        try:
            with warnings.catch_warnings():  # anchors are reported as errors of their own (loader.check_no_anchors)
                warnings.simplefilter("ignore")
                return YAML(typ="rt").compose(self.text)
        except ReaderError as exc:  # a control character or a byte YAML does not allow
            line0, col0 = self.position(exc.position)
            where = Location(self.path, line0 + 1, col0 + 1)
            message = f"character #x{exc.character:04x} is not allowed in a YAML file" if isinstance(exc.character, int) else "unreadable YAML text"
            raise SourceError([Diagnostic(where, message, "write it as an escape in a quoted string (\"\\x07\")")],
                              self.text if self.looks_like_world() else None) from None
        except RecursionError:
            raise SourceError([Diagnostic(Location(self.path, 1, 1), "nested too deeply")]) from None
        except MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line0, col0 = (mark.line, mark.column) if mark is not None else (0, 0)
            message = f"YAML syntax error: {exc.problem or exc.context}"
            loc = Location(self.path, line0 + 1, col0 + 1)
            hint = f"{exc.context} (line {exc.context_mark.line + 1})" if exc.context and exc.context_mark and exc.problem else ""
            if not self.looks_like_world():  # never show the lines of a file that is not a world (`# world: /etc/shadow`)
                raise self.not_a_world() from None
            raise SourceError([Diagnostic(loc, message, hint, source_line=self.line(line0))], self.text) from None

    def position(self, offset: int) -> tuple[int, int]:
        """0-based line and column of a character offset."""
        line0 = max(0, bisect.bisect_right(self._starts, offset) - 1)
        return line0, offset - self._starts[line0]

    def looks_like_world(self) -> bool:
        """True when a line starts with the key `robot:` or `world:` (what every world file has)."""
        return _WORLD_KEY.search(self.text) is not None

    def not_a_world(self) -> SourceError:
        """The error for a file that is not a world model; it quotes nothing of the file."""
        return SourceError([Diagnostic(Location(self.path, 1, 1), "not a world model: a world file is a YAML mapping "
                                       "with the keys 'robot' and 'world'")], None)

    def last_line(self, node: Node) -> int:
        """The 0-based last line that holds text of the node (a block collection ends where the next token starts)."""
        if isinstance(node, (MappingNode, SequenceNode)) and not node.flow_style and node.value:
            last = node.value[-1]
            return self.last_line(last[1] if isinstance(last, tuple) else last)
        end = node.end_mark
        if isinstance(node, ScalarNode) and node.style in ("|", ">") and end.column == 0:
            return end.line - 1
        return end.line

    def text_of(self, node: Node) -> str:
        """The exact source text of a node."""
        return self.text[self.index(node.start_mark.line, node.start_mark.column) : self.index(node.end_mark.line, node.end_mark.column)]


def find(node: MappingNode, key: str) -> tuple[ScalarNode, Node] | None:
    """The (key, value) nodes of a key in a mapping, or None."""
    for k, v in node.value:
        if isinstance(k, ScalarNode) and k.value == key:
            return k, v
    return None


def did_you_mean(name: str, candidates: list[str] | set[str]) -> str:
    """A 'did you mean' hint for a misspelt name, or an empty string."""
    close = difflib.get_close_matches(name, sorted(candidates), n=1, cutoff=0.6)
    return f"did you mean '{close[0]}'?" if close else ""
