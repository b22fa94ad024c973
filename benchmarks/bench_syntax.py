"""Parse-and-check throughput on a generated 10,000-line program, and one pendant statement's parse time.

Targets (issue 2): at least 20,000 lines/s with positions; one statement in under 1 ms.
Run: python benchmarks/bench_syntax.py   (prints key=value figures as its last lines; times are medians)
"""

from __future__ import annotations

import os
import statistics
import time

from orc_rpl.application.registry import default_registry
from orc_rpl.checking.checker import check_program
from orc_rpl.syntax.parser import parse, parse_statement

BLOCK = """-- cell {i}
POS p{i} = POSE({x}mm, {y}mm, 600mm, 0, 180deg, 0) IN plate
VAR n{i} = {i} * 2 + 1
IF n{i} > 10 THEN
    n{i} = n{i} - 1  -- count down
ELSE
    PRINT "small", n{i}
ENDIF
FRAME plate
    MOVE grinder TO p{i} WITH SPEED = 0.5 * Vmax WITH ZONE = 5mm
    LMOVE grinder TO OFFS(p{i}, 0, 0, 50mm)
      WITH SPEED = 200mm/s
ENDFRAME
WAIT UNTIL DigIn[1] = 1 TIMEOUT 2s
FOR k FROM 1 TO 3 DO
    DigOut[k] = 0
ENDFOR

"""
#: How many times parse-and-check and bare Lark are each timed (alternately); figures are medians.
RUNS = 7

HEADER = """TOOL grinder = POSE(0, 0, 150mm, 0, 0, 0)
FRAME plate = POSE(900mm, 0, 0, 0, 0, 0)
CONST Vmax = 1.5mps
"""


def generated_program(lines: int) -> str:
    """A realistic program of about `lines` lines."""
    parts, count, i = [HEADER], HEADER.count("\n"), 0
    while count < lines:
        block = BLOCK.format(i=i, x=100 + i % 300, y=-200 + i % 400)
        parts.append(block)
        count += block.count("\n")
        i += 1
    return "".join(parts)


def timed(action) -> float:  # type: ignore[no-untyped-def]
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def main() -> None:
    text = generated_program(10_000)
    lines = text.count("\n")
    registry = default_registry()
    parse(text)  # build the parser once, as a long-running tool does
    parse_s = statistics.median(timed(lambda: parse(text, "bench.rpl")) for _ in range(5))
    program = parse(text, "bench.rpl")
    assert not check_program(program, "bench.rpl", registry), "the benchmark program must be clean"
    # Baseline in the same run: Lark alone on the same grammar (its own lexer and LALR loop building its parse tree,
    # no tree of ours, no positions of ours, no check), so the figure can be read on a loaded machine as our cost
    # over the library. The two are timed alternately, RUNS times each, and compared by their medians, so a burst
    # of load on the shared machine hits both alike.
    from lark import Lark

    from orc_rpl.syntax.grammar_files import grammar_path

    bare = Lark(grammar_path("rpl.lark").read_text(), parser="lalr", lexer="contextual", start="program")
    total_times, bare_times = [], []
    for _ in range(RUNS):
        total_times.append(timed(lambda: check_program(parse(text, "bench.rpl"), "bench.rpl", registry)))
        bare_times.append(timed(lambda: bare.parse(text)))
    total_s, bare_s = statistics.median(total_times), statistics.median(bare_times)
    statement = "MOVE grinder TO OFFS(p1, 0, 0, 50mm) WITH SPEED = 0.5 * Vmax WITH ZONE = 5mm"
    samples = []
    for _ in range(200):
        start = time.perf_counter()
        parse_statement(statement)
        samples.append(time.perf_counter() - start)
    print(f"program: {lines} lines; medians of {RUNS} runs: parse only {parse_s * 1e3:.0f} ms; parse and check "
          f"{total_s * 1e3:.0f} ms; bare Lark {bare_s * 1e3:.0f} ms")
    print(f"load_average_1min={os.getloadavg()[0]:.2f}")
    print(f"parse_lines_per_s={lines / parse_s:.0f}")
    print(f"parse_check_lines_per_s={lines / total_s:.0f}")
    print(f"bare_lark_lines_per_s={lines / bare_s:.0f}")
    print(f"parse_check_over_bare_lark_ratio={total_s / bare_s:.2f}")
    print(f"statement_parse_ms_median={statistics.median(samples) * 1e3:.3f}")
    print(f"statement_parse_ms_p99={sorted(samples)[int(len(samples) * 0.99)] * 1e3:.3f}")


if __name__ == "__main__":
    main()
