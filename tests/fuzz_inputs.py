"""Seeded hostile inputs for the fuzz tests and benchmarks/bench_fuzz.py: programs, worlds, sidecars, pendant lines.

Each generator takes a `random.Random` and mutates real files of the repository (programs/, worlds/)
with what a careless or hostile user writes: deep nesting, huge or non-finite numbers, URL ports,
control characters, stray block ends, YAML values of the wrong type. The same seed gives the same input.
"""

from __future__ import annotations

import random
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Hostile fragments of program text (numbers, strings, ports, block words, bytes).
PROGRAM_TOKENS = (
    "IF", "THEN", "ELSE", "ENDIF", "WHILE", "DO", "ENDWHILE", "FOR", "FROM", "TO", "STEP", "ENDFOR", "CASE", "OF",
    "ENDCASE", "TRY", "ON", "ENDTRY", "PROC", "ENDPROC", "FUNC", "ENDFUNC", "RETURN", "FRAME", "ENDFRAME", "MOVE",
    "LMOVE", "WITH", "TIME", "SPEED", "VIA", "UNTIL", "WAIT", "PRINT", "INSTALL", "AS", "PORT", "VAR", "CONST", "POS",
    "TOOL", "HERE", "ARM", "AND", "OR", "NOT", "=", "==", "<>", "+", "-", "*", "/", "(", ")", "[", "]", ",", ".", ":",
    "1e999", "1e308", "1e-300", "1e300", "9" * 4400, "9" * 400 + "mm", "1e400mm", "0.5mm", "100mm/s", "1e9s", "90deg", "50%", "-0", "0x1F", ".nan",
    '"spy://loop://?file=/tmp/x"', '"socket://127.0.0.1:9"', '"/dev/zero"', '"/etc/shadow"', '"sim"', '"\\x07"',
    '"unterminated', "\t", "\r", "\x00", "\x07", "\u202e", "é", "__class__", "__import__", "DigOut[3]", "DigIn[99]",
    "POSE(1, 2, 3, 0, 0, 0)", "# world: /etc/passwd", "move", "to", "for", "in", "1..5", "print(", "install",
)

#: Hostile YAML values for worlds and sidecars.
YAML_VALUES = (
    ".nan", ".inf", "-.inf", ".NaN", "0x1F", "0o17", "0b101", "1e999", "-1e999", "9" * 4400, "[1m]", "[1m, 0, 0]",
    "[.nan, 0, 0]", "{a: 1}", "[]", "{}", "", "~", "null", "true", "yes", "\"\\x07\"", "\x07", "\x1b[31m", "1mm/s",
    "90deg", "300mm", "-0", "&a 1", "*a", "!!python/object/apply:os.system ['true']", "!!binary aGVsbG8=", "|", ">",
    "'unterminated", "\"\\u0000\"", "[" * 60 + "]" * 60, "{" * 60 + "}" * 60, "2026-01-01", "12:30:00", "@", "`",
    "[0, 0, 0, 0, 0]", "[0, 0, 0, 0, 0, 0, 0]", "[a, b, c, d, e, f]", "box", "mesh", "flange", "world", "robot",
)

PENDANT_COMMANDS = (
    ":jog joint 1 5deg", ":jog joint 9 5deg", ":jog world x 10mm", ":jog tool z -1e999mm", ":jog", ":override 50%",
    ":override 1e999%", ":override -5%", ":mode auto", ":mode manual", ":mode x", ":tool ARM", ":tool nosuch",
    ":teach p1", ":teach __class__", ":teach 1abc", ":insert move p1", ":insert PRINT 1", ":modpos p1", ":positions",
    ":undo", ":undo p1", ":goto 1", ":goto 999999", ":goto -1", ":goto x", ":select", ":delete", ":replace PRINT 2",
    ":edit", ":wrap FRAME f", ":shift up", ":shift down", ":check", ":run", ":stop", ":step", ":back", ":pp",
    ":exec", ":io", ":io DigOut[3] 1", ":io DigOut[99] 1", ":log", ":where", ":help", ":help MOVE", ":nosuch",
    ":snapshot shot.png", ":snapshot shot.txt", ":save", ":save copy.rpl", ":save copy.txt", ":recover", ":",
)

PENDANT_STATEMENTS = (
    "PRINT 1 + 1", "PRINT 1 / 0", "VAR x = 1", "x = x + 1", "MOVE ARM TO HERE", "WAIT 10ms", "WAIT -1s", "WAIT 1e999s",
    "WAIT 100000s", "FOR i FROM 1e300 TO 1e300 + 1 DO\nENDFOR", "FOR i FROM 0 TO 1 STEP 1e-300 DO\nENDFOR",
    "WHILE TRUE DO\nENDWHILE", "MOVE ARM TO HERE WITH TIME = 1e9s", 'INSTALL L AS LaserDistance WITH PORT = "spy://x"',
    "PRINT " + "(" * 200 + "1" + ")" * 200, "PRINT " + "+".join(["1"] * 300), "PRINT " + "9" * 5000, "ENDIF",
    "IF TRUE THEN", "PRINT DigIn[99]", "DigOut[3] = 1", "PRINT HERE", "STOP", "RETURN", "PRINT __class__",
)


def _corpus(patterns: tuple[str, ...]) -> list[tuple[str, str]]:
    """(suffix, text) of the repository's files matching the patterns, sorted for a stable order."""
    files = sorted({path for pattern in patterns for path in ROOT.glob(pattern)})
    return [(path.suffix, path.read_text(encoding="utf-8")) for path in files]


PROGRAMS = _corpus(("programs/online/*.rpl", "programs/offline/*.orl", "tests/transform/golden/*.rpl",
                    "tests/checking/foreign/*.rpl"))
WORLDS = _corpus(("worlds/*.yaml",))
SIDECARS = _corpus(("programs/*/*.sim.yaml",))


def _mutate_lines(rng: random.Random, lines: list[str], fragments: tuple[str, ...]) -> list[str]:
    """One edit a careless hand makes: a line deleted, doubled, swapped, cut, or a fragment pasted in."""
    if not lines:
        return [rng.choice(fragments)]
    i = rng.randrange(len(lines))
    kind = rng.randrange(7)
    if kind == 0:
        del lines[i]
    elif kind == 1:
        lines.insert(i, lines[i])
    elif kind == 2:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    elif kind == 3:
        lines[i] = lines[i][: rng.randrange(len(lines[i]) + 1)]
    elif kind == 4:
        cut = rng.randrange(len(lines[i]) + 1)
        lines[i] = lines[i][:cut] + " " + rng.choice(fragments) + " " + lines[i][cut:]
    elif kind == 5:
        lines.insert(i, rng.choice(fragments))
    else:
        lines[i] = rng.choice(("", " ", "\t", "    ")) + lines[i]
    return lines


def _nest(rng: random.Random, suffix: str) -> str:
    """A deeply nested block or expression (up to several hundred levels)."""
    depth = rng.choice((5, 50, 99, 101, 150, 400, 1000))
    if suffix == ".orl":
        return "".join("    " * k + "if true:\n" for k in range(depth)) + "    " * depth + "print(1)\n"
    kind = rng.randrange(4)
    if kind == 0:
        return "IF TRUE THEN\n" * depth + "PRINT 1\n" + "ENDIF\n" * depth
    if kind == 1:
        return "PRINT " + "+".join(["1"] * depth) + "\n"
    if kind == 2:
        return "PRINT " + "-" * depth + "1\n"
    return "PRINT " + "(" * depth + "1" + ")" * depth + "\n"


def program(rng: random.Random) -> tuple[str, str]:
    """(suffix, text) of one generated program: a real one mutated, or a nesting or repetition extreme."""
    suffix, text = rng.choice(PROGRAMS)
    roll = rng.random()
    if roll < 0.08:
        return suffix, _nest(rng, suffix)
    if roll < 0.1:
        return suffix, rng.choice(("ENDIF\n", "ENDWHILE\n", "ENDFOR\n", "else:\n")) * rng.choice((10, 1000, 16000))
    lines = text.split("\n")
    for _ in range(rng.randint(1, 4)):
        lines = _mutate_lines(rng, lines, PROGRAM_TOKENS)
    return suffix, "\n".join(lines)


def _yaml_mutation(rng: random.Random, lines: list[str]) -> list[str]:
    """A scalar replaced by a hostile value, or a line-level edit."""
    if lines and rng.random() < 0.6:
        i = rng.randrange(len(lines))
        line = lines[i]
        if ": " in line:
            head, _, _ = line.partition(": ")
            lines[i] = f"{head}: {rng.choice(YAML_VALUES)}"
        elif "[" in line:
            lines[i] = line.replace("0", rng.choice(YAML_VALUES), 1)
        return lines
    return _mutate_lines(rng, lines, YAML_VALUES)


def _mutated_yaml(rng: random.Random, corpus: list[tuple[str, str]]) -> str:
    _, text = rng.choice(corpus)
    lines = text.split("\n")
    for _ in range(rng.randint(1, 4)):
        lines = _yaml_mutation(rng, lines)
    return "\n".join(lines)


def world(rng: random.Random) -> str:
    """The text of one generated world file."""
    return _mutated_yaml(rng, WORLDS)


def sidecar(rng: random.Random) -> str:
    """The text of one generated `.sim.yaml` sidecar."""
    return _mutated_yaml(rng, SIDECARS)


def pendant_line(rng: random.Random) -> str:
    """One line typed at the pendant: a `:` command or a statement, sometimes mangled."""
    line = rng.choice(PENDANT_COMMANDS if rng.random() < 0.5 else PENDANT_STATEMENTS)
    if rng.random() < 0.3:
        cut = rng.randrange(len(line) + 1)
        line = line[:cut] + rng.choice(PROGRAM_TOKENS) + line[cut:]
    return line


#: Command lines of `orc` with hostile options ({p}: a program, {w}: a world, {d}: a folder, {o}: an output).
OPTION_LINES = (
    ["run", "{p}", "--speed-override", "1e999%"], ["run", "{p}", "--speed-override", "nan"],
    ["run", "{p}", "--timeout", "-1"], ["run", "{p}", "--timeout", "inf"], ["run", "{p}", "--timeout", "x"],
    ["run", "{p}", "--statement-budget", "-5"], ["run", "{p}", "--robot", "../../etc/passwd"],
    ["run", "{p}", "--summary-json", "{p}"], ["run", "{p}", "--log", "{d}"], ["run", "{p}", "--plot", "{d}/no/x.png"],
    ["run", "{p}", "--world", "/dev/zero"], ["run", "{p}", "--world", "{d}/none"], ["check", "{p}", "--world", "{p}"],
    ["check", "/dev/null"], ["fmt", "{p}", "--check", "--write"], ["convert", "{p}", "-o", "{p}"],
    ["convert", "{p}", "-o", "{o}.rpl", "--online-world", "{o}.rpl"], ["diff", "{p}", "/dev/zero"],
    ["pendant", "{p}", "--robot", "nosuch"], ["pendant", "{d}"], ["pendant", "x.txt"], ["nosuch"], [],
)
