"""Parsing: source text -> the expected syntax tree, one row per construct of docs/language.md sections 1-8."""

from __future__ import annotations

import pytest

from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse, parse_statement

N = n.Name
NUM = n.Number


def one(text: str) -> n.Statement:
    return parse_statement(text)


CASES = [
    ("tool", "TOOL grinder = TRANSL(0, 0, 150mm)",
     n.Declaration("TOOL", N("grinder"), n.Call(N("TRANSL"), (n.Argument(None, NUM("0")), n.Argument(None, NUM("0")), n.Argument(None, NUM("150mm")))))),
    ("pos in frame", "POS p = q IN base_plate", n.Declaration("POS", N("p"), N("q"), N("base_plate"))),
    ("frame declaration", "FRAME clamp = p IN base_plate", n.Declaration("FRAME", N("clamp"), N("p"), N("base_plate"))),
    ("const with unit", "CONST Vmax = 1.5mps", n.Declaration("CONST", N("Vmax"), NUM("1.5mps"))),
    ("enum", "ENUM Part = NoObject, Bolt, Nut", n.EnumDecl(N("Part"), (N("NoObject"), N("Bolt"), N("Nut")))),
    ("install", "INSTALL Gun AS SpotGun WITH REACTION = 80ms",
     n.Install(N("Gun"), N("SpotGun"), (n.With(N("REACTION"), NUM("80ms")),))),
    ("motion clauses in any order", "CMOVE t VIA p TO q WITH ZONE = 5mm UNTIL DigIn[1] = 1",
     n.Motion("CMOVE", N("t"), (n.Via((N("p"),)), n.To(N("q")), n.With(N("ZONE"), NUM("5mm")),
                                n.Until(n.Binary("=", n.Index(N("DigIn"), NUM("1")), NUM("1")))))),
    ("continuation lines", "MOVE g TO e\n  WITH SPEED=0.15*mps\n  WITH FORCE=F",
     n.Motion("MOVE", N("g"), (n.To(N("e")), n.With(N("SPEED"), n.Binary("*", NUM("0.15"), N("mps")), new_line=True),
                               n.With(N("FORCE"), N("F"), new_line=True)))),
    ("comment before continuation", "MOVE g TO e -- fast\n  VIA a, b",
     n.Motion("MOVE", N("g"), (n.To(N("e")), n.Via((N("a"), N("b")), new_line=True, line_comment=" fast")))),
    ("any MOVE word is a motion", "GRNDMOVE g ALONG p", n.Motion("GRNDMOVE", N("g"), (n.Along(N("p")),))),
    ("assignment", "x = 2 * y + 1", n.Assign(N("x"), n.Binary("+", n.Binary("*", NUM("2"), N("y")), NUM("1")))),
    ("io assignment", "DigOut[5] = 0", n.Assign(n.Index(N("DigOut"), NUM("5")), NUM("0"))),
    ("field assignment", "rec.field = v", n.Assign(n.Field(N("rec"), N("field")), N("v"))),
    ("call without arguments", "GrinderOff", n.CallStatement(N("GrinderOff"))),
    ("method", "Gripper1.Close", n.CallStatement(n.Field(N("Gripper1"), N("Close")))),
    ("call with keyword", "f(1, tolerance = 0.2mm)",
     n.CallStatement(n.Call(N("f"), (n.Argument(None, NUM("1")), n.Argument(N("tolerance"), NUM("0.2mm")))))),
    ("wait", "WAIT 0.5s", n.Wait(NUM("0.5s"))),
    ("wait until", "WAIT UNTIL DigIn[2] = 1 TIMEOUT 3s",
     n.WaitUntil(n.Binary("=", n.Index(N("DigIn"), NUM("2")), NUM("1")), NUM("3s"))),
    ("print", 'PRINT "cycle done", count', n.Print((n.String("cycle done"), N("count")))),
    ("raise", "RAISE UnknownPart", n.Raise(N("UnknownPart"))),
    ("return value", "RETURN 20N + 10N * s", n.Return(n.Binary("+", NUM("20N"), n.Binary("*", NUM("10N"), N("s"))))),
    ("stop", "STOP", n.Stop()),
    ("precedence", "a = NOT b OR c AND d <> -e", n.Assign(N("a"), n.Binary("OR", n.Unary("NOT", N("b")),
                                                                  n.Binary("AND", N("c"), n.Binary("<>", N("d"), n.Unary("-", N("e"))))))),
    ("list and index", "x = [1, 2, 3][2]", n.Assign(N("x"), n.Index(n.ListExpr((NUM("1"), NUM("2"), NUM("3"))), NUM("2")))),
    ("trailing comment", "STOP  -- done", n.Stop(comment=" done")),
    ("while", "WHILE DigIn[1] = 0 DO\n    WAIT 10ms\nENDWHILE",
     n.While(n.Binary("=", n.Index(N("DigIn"), NUM("1")), NUM("0")), (n.Wait(NUM("10ms")),))),
    ("for with step", "FOR i FROM 1 TO 10 STEP 2 DO\nENDFOR", n.For(N("i"), NUM("1"), NUM("10"), NUM("2"), ())),
    ("frame block", "FRAME base_plate\n    MOVE ARM TO pos1\nENDFRAME",
     n.FrameBlock(N("base_plate"), (n.Motion("MOVE", N("ARM"), (n.To(N("pos1")),)),))),
    ("proc without parentheses", "PROC GrinderOff\n    DigOut[5] = 0\nENDPROC",
     n.Routine("PROC", N("GrinderOff"), (), (n.Assign(n.Index(N("DigOut"), NUM("5")), NUM("0")),), parenthesized=False)),
    ("func", "FUNC ramp(s)\n    RETURN s\nENDFUNC", n.Routine("FUNC", N("ramp"), (N("s"),), (n.Return(N("s")),))),
    ("try", "TRY\n    STOP\nON SeamLost, Timeout : STOP\nENDTRY",
     n.Try((n.Stop(),), (n.Handler((N("SeamLost"), N("Timeout")), n.Stop(), ()),))),
    ("if elsif else", "IF x > 3 THEN\nELSIF x = 3 THEN\n    STOP\nELSE\nENDIF",
     n.If((n.Branch(n.Binary(">", N("x"), NUM("3")), ()), n.Branch(n.Binary("=", N("x"), NUM("3")), (n.Stop(),))), ())),
]


@pytest.mark.parametrize("source, expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_parses_to_tree(source: str, expected: n.Statement) -> None:
    assert one(source) == expected


def test_case_arms_are_grouped_from_label_lines() -> None:
    source = 'CASE Id OF\n    NoObject : PRINT "nothing"\n    Bolt, Nut :\n        MOVE g TO bin\n    ELSE : RAISE UnknownPart\nENDCASE\n'
    case = one(source)
    assert isinstance(case, n.Case)
    assert [arm.labels for arm in case.arms] == [(N("NoObject"),), (N("Bolt"), N("Nut"))]
    assert case.arms[0].inline == n.Print((n.String("nothing"),))
    assert case.arms[1].body == (n.Motion("MOVE", N("g"), (n.To(N("bin")),)),)
    assert case.else_arm is not None and case.else_arm.inline == n.Raise(N("UnknownPart"))


def test_comments_and_blank_lines_are_in_the_tree() -> None:
    program = parse("-- head\n\nSTOP  -- end\n")
    assert program.body == (n.Comment(" head"), n.Blank(), n.Stop(comment=" end"))


def test_spans_point_at_the_statement_and_are_not_compared() -> None:
    program = parse("\n\n  MOVE ARM TO p\n")
    motion = program.body[2]
    assert (motion.span.line, motion.span.column) == (3, 3)
    assert parse("MOVE ARM TO p\n").body[0] == motion


def test_keywords_are_case_sensitive_and_lowercase_words_are_names() -> None:
    assert one("to = 1") == n.Assign(N("to"), NUM("1"))
