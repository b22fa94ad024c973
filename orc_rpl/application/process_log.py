"""The application room's process record: what each process achieved (welds, bulges, seams, parts, tunings), as plain data.

Behaviours append one record per outcome and keep the current process signals (force, stroke, error along the
normal, seam error, payload estimate) up to date every motion cycle; `orc run` puts `as_dict()` in the
summary's `process` section and samples `signals` into its recording. Everything here is numbers, strings and
lists, so a viewer or a report can read it without orc_rpl.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

from orc_rpl.application.runtime import attached
from orc_rpl.errors import MotionFault

#: The process signals recorded every motion cycle (`--log`), with their units; NaN while no process runs.
SIGNALS: dict[str, str] = {
    "force_n": "N",              #: measured contact force (grinding)
    "force_cmd_n": "N",          #: commanded contact force
    "stroke_m": "m",             #: compliant flange's stroke
    "normal_error_m": "m",       #: tool tip's position error along the path normal (CatchBulge)
    "seam_error_m": "m",         #: seam tracking: the laser's lateral error after the correction
    "payload_kg": "kg",          #: the last payload estimate (IDENTMOVE)
}


class ProcessFault(MotionFault):
    """A process went wrong in a way its own control detected (an unstable force loop)."""

    rpl_name = "ProcessFault"


@dataclass(frozen=True, slots=True)
class WeldRecord:
    """One spot weld as the controller measured it when the gun closed."""

    gun: str
    time_s: float                          #: the gun closed (close signal + REACTION)
    position_m: tuple[float, float, float]  #: TCP then (world)
    speed_m_s: float                       #: TCP speed then
    offset_m: float                        #: TCP distance from the spot then
    good: bool                             #: within the gun's speed and offset limits, and WELD_OK came
    reason: str = ""                       #: why not, for a bad weld


@dataclass(frozen=True, slots=True)
class BulgeRecord:
    """One bulge caught by GRINDMOVE and what grinding did to it (heights above the edge, m)."""

    s0: float                              #: path coordinate where it starts (0..1)
    s1: float
    caught_height_m: float                 #: as caught
    pass_heights_m: tuple[float, ...]      #: measured after each pass
    left_m: float                          #: what the last measurement left
    within_tolerance: bool


@dataclass(frozen=True, slots=True)
class SeamRecord:
    """One TRACKMOVE: the laser's lateral error after the correction, over the motion (start included; a noisy
    laser's noise is part of it)."""

    length_m: float
    rms_m: float
    max_m: float
    gain: float


@dataclass(frozen=True, slots=True)
class IdentRecord:
    """One IDENTMOVE: the payload estimate, its standard deviation and the part it gave."""

    payload_kg: float
    sigma_kg: float
    confidence: float                      #: 1 - the probability that the answer would change within the estimate's spread
    part: str                              #: the answer, or "" when the identification was uncertain


@dataclass(frozen=True, slots=True)
class TuningRecord:
    """One CALIBRATE: what it identified and the gains it chose."""

    figures: dict[str, Any]


@dataclass(frozen=True, slots=True)
class FaultRecord:
    """A process exception raised (caught by the program or not)."""

    exception: str
    message: str
    time_s: float


@dataclass
class ProcessLog:
    """Every process outcome of one run, and the current process signals."""

    welds: list[WeldRecord] = field(default_factory=list)
    bulges: list[BulgeRecord] = field(default_factory=list)
    seams: list[SeamRecord] = field(default_factory=list)
    identifications: list[IdentRecord] = field(default_factory=list)
    tunings: list[TuningRecord] = field(default_factory=list)
    faults: list[FaultRecord] = field(default_factory=list)
    signals: dict[str, float] = field(default_factory=lambda: dict.fromkeys(SIGNALS, math.nan))

    def fault(self, error: MotionFault, time_s: float) -> MotionFault:
        """Record a process exception about to be raised; returns it (`raise log.fault(...)`)."""
        self.faults.append(FaultRecord(error.rpl_name, str(error), time_s))
        return error

    def __bool__(self) -> bool:
        return bool(self.welds or self.bulges or self.seams or self.identifications or self.tunings or self.faults)

    def as_dict(self) -> dict[str, Any]:
        """The summary's `process` section: plain JSON data (units in the key names)."""
        return {
            "welds": [asdict(w) for w in self.welds],
            "bulges": [asdict(b) for b in self.bulges],
            "seams": [asdict(s) for s in self.seams],
            "identifications": [asdict(i) for i in self.identifications],
            "tunings": [_plain(t.figures) for t in self.tunings],
            "faults": [asdict(f) for f in self.faults],
        }


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "item"):
        return value.item()
    return value


def process_log(robot: Any) -> ProcessLog:
    """The robot's process record (made on first use)."""
    return attached(robot, "process_log", ProcessLog)
