"""What a caller asks the motion layer for: motion specifications, parameters and the small enums of the interface."""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.world.pose import Pose

FINE = 0.0  #: zone radius meaning "stop exactly at the target"

#: a function of one variable (the path coordinate s in [0, 1], or the time t in s)
Scalar = float | Callable[[float], float]


class MoveStatus(enum.Enum):
    """What `MotionLayer.move` answers (thesis 4.3, `enum mv`)."""

    READY = "ready"              #: nothing left to do (zero-length move, or a plan saved)
    SPAWNED = "spawned"          #: accepted; it runs while the caller goes on
    ILLEGAL = "illegal"          #: refused: wrong mode or a malformed request
    FAULT = "fault"              #: planning or execution failed (see the handle's error)
    ACT_STOPPED = "act_stopped"  #: stopped on its path by an action or by stop_move()


class Mode(enum.Enum):
    """Servo modes of the motion layer (thesis 4.3, `enum mode`)."""

    OFF = "off"          #: drives off, nothing commanded
    STANDBY = "standby"  #: holding position, no motion accepted
    BLOCK = "block"      #: joints blocked (held), no motion accepted
    BRAKE = "brake"      #: decelerating on the path to standstill
    RUN = "run"          #: normal operation
    TRACK = "track"      #: sensor-guided operation; motions accepted as in run


class Computation(enum.Enum):
    """When the planning of a move is done (thesis 5.2, `enum causality`)."""

    DURING = "during"  #: plan and move in one call
    SAVE = "save"      #: plan now, store under `descriptor`, do not move
    DONE = "done"      #: use the plan stored under `descriptor` if start and target still match


class Known(enum.Enum):
    """How much the motion depends on external sensors (thesis 5.2, `enum mv_spec`)."""

    COMPLETELY = "completely"
    ALMOST = "almost"
    PARTLY = "partly"
    NOT = "not"


def _finite(name: str, values: np.ndarray) -> None:
    if not np.all(np.isfinite(values)):
        raise UsageError(f"{name} must be finite numbers, got {values.tolist()}")


@dataclass(frozen=True, slots=True)
class JointMotion:
    """A joint-space motion to `target_rad`, passing near the `via_rad` points (blended with the zone)."""

    target_rad: tuple[float, ...]                   #: joint target, one angle per axis
    via_rad: tuple[tuple[float, ...], ...] = ()     #: intermediate joint positions, in order
    tool: np.ndarray | None = field(default=None, compare=False)  #: 4x4 flange->TCP, for zones and TCP speed

    def __post_init__(self) -> None:
        object.__setattr__(self, "target_rad", tuple(float(v) for v in self.target_rad))
        object.__setattr__(self, "via_rad", tuple(tuple(float(v) for v in p) for p in self.via_rad))
        _finite("JointMotion target", np.array(self.target_rad))
        for p in self.via_rad:
            _finite("JointMotion via point", np.array(p))


@dataclass(frozen=True, slots=True)
class CartesianMotion:
    """A TCP motion to `target`: straight line (`linear`), circle through `via` (`circular`) or joint-interpolated (`joint`)."""

    target: Pose                         #: TCP target in world coordinates
    kind: str = "linear"                 #: "linear" (LMOVE), "circular" (CMOVE) or "joint" (MOVE)
    via: Pose | None = None              #: auxiliary point of a circle (CMOVE)
    tool: np.ndarray | None = field(default=None, compare=False)  #: 4x4 flange->TCP (None: the flange)

    def __post_init__(self) -> None:
        if self.kind not in ("linear", "circular", "joint"):
            raise UsageError(f"CartesianMotion kind must be 'linear', 'circular' or 'joint', not {self.kind!r}")
        if self.kind == "circular" and self.via is None:
            raise UsageError("a circular motion needs its auxiliary point `via`")
        for pose in (self.target, self.via):
            if pose is not None:
                _finite("CartesianMotion pose", np.array([pose.x, pose.y, pose.z, pose.a, pose.b, pose.c]))


@dataclass(frozen=True, slots=True)
class FunctionMotion:
    """A motion in function space: each TCP component is a number or a function of s in [0, 1] (or of t)."""

    x: Scalar
    y: Scalar
    z: Scalar
    a: Scalar = 0.0
    b: Scalar = 0.0
    c: Scalar = 0.0
    variable: str = "s"          #: "s": a path, timed by the planner; "t": a trajectory lasting `duration_s`
    duration_s: float = 0.0      #: only for variable "t"
    tool: np.ndarray | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if self.variable not in ("s", "t"):
            raise UsageError(f"FunctionMotion variable must be 's' or 't', not {self.variable!r}")
        if self.variable == "t" and not (self.duration_s > 0 and math.isfinite(self.duration_s)):
            raise UsageError("a FunctionMotion of t needs a positive duration_s")

    def pose_at(self, u: float) -> np.ndarray:
        """The 4x4 TCP pose at path coordinate (or time) u."""
        vals = [float(v(u)) if callable(v) else float(v) for v in (self.x, self.y, self.z, self.a, self.b, self.c)]
        _finite("FunctionMotion value", np.array(vals))
        return Pose(*vals).matrix()


Motion = JointMotion | CartesianMotion | FunctionMotion


@dataclass(frozen=True, slots=True)
class Params:
    """Motion parameters (thesis 4.3): constants only; `FuncParams` allows functions of s."""

    speed_m_s: Scalar | None = None      #: TCP speed limit (None: only the joint limits)
    speed_fraction: Scalar = 1.0         #: override of the joint velocity limits, 0 < f <= 1
    accel_fraction: float = 1.0          #: fraction of the joint acceleration limits, 0 < f <= 1
    zone_m: float = FINE                 #: blend radius at the TCP (0: FINE, stop exactly)
    time_s: float | None = None          #: requested duration: the motion takes at least this long
    load_kg: float = 0.0                 #: payload carried, included in the torque limits
    tuning: Any = None                   #: servo tuning for this motion only (a `ServoTuning`; None: default gains)
    path_velocity: bool | None = None    #: path velocity control on/off for this motion (None: the layer's default)
    #: elastic gears: from rest, averaged over the gears' whole periods even where the layer scales the averaging
    #: to each move's steps (a quiet start for a recording or a seam: IDENTMOVE's lift, TRACKMOVE)
    whole_averaging: bool = False
    computation: Computation = Computation.DURING
    descriptor: int | None = None        #: plan store slot for SAVE / DONE
    known: Known = Known.COMPLETELY

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if callable(v) and not isinstance(v, enum.Enum) and not isinstance(self, FuncParams):
                raise UsageError(f"Params.{f.name} is a function: use FuncParams for functions of s")
        checks = {
            "accel_fraction": 0 < self.accel_fraction <= 1,
            "zone_m": math.isfinite(self.zone_m) and self.zone_m >= 0,
            "load_kg": math.isfinite(self.load_kg) and self.load_kg >= 0,
            "time_s": self.time_s is None or (math.isfinite(self.time_s) and self.time_s >= 0),
            "speed_fraction": callable(self.speed_fraction) or 0 < self.speed_fraction <= 1,
            "speed_m_s": self.speed_m_s is None or callable(self.speed_m_s)
            or (math.isfinite(self.speed_m_s) and self.speed_m_s > 0),
        }
        for name, ok in checks.items():
            if not ok:
                raise UsageError(f"Params.{name} = {getattr(self, name)!r} is out of range")
        if self.computation is not Computation.DURING and self.descriptor is None:
            raise UsageError(f"computation={self.computation.value} needs a descriptor")

    def speed_m_s_at(self, s: float) -> float | None:
        """TCP speed limit at path coordinate s."""
        v = self.speed_m_s
        return float(v(s)) if callable(v) else v

    def speed_fraction_at(self, s: float) -> float:
        """Joint velocity override at path coordinate s."""
        v = self.speed_fraction
        return float(v(s)) if callable(v) else float(v)


@dataclass(frozen=True, slots=True)
class FuncParams(Params):
    """Parameters whose `speed_m_s` and `speed_fraction` may be functions of s in [0, 1]."""


DEFAULT_PARAMS = Params()
