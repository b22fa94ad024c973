"""The interpreter's semantics on the recording robot: program text -> PRINT lines (docs/language.md sections 6-8)."""

from __future__ import annotations

import pytest

from tests.executive.support import prints

CASES = {
    "print_numbers": ("PRINT 3, 0.25, 7 / 2, 8 / 4, 1.5e-3, 2 * 0.5", ["3 0.25 3.5 2 0.0015 1"]),
    "print_quantities": ("PRINT 100mm, 1.5mps, 90deg / 2, 80ms, 20N, 2 * mm", ["0.1 m 1.5 m/s 0.7853981633974483 rad 0.08 s 20 N 0.002 m"]),
    "print_percent_is_a_fraction": ("PRINT 50%", ["0.5"]),
    "print_strings_booleans_lists": ('PRINT "cycle done", TRUE, FALSE, [1, 2, 3]', ["cycle done TRUE FALSE [1, 2, 3]"]),
    "print_nested_list_quotes_strings": ('PRINT ["a", [1, 2.5]]', ['["a", [1, 2.5]]']),
    "print_empty": ("PRINT", [""]),
    "units_cancel_to_numbers": ("PRINT 300mm / 1m, 1s * 2mps", ["0.3 2 m"]),
    "arithmetic_precedence": ("VAR y = 4\nVAR x = 2 * y + 1\nPRINT x, -x, (x - 1) / 2", ["9 -9 4"]),
    "comparisons_and_logic": ("PRINT 1 < 2, 2 <= 1, 3 = 3, 3 <> 3, 1mm < 1m, NOT (1 > 2) AND TRUE OR FALSE",
                              ["TRUE FALSE TRUE FALSE TRUE TRUE"]),
    "string_concatenation_and_compare": ('PRINT "ab" + "c", "a" < "b"', ["abc TRUE"]),
    "if_elsif_else": ("""
        VAR x = 3
        IF x > 3 THEN
            PRINT "big"
        ELSIF x = 3 THEN
            PRINT "three"
        ELSE
            PRINT "small"
        ENDIF
        """, ["three"]),
    "while": ("""
        VAR n = 0
        WHILE n < 3 DO
            n = n + 1
        ENDWHILE
        PRINT n
        """, ["3"]),
    "for_inclusive_with_step": ("""
        FOR i FROM 1 TO 10 STEP 3 DO
            PRINT i
        ENDFOR
        """, ["1", "4", "7", "10"]),
    "for_downwards": ("FOR i FROM 3 TO 1 STEP -1 DO\n    PRINT i\nENDFOR", ["3", "2", "1"]),
    "for_empty_range": ("FOR i FROM 3 TO 1 DO\n    PRINT i\nENDFOR\nPRINT \"after\"", ["after"]),
    "for_quantities": ("FOR d FROM 0mm TO 20mm STEP 10mm DO\n    PRINT d\nENDFOR", ["0 m", "0.01 m", "0.02 m"]),
    "case_with_enum_and_else": ("""
        ENUM Part = NoObject, Bolt, Nut
        VAR Id = Nut
        CASE Id OF
            NoObject : PRINT "nothing grasped"
            Bolt, Nut :
                PRINT "part", Id
            ELSE : PRINT "unknown"
        ENDCASE
        """, ["part Nut"]),
    "case_falls_to_else": ("CASE 5 OF\n    1 : PRINT 1\n    ELSE : PRINT \"else\"\nENDCASE", ["else"]),
    "case_no_match_no_else": ("CASE 5 OF\n    1 : PRINT 1\nENDCASE\nPRINT \"on\"", ["on"]),
    "lists_index_from_one": ("VAR a = [10, 20, 30]\nPRINT a[1], a[3], LEN(a)", ["10 30 3"]),
    "enum_values_index_lists": ("ENUM Part = NoObject, Bolt, Nut\nVAR w = [0kg, 2kg, 1kg]\nPRINT w[Bolt], Bolt < Nut", ["2 kg TRUE"]),
    "list_element_assignment_copies": ("""
        VAR a = [1, 2, 3]
        VAR b = a
        a[2] = 5
        PRINT a, b
        """, ["[1, 5, 3] [1, 2, 3]"]),
    "pose_fields": ("VAR p = POSE(100mm, 50mm, 20mm, 180deg, 0, 0)\nPRINT p.x, p.y, p.z, p.b", ["0.1 m 0.05 m 0.02 m 0 rad"]),
    "pose_field_assignment": ("VAR p = POSE(100mm, 0, 0, 0, 0, 0)\np.z = 30mm\nPRINT p.x, p.z", ["0.1 m 0.03 m"]),
    "pose_functions": ("""
        VAR p = POSE(1m, 0, 0, 90deg, 0, 0)
        VAR q = OFFS(p, 10mm, 0, 0)
        VAR r = RELTOOL(p, 10mm, 0, 0)
        PRINT q.x, ROUND(r.y / 1mm, 6), (p * INV(p)).x, TRANSL(1m, 2m, 3m).z
        """, ["1.01 m 10 0 m 3 m"]),
    "math_functions": ("PRINT ABS(-2mm), ROUND(2.5), ROUND(-2.5), ROUND(3.14159, 2), SQRT(16), SQRT(4m * 1m)",
                       ["0.002 m 3 -3 3.14 4 2 m"]),
    "trigonometry": ("PRINT SIN(90deg), COS(0), ROUND(ATAN2(1, 1) / 1deg, 9), MIN(3, 1, 2), MAX(1mm, 2mm)",
                     ["1 1 45 1 0.002 m"]),
    "proc_with_global_update": ("""
        VAR count = 0
        PROC Bump
            count = count + 1
        ENDPROC
        Bump
        Bump
        PRINT count
        """, ["2"]),
    "routine_locals_are_per_call": ("""
        VAR x = 1
        PROC Set(v)
            y = v
            PRINT y
        ENDPROC
        Set(5)
        PRINT x
        """, ["5", "1"]),
    "parameters_by_value": ("""
        VAR a = [1, 2]
        PROC Change(l)
            l[1] = 9
            PRINT l
        ENDPROC
        Change(a)
        PRINT a
        """, ["[9, 2]", "[1, 2]"]),
    "func_recursion": ("""
        FUNC fact(k)
            IF k <= 1 THEN
                RETURN 1
            ENDIF
            RETURN k * fact(k - 1)
        ENDFUNC
        PRINT fact(10), fact(1)
        """, ["3628800 1"]),
    "func_with_units_and_named_argument": ("""
        FUNC ramp(s)
            RETURN 20N + 10N * s
        ENDFUNC
        PRINT ramp(0.5), ramp(s = 1)
        """, ["25 N 30 N"]),
    "return_from_proc_early": ("""
        PROC P(x)
            IF x > 0 THEN
                RETURN
            ENDIF
            PRINT "not positive"
        ENDPROC
        P(1)
        P(-1)
        """, ["not positive"]),
    "try_catches_raise": ("""
        TRY
            RAISE PartMissing
            PRINT "not here"
        ON Other :
            PRINT "other"
        ON PartMissing :
            PRINT "caught"
        ENDTRY
        PRINT "on"
        """, ["caught", "on"]),
    "try_catches_through_calls": ("""
        PROC Deep
            RAISE Oops
        ENDPROC
        TRY
            Deep
        ON Oops : PRINT "from deep"
        ENDTRY
        """, ["from deep"]),
    "nested_try_inner_rethrows_unmatched": ("""
        TRY
            TRY
                RAISE B
            ON A : PRINT "a"
            ENDTRY
        ON B : PRINT "b"
        ENDTRY
        """, ["b"]),
    "stop_ends_program": ('PRINT "one"\nSTOP\nPRINT "two"', ["one"]),
    "wait_advances_time": ("WAIT 0.5s\nPRINT \"waited\"", ["waited"]),
    "const_and_var": ("CONST Vmax = 1.5mps\nVAR v = 0.5 * Vmax\nPRINT v", ["0.75 m/s"]),
    "digital_io": ("DigOut[5] = 1\nPRINT DigOut[5], DigIn[1]\nDigOut[5] = FALSE\nPRINT DigOut[5] = 0", ["1 0", "TRUE"]),
    "analog_io": ("AnalogOut[2] = 2.5\nPRINT AnalogOut[2], AnalogIn[1]", ["2.5 0"]),
    "wait_until_true_at_once": ("DigOut[1] = 1\nWAIT UNTIL DigOut[1] = 1 TIMEOUT 1s\nPRINT \"ok\"", ["ok"]),
    "wait_until_timeout_raises_timeout": ("""
        TRY
            WAIT UNTIL DigIn[2] = 1 TIMEOUT 0.1s
        ON Timeout : PRINT "timed out"
        ENDTRY
        """, ["timed out"]),
    "gripper_drives_its_output": ("""
        TOOL gripper = POSE(0, 0, 150mm, 0, 0, 0)
        INSTALL gripper AS Gripper WITH CLOSE = DigOut[3]
        gripper.Close
        PRINT DigOut[3], gripper.Closed
        gripper.Open
        PRINT DigOut[3]
        """, ["1 TRUE", "0"]),
    "switch_reads_its_input": ("INSTALL s AS Switch WITH INPUT = DigIn[4]\nPRINT s.State", ["0"]),
    "function_without_arguments_called_by_name": ("""
        FUNC answer()
            RETURN 42
        ENDFUNC
        PRINT answer, answer()
        """, ["42 42"]),
    "comments_and_blank_lines_are_ignored": ("-- a comment\n\nPRINT 1 -- trailing\n", ["1"]),
}


@pytest.mark.parametrize("text, expected", CASES.values(), ids=CASES.keys())
def test_program_prints(text: str, expected: list[str]) -> None:
    assert prints(text) == expected


@pytest.mark.parametrize("text, expected", CASES.values(), ids=CASES.keys())
def test_stepping_mode_gives_the_same_output(text: str, expected: list[str]) -> None:
    """The pendant runs programs traced (a yield before every statement): same results."""
    assert prints(text, tracing=True) == expected


def test_an_application_function_and_its_record() -> None:
    """A feature's function with an implementation is called; its record's fields read and assign by copy."""
    import dataclasses

    from orc_rpl.application.declarations import FunctionSpec, ParamSpec
    from orc_rpl.application.standard_behaviour import runtime_registry
    from orc_rpl.executive.values import Record

    registry = runtime_registry()
    registry.add_function(FunctionSpec("Pars", "test record", (ParamSpec("tolerance"), ParamSpec("passes")), origin="test"))
    registry.functions["Pars"] = dataclasses.replace(
        registry.functions["Pars"], implementation=lambda tolerance, passes: Record("Pars", (("tolerance", tolerance), ("passes", passes))))
    from tests.executive.support import execute

    executive = execute("""
        VAR p = Pars(0.2mm, 4)
        VAR q = p
        q.passes = 5
        PRINT p.tolerance, p.passes, q.passes, q
        """, registry=registry)
    assert executive.prints == ["0.0002 m 4 5 Pars(tolerance = 0.0002 m, passes = 5)"], executive.report()
