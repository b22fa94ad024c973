"""Run-time errors: program text -> the failing statement's line and column and the message, never a traceback."""

from __future__ import annotations

import pytest

from tests.executive.support import execute

CASES = {
    "division_by_zero": ("VAR x = 1\nx = x / 0", 2, 1, "division by zero"),
    "mixed_dimensions_name_both": ("PRINT 1s + 2mm", 1, 1, "cannot add time (s) and length (m)"),
    "compare_dimensions": ("IF 1s < 2mm THEN\n    PRINT 1\nENDIF", 1, 1, "cannot compare time (s) with length (m)"),
    "index_out_of_range": ("VAR a = [1, 2]\nPRINT a[3]", 2, 1, "index 3 is out of range: the list has 2 elements"),
    "index_zero": ("VAR a = [1, 2]\nPRINT a[0]", 2, 1, "index 0 is out of range"),
    "const_cannot_be_assigned": ("CONST Vmax = 1.5mps\nVmax = 2mps", 2, 1, "'Vmax' is a CONST"),
    "undefined_name": ("PRINT nothing", 1, 1, "'nothing' is not defined"),
    "uncaught_raise": ("PRINT 1\n    RAISE UnknownPart", 2, 5, "UnknownPart"),
    "condition_not_boolean": ("IF 3 THEN\n    PRINT 1\nENDIF", 1, 1, "expected TRUE or FALSE"),
    "error_inside_loop_body_points_at_body": ("FOR i FROM 1 TO 3 DO\n    PRINT 1 / (i - 2)\nENDFOR", 2, 5, "division by zero"),
    "error_inside_routine_points_at_routine_line": (
        "PROC Bad(x)\n    PRINT x + 1mm\nENDPROC\nBad(2s)", 2, 5, "cannot add time"),
    "func_without_return": ("FUNC f(x)\n    x = 1\nENDFUNC\nPRINT f(1)", 4, 1, "FUNC f ended without RETURN"),
    "recursion_depth": ("FUNC f(x)\n    RETURN f(x + 1)\nENDFUNC\nPRINT f(1)", 2, 5, "nested deeper than"),
    "wrong_argument_count": ("PROC P(a, b)\n    PRINT a\nENDPROC\nP(1)", 4, 1, "takes 2 arguments, got 1"),
    "wait_needs_time": ("WAIT 2", 1, 1, "WAIT needs a time"),
    "timeout_uncaught": ("WAIT UNTIL DigIn[1] = 1 TIMEOUT 0.2s", 1, 1, "Timeout"),
    "digital_output_value": ("DigOut[1] = 2", 1, 1, "is digital"),
    "input_cannot_be_written": ("DigIn[1] = 1", 1, 1, "is an input"),
    "channel_out_of_range": ("PRINT DigIn[99]", 1, 1, "DigIn[99] does not exist"),
    "frame_mismatch_at_run_time": ("""FRAME table = POSE(1m, 0, 0.5m, 0, 0, 0)
POS p = POSE(0.9m, 0, 0.8m, 0, 180deg, 0)
FRAME table
    MOVE ARM TO p
ENDFRAME""", 4, 5, "relative to world, but this motion is inside FRAME table"),
    "frame_block_of_undeclared_frame": ("FRAME nowhere\n    PRINT 1\nENDFRAME", 1, 1, "not a declared FRAME"),
    "unreachable_uncaught": ("MOVE ARM TO POSE(3m, 0, 0, 0, 0, 0)", 1, 1, "Unreachable"),
    "lmove_needs_pose": ("LMOVE ARM TO JOINTS(0, 0, 0, 0, 0, 0)", 1, 1, "needs a pose as its target"),
    "function_arity": ("PRINT 1\nPRINT POSE(1m, 2m)", 2, 1, "POSE takes 6 arguments, got 2"),
    "proc_has_no_value": ("PROC p\n    PRINT 1\nENDPROC\nx = p()", 4, 1, "PROC p gives no value"),
    "behaviour_error": ("PRINT SQRT(-4)", 1, 1, "SQRT of a negative value"),
    "speed_fraction_out_of_range": ("MOVE ARM TO POSE(1m, 0, 0.8m, 0, 180deg, 0) WITH SPEED = 2", 1, 1, "in (0, 1]"),
}


@pytest.mark.parametrize("text, line, column, message", CASES.values(), ids=CASES.keys())
def test_error_is_located_at_the_failing_statement(text: str, line: int, column: int, message: str) -> None:
    executive = execute(text)
    assert executive.status == "failed", executive.prints
    error = executive.error
    assert error is not None and error.span is not None
    assert (error.span.line, error.span.column) == (line, column), executive.report()
    assert message in error.message
    report = executive.report()
    assert report.startswith(f"test.rpl:{line}:{column}: ")
    assert "Traceback" not in report


def test_application_keyword_without_behaviour_is_not_implemented_yet() -> None:
    import dataclasses

    from orc_rpl.application.standard_behaviour import runtime_registry

    registry = runtime_registry()
    registry.motions["GRINDMOVE"] = dataclasses.replace(registry.motions["GRINDMOVE"], execute=None)
    executive = execute("POS p = POSE(1m, 0, 0.8m, 0, 180deg, 0)\nGRINDMOVE ARM TO p", registry=registry)
    assert executive.status == "failed" and executive.error is not None and executive.error.span is not None
    assert (executive.error.span.line, executive.error.span.column) == (2, 1)
    assert "GRINDMOVE is not implemented yet" in executive.error.message


def test_report_has_the_call_stack_innermost_last() -> None:
    executive = execute("""
        PROC Inner
            PRINT 1 / 0
        ENDPROC
        PROC Outer
            Inner
        ENDPROC
        Outer
        """)
    report = executive.report()
    assert report.splitlines()[0] == "test.rpl:2:5: division by zero"
    assert report.endswith("call stack (innermost last):\n  test.rpl:7:1: in Outer\n  test.rpl:5:5: in Inner")
    assert [(e.routine, e.line) for e in executive.error.stack] == [("main", 0), ("Outer", 7), ("Inner", 5)]


def test_frame_mismatch_moves_nothing() -> None:
    executive = execute(CASES["frame_mismatch_at_run_time"][0])
    assert executive.robot.recorded == []


def test_failed_run_stops_the_robot_on_its_path() -> None:
    executive = execute("""
        POS a = POSE(1m, 0.3m, 0.8m, 0, 180deg, 0)
        MOVE ARM TO a WITH ZONE = 10mm
        PRINT 1 / 0
        """)
    assert executive.status == "failed"
    assert executive.robot.stops == 1 and executive.robot.pending() == 0
