"""Hypothesis strategies for programs in odd but legal layouts, in both syntaxes, from one drawn outline.

An outline is a list of statements (some with blocks); every spacing, comment column, parenthesis, blank line and
block indentation is drawn while it is written out, so the same outline gives many layouts.
"""

from __future__ import annotations

from hypothesis import strategies as st

#: What the off-line programs move to (worlds/cell_thesis.yaml) and the on-line programs declare themselves.
OFFLINE_TARGETS = ["pos0", "base_plate.pos1", "base_plate.pos2", "pos3"]
ONLINE_TARGETS = ["p1", "p2"]
ONLINE_HEADER = "POS p1 = POSE(800mm, -300mm, 900mm, 0, 180deg, 0)\nPOS p2 = POSE(1100mm, -200mm, 800mm, 0, 180deg, 0)\n"


class _Writer:
    """Writes an outline in one syntax, drawing every layout choice."""

    def __init__(self, draw, offline: bool) -> None:  # type: ignore[no-untyped-def]
        self.draw = draw
        self.offline = offline
        self.lines: list[str] = []

    def space(self, least: int = 0) -> str:
        return " " * self.draw(st.integers(least, least + 2))

    def parens(self, text: str) -> str:
        for _ in range(self.draw(st.integers(0, 2))):
            text = f"({self.space(0) if self.draw(st.booleans()) else ''}{text})"
        return text

    def comment(self) -> str:
        if not self.draw(st.booleans()):
            return ""
        mark = "#" if self.offline else "--"
        return " " * self.draw(st.integers(1, 12)) + mark + self.draw(st.sampled_from([" note", "", "  aligned", " n = 1"]))

    def line(self, indent: str, text: str) -> None:
        self.lines.append(indent + text + self.comment())

    def extras(self, indent: str) -> None:
        """Blank and comment lines between statements."""
        for _ in range(self.draw(st.integers(0, 2))):
            if self.draw(st.booleans()):
                self.lines.append("")
            else:
                self.lines.append(indent + ("#" if self.offline else "--") + self.draw(st.sampled_from([" c", "", " x = 2"])))

    def expression(self) -> str:
        s = self.space
        left = self.parens("n")
        op = self.draw(st.sampled_from(["+", "*", "-"]))
        return self.parens(f"{left}{s()}{op}{s()}{self.draw(st.integers(0, 9))}")

    def simple(self, indent: str, kind: str) -> None:
        s = self.space
        if kind == "assign":
            self.line(indent, f"n{s()}={s()}{self.expression()}")
        elif kind == "print":
            head = "print(" if self.offline else "PRINT" + s(1)
            tail = ")" if self.offline else ""
            self.line(indent, f'{head}{s()}"n =",{s()}{self.parens("n")}{s()}{tail}')
        elif kind == "wait":
            self.line(indent, f"{'wait' if self.offline else 'WAIT'}{s(1)}0.{self.draw(st.integers(1, 9))}s")
        else:
            targets = OFFLINE_TARGETS if self.offline else ONLINE_TARGETS
            target = self.parens(self.draw(st.sampled_from(targets)))
            head = f"moveto{s(1)}{target}" if self.offline else f"MOVE ARM TO{s(1)}{target}"
            if self.draw(st.booleans()):
                head += f"{s(1)}speed=0.5*1.5mps" if self.offline else f"{s(1)}WITH SPEED{s()}={s()}0.5*1.5mps"
            self.line(indent, head)
            if self.draw(st.booleans()):
                deeper = indent + " " * self.draw(st.integers(1, 6))
                if self.draw(st.booleans()):  # a comment line between a motion and its continuation
                    self.lines.append(deeper + ("# between" if self.offline else "-- between"))
                self.line(deeper, "with accel=50%" if self.offline else f"WITH ACCEL{s()}={s()}{self.parens('50%')}")

    def block(self, indent: str, outline: list) -> None:  # type: ignore[type-arg]
        inner = indent + " " * self.draw(st.sampled_from([1, 2, 3, 4, 8]))
        self.body(inner, outline)

    def body(self, indent: str, outline: list) -> None:  # type: ignore[type-arg]
        s = self.space
        for item in outline:
            self.extras(indent)
            if isinstance(item, str):
                self.simple(indent, item)
                continue
            kind, first, second = item
            if kind == "if":
                condition = self.parens(f"n{s()}{'==' if self.offline else '='}{s()}2")
                self.line(indent, f"if{s(1)}{condition}{s()}:" if self.offline else f"IF{s(1)}{condition}{s(1)}THEN")
                self.block(indent, first)
                if second:
                    if self.draw(st.booleans()):  # a comment before `else` at the if's indentation
                        self.lines.append(indent + ("# before else" if self.offline else "-- before ELSE"))
                    self.line(indent, f"else{s()}:" if self.offline else "ELSE")
                    self.block(indent, second)
                if not self.offline:
                    self.line(indent, "ENDIF")
            else:
                condition = f"n{s()}<{s()}{self.parens('3')}"
                self.line(indent, f"while{s(1)}{condition}{s()}:" if self.offline else f"WHILE{s(1)}{condition}{s(1)}DO")
                self.block(indent, first)
                if not self.offline:
                    self.line(indent, "ENDWHILE")


SIMPLE = st.sampled_from(["assign", "print", "wait", "move"])


def _outlines(depth: int) -> st.SearchStrategy[list]:  # type: ignore[type-arg]
    if depth == 0:
        return st.lists(SIMPLE, min_size=1, max_size=3)
    inner = _outlines(depth - 1)
    compound = st.one_of(st.tuples(st.just("if"), inner, st.one_of(st.just([]), inner)),
                         st.tuples(st.just("while"), inner, st.just([])))
    return st.lists(st.one_of(SIMPLE, compound), min_size=1, max_size=4)


@st.composite
def layouts(draw, offline: bool) -> str:  # type: ignore[no-untyped-def]
    """A program text in a drawn layout: off-line over worlds/cell_thesis.yaml, or on-line declaring its positions."""
    outline = draw(_outlines(2))
    writer = _Writer(draw, offline)
    writer.body("", outline)
    declaration = "var n = 0" if offline else "VAR n = 0"
    text = "\n".join(writer.lines) + "\n"
    if draw(st.booleans()):
        text += "\n" * draw(st.integers(1, 2))
    return (declaration + writer.comment() + "\n" if offline else ONLINE_HEADER + declaration + "\n") + text
