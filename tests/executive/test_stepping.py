"""The pendant's view of the executive: program pointer, step into/over/out, breakpoints, pause, exec in context."""

from __future__ import annotations

import textwrap

from orc_rpl.executive.executive import Executive
from orc_rpl.executive.recording_robot import RecordingRobot
from orc_rpl.syntax.parser import parse

PROGRAM = textwrap.dedent("""\
    FRAME table = POSE(1000mm, 0, 500mm, 0, 0, 0)
    POS p = POSE(0, 0, 200mm, 0, 180deg, 0) IN table
    VAR count = 0
    PROC Work(n)
        VAR local = n * 10
        count = count + n
        WAIT 0.5s
    ENDPROC
    Work(1)
    FRAME table
        MOVE ARM TO p
        Work(2)
    ENDFRAME
    PRINT count
    """)


def executive(robot: RecordingRobot | None = None) -> Executive:
    lines: list[str] = []
    ex = Executive(parse(PROGRAM, "p.rpl"), robot or RecordingRobot(), path="p.rpl", source=PROGRAM, output=lines.append)
    return ex


def test_first_step_stops_before_the_first_statement() -> None:
    ex = executive()
    assert ex.step_into() == "paused"
    assert (ex.pointer.line, ex.pointer.routine, ex.pointer.depth) == (1, "main", 1)


def test_step_over_runs_a_call_as_one_step() -> None:
    ex = executive()
    for _ in range(4):
        ex.step_over()
    assert ex.pointer.line == 9 and ex.value("count") == 0
    ex.step_over()
    assert ex.pointer.line == 10 and ex.value("count") == 1


def test_step_into_enters_the_routine_with_its_call_stack() -> None:
    ex = executive()
    for _ in range(4):
        ex.step_over()
    ex.step_into()
    pointer = ex.pointer
    assert (pointer.line, pointer.routine) == (5, "Work")
    assert [(e.routine, e.line) for e in pointer.call_stack] == [("main", 0), ("Work", 9)]
    ex.step_out()
    assert ex.pointer.line == 10 and ex.pointer.depth == 1


def test_breakpoints_stop_each_time_the_line_is_reached() -> None:
    ex = executive()
    ex.breakpoints.add(6)
    assert ex.run() == "paused" and ex.pointer.line == 6 and ex.machine.stack[-1].locals["n"] == 1
    assert ex.run() == "paused" and ex.pointer.line == 6 and ex.machine.stack[-1].locals["n"] == 2
    assert ex.run() == "finished" and ex.prints == ["3"]


def test_execute_uses_the_routine_scope_at_the_pointer() -> None:
    ex = executive()
    ex.breakpoints.add(7)
    ex.run()
    assert ex.execute("PRINT local, n") == "ok"
    assert ex.prints[-1] == "10 1"
    assert ex.execute("local = 99") == "ok" and ex.machine.stack[-1].locals["local"] == 99


def test_execute_uses_the_frame_block_of_a_line() -> None:
    ex = executive()
    assert ex.execute("MOVE ARM TO p", line=11).startswith("<pendant>:1:1: ")  # p has no value yet
    ex.breakpoints.add(11)
    ex.run()
    assert ex.execute("MOVE ARM TO OFFS(p, 0, 0, 10mm)") == "ok"
    assert ex.robot.recorded[-1].request.target.z == 0.71
    outside = ex.execute("MOVE ARM TO p", line=14)
    assert "relative to table, but this motion is outside every FRAME block" in outside


def test_pause_stops_in_the_middle_of_a_wait_and_resumes() -> None:
    robot = RecordingRobot()
    ex = executive(robot)
    robot.io.add_process(lambda io, t: ex.pause() if abs(t - 0.2) < 1e-9 else None)
    assert ex.run() == "paused"
    assert robot.time_s() == 0.2 and ex.pointer is None
    assert ex.run() == "finished" and ex.prints == ["3"]


def test_tracing_does_not_change_results() -> None:
    ex = executive()
    ex.tracing = True
    assert ex.run() == "finished" and ex.prints == ["3"]


def test_statement_steps_yield_motion_cycles_and_restart_sets_the_pointer() -> None:
    ex = executive()
    ex.breakpoints.add(9)
    ex.run()
    move = parse("MOVE ARM TO p\n", "s.rpl").body[0]
    cycles = sum(1 for _ in ex.statement_steps(move, None, "table"))
    assert cycles > 10 and ex.robot.pending() == 0
    program = parse(PROGRAM, "p.rpl")
    assert ex.restart_at(program.body[-1:]) == "paused" and ex.pointer.line == 14
    ex.breakpoints.clear()
    assert ex.run() == "finished" and ex.prints == ["0"]


def test_after_a_failure_the_pointer_shows_the_failing_statement() -> None:
    source = "VAR x = 0\nPROC P\n    x = 1 / x\nENDPROC\nP\n"
    ex = Executive(parse(source, "f.rpl"), RecordingRobot(), path="f.rpl", source=source, output=lambda line: None)
    assert ex.run() == "failed"
    assert (ex.pointer.line, ex.pointer.column, ex.pointer.routine, ex.pointer.depth) == (3, 5, "P", 2)
