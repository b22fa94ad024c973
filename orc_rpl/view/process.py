"""The view's process overlays: weld spots and their quality, the tracked seam and the ground edge coloured by their
error, and a caption line, all read from the applications' process record (it commands nothing)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from orc_rpl.application.process_log import ProcessLog, WeldRecord

#: The process signals drawn along the TCP where they are measured, with the error that colours a point fully red.
TRACED: dict[str, float] = {
    "seam_error_m": 0.001,       #: seam tracking: the laser's lateral error after the correction
    "normal_error_m": 0.001,     #: grinding: the tool tip's error along the path normal (a bulge shows as a rise)
}


@dataclass(frozen=True, slots=True)
class ProcessState:
    """What the process record says at one instant, copied in the motion cycle for the sending thread."""

    welds: tuple[WeldRecord, ...]        #: welds made since the last state (the view draws each once)
    first_weld: int                      #: the number of the first of them (1-based)
    caption: str                         #: one line: welds so far, the current signal, the last outcome


def process_record(robot: Any) -> ProcessLog | None:
    """The process record the applications keep on the robot the executive drives (None before any process ran)."""
    record = getattr(robot, "process_log", None)
    return record if isinstance(record, ProcessLog) else None


class ProcessOverlay:
    """Samples the process record each motion cycle the trace is sampled, and states what is new at each update."""

    def __init__(self) -> None:
        self._welds_seen = 0
        self.points: dict[str, list[tuple[np.ndarray, float]]] = {name: [] for name in TRACED}  #: not sent yet

    def sample(self, signals: Mapping[str, float] | None, tcp_m: np.ndarray) -> None:
        """Where the TCP is while a traced signal is measured (None, NaN: no process runs, nothing drawn)."""
        if signals is None:
            return
        for name in TRACED:
            value = signals.get(name, math.nan)
            if not math.isnan(value):
                self.points[name].append((tcp_m, float(value)))

    def state(self, record: ProcessLog | None) -> ProcessState | None:
        """New welds and the caption line; None when no process has run."""
        if record is None or not (record or any(not math.isnan(v) for v in record.signals.values())):
            return None
        welds = tuple(record.welds[self._welds_seen:])
        first = self._welds_seen + 1
        self._welds_seen = len(record.welds)
        return ProcessState(welds, first, caption_line(record))

    def take_points(self) -> list[tuple[str, list[np.ndarray], np.ndarray]]:
        """The sampled points not handed over yet, each signal's with their colours (RGB 0..255); forget them."""
        taken = [(name, [p for p, _ in points], error_colours(np.array([value for _, value in points]), TRACED[name]))
                 for name, points in self.points.items() if points]
        self.points = {name: [] for name in TRACED}
        return taken


def caption_line(record: ProcessLog) -> str:
    """`welds 5 good, 1 bad · seam error 0.12 mm · part small_box (2.00 kg)`: what the processes did and do now."""
    parts = []
    if record.welds:
        good = sum(w.good for w in record.welds)
        parts.append(f"welds {good} good, {len(record.welds) - good} bad")
    signals = record.signals
    if not math.isnan(signals.get("seam_error_m", math.nan)):
        parts.append(f"seam error {1000 * signals['seam_error_m']:.2f} mm")
    elif record.seams:
        seam = record.seams[-1]
        parts.append(f"seam tracked, error rms {1000 * seam.rms_m:.2f} mm, max {1000 * seam.max_m:.2f} mm")
    if not math.isnan(signals.get("force_n", math.nan)):
        parts.append(f"force {signals['force_n']:.1f} N (commanded {signals.get('force_cmd_n', math.nan):.1f} N)")
    if record.bulges:
        bulge = record.bulges[-1]
        verdict = "within tolerance" if bulge.within_tolerance else "out of tolerance"
        parts.append(f"bulge {1000 * bulge.caught_height_m:.2f} mm before, {1000 * bulge.left_m:.2f} mm after "
                     f"({verdict})")
    if record.identifications:
        ident = record.identifications[-1]
        part = ident.part or "uncertain"
        parts.append(f"part {part} ({ident.payload_kg:.2f} kg)")
    if record.faults:
        parts.append(f"{record.faults[-1].exception}")
    return " · ".join(parts)


def error_colours(values: np.ndarray, full_scale: float) -> np.ndarray:
    """RGB 0..255 per value: green at no error, red at `full_scale` and beyond."""
    share = np.clip(np.abs(values) / full_scale, 0.0, 1.0)[:, None]
    return (np.array([40, 170, 60]) * (1 - share) + np.array([220, 30, 30]) * share).astype(np.uint8)
