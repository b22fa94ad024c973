"""The words of the on-line language: reserved words, predefined names, the motion-keyword rule."""

from __future__ import annotations

import re

#: docs/language.md section 1: reserved, upper case and exact; never usable as names.
RESERVED: frozenset[str] = frozenset(
    """MOVE TO ALONG VIA WITH UNTIL IF THEN ELSIF ELSE ENDIF WHILE DO ENDWHILE FOR FROM STEP
    ENDFOR CASE OF ENDCASE FRAME ENDFRAME PROC ENDPROC FUNC ENDFUNC RETURN TRY ON ENDTRY
    RAISE WAIT PRINT STOP INSTALL AS IN TOOL POS PATH VAR CONST ENUM TIMEOUT AND OR NOT
    TRUE FALSE""".split()
)

#: Names every program may use without declaring them (docs/language.md section 1).
PREDEFINED_NAMES: frozenset[str] = frozenset({"ARM", "ROBOT", "HERE", "world", "DigIn", "DigOut", "AnalogIn", "AnalogOut", "FINE"})

#: Exceptions the system raises (docs/language.md section 8); exception names need no declaration.
SYSTEM_EXCEPTIONS: tuple[str, ...] = ("NotFound", "Unreachable", "JointLimit", "Timeout", "SensorFault", "DriveFault",
                                      "Collision")

_MOTION_KEYWORD = re.compile(r"(?:[A-Z][A-Z0-9_]*)?MOVE")


def is_motion_keyword(word: str) -> bool:
    """True for every upper-case word ending in MOVE (`MOVE`, `LMOVE`, `GRINDMOVE`, ...)."""
    return word.endswith("MOVE") and _MOTION_KEYWORD.fullmatch(word) is not None  # the cheap test first: every NAME asks


def is_reserved(word: str) -> bool:
    """True for words that can never be a name: reserved words and motion keywords."""
    return word in RESERVED or is_motion_keyword(word)
