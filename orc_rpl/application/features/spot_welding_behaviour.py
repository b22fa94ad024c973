"""Behaviour of spot welding (thesis 2.2, 4.5): the SpotGun on its IO channels and WELDMOVE as a procedure.

    WeldMove(Pos, ...)
        if (ShortMotion) ShortMove(Pos, Par, Act); else Move(Pos, Par, Act);
        Wait(Act->MoveSignal);      -- signalled by an action at t >= T_d - tau
        Gun->Close(); Gun->Weld(); Gun->WaitWelding(); Gun->Open();

T_d is where the TCP stops, not where its reference ends: a real arm settles after its reference (servo,
elastic gears, friction). The first weld of a gun with each kind of move waits for the stop and measures how
far it lies from the reference's end; later ones close the gun that much later (see `weldmove`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from orc_rpl.application.process_log import WeldRecord, process_log
from orc_rpl.application.runtime import BehaviourError, InstallContext, MotionCall, MotionRequest
from orc_rpl.application.standard_behaviour import standard_motion
from orc_rpl.errors import MotionFault, Timeout
from orc_rpl.syntax.units import LENGTH, TIME, VELOCITY, Quantity
from orc_rpl.world.pose import Pose

#: A motion up to this long (TCP distance, m) is a ShortMove (jerk-limited, dynamics constant).
SHORT_MOTION_M = 0.15
#: WELD_OK must come within this much after the weld should be done (WELD_TIME), or Timeout is raised.
WELD_OK_MARGIN_S = 1.0
#: Default quality limits when the gun closes (MAX_SPEED, MAX_OFFSET): the servo's tracking lag alone leaves a
#: few mm/s and a few hundredths of a mm for some 30 ms after the reference has stopped.
MAX_SPEED_M_S = 0.02
MAX_OFFSET_M = 0.001
#: The TCP stands still from the start of the first motion cycle from which its speed stays below STILL_SHARE
#: of MAX_SPEED for this long (two motion cycles: the window over which a welder measures; the share leaves
#: the welder's window, which reaches back into the last faster cycles, below MAX_SPEED).
STILL_WINDOW_S = 0.008
STILL_SHARE = 0.25
#: The motion signals this much earlier than REACTION before its end: a TCP that stops before its reference
#: ends (the servo's lag taken up in the last cycles) gets its gun closed on time too.
EARLY_S = 0.008
#: A gun without a measured settling waits at most this long after the reference's end for the TCP to stand still.
SETTLE_WAIT_S = 0.1


class WeldFault(MotionFault):
    """A bad spot weld: the gun closed while the TCP moved faster than MAX_SPEED or farther than MAX_OFFSET from the spot."""

    rpl_name = "WeldFault"


def _limit(value: Any, dim: Any, what: str, example: str, default: float) -> float:
    if value is None:
        return default
    if type(value) is Quantity and value.dim == dim and value.value > 0:
        return value.value
    if type(value) in (int, float) and value > 0:
        return float(value)  # a declared default, in SI units
    raise BehaviourError(f"{what} must be > 0 (e.g. {example}), got {value}")


def _seconds(value: Any, what: str, default: float) -> float:
    if value is None:
        return default
    if type(value) is Quantity and value.dim == TIME and value.value >= 0:
        return value.value
    if type(value) in (int, float) and value >= 0:
        return float(value)  # a declared default, in seconds
    raise BehaviourError(f"{what} must be a time >= 0 (e.g. 80ms), got {value}")


class SpotGun:
    """A spot-welding gun: CLOSE (digital output) closes it and starts the weld, WELD_OK (digital input)
    reports a good weld; REACTION is the time from the close signal until the gun is closed."""

    def __init__(self, context: InstallContext) -> None:
        attrs = context.attributes
        self._context = context
        self.name = context.name
        self.close_channel, self.weld_ok_channel = attrs.get("CLOSE"), attrs.get("WELD_OK")
        if self.close_channel is None or self.weld_ok_channel is None:
            raise BehaviourError(f"INSTALL {context.name} AS SpotGun needs WITH CLOSE = DigOut[n] WITH WELD_OK = DigIn[m]")
        self.reaction_s = _seconds(attrs.get("REACTION"), "REACTION", 0.08)
        self.weld_time_s = _seconds(attrs.get("WELD_TIME"), "WELD_TIME", 0.2)
        self.max_speed_m_s = _limit(attrs.get("MAX_SPEED"), VELOCITY, "MAX_SPEED", "20mm/s", MAX_SPEED_M_S)
        self.max_offset_m = _limit(attrs.get("MAX_OFFSET"), LENGTH, "MAX_OFFSET", "1mm", MAX_OFFSET_M)
        self.welds = 0
        #: from the reference's end until the TCP stood still (< 0: before), last weld, for ShortMoves and others
        self.settle_s: dict[bool, float] = {}
        self.signals: list[float] = []      #: controller times of the close signals
        self.stops: list[float] = []        #: controller times the TCP was seen still, per weld

    def Close(self) -> None:  # noqa: N802 - the language's method names
        self._context.write(self.close_channel, 1)

    def Open(self) -> None:  # noqa: N802
        self._context.write(self.close_channel, 0)

    def Welds(self) -> int:  # noqa: N802
        return self.welds

    def weld_ok(self) -> bool:
        return bool(self._context.read(self.weld_ok_channel))


def weldmove(call: MotionCall) -> Iterator[Any]:
    """WELDMOVE gun TO spot: a short fast FINE move, the gun closed REACTION before it ends, wait for WELD_OK, open."""
    gun = call.equipment
    if not isinstance(gun, SpotGun):
        raise BehaviourError("the tool must be an installed SpotGun mounted as a TOOL")
    robot = call.robot
    if robot is None:
        raise BehaviourError("needs a robot")
    base = standard_motion(_as_move(call))
    target = base.target
    short = False
    if type(target) is Pose:
        here = robot.tcp_pose(call.tool)
        short = math.dist((here.x, here.y, here.z), (target.x, target.y, target.z)) <= SHORT_MOTION_M
    request = MotionRequest(
        keyword=call.keyword, kind=base.kind, target=target, via=base.via, tool=base.tool,
        speed_m_s=base.speed_m_s, speed_fraction=base.speed_fraction, accel_fraction=base.accel_fraction,
        zone_m=0.0, time_s=base.time_s, load_kg=base.load_kg, tuning=base.tuning, short=short,
        signal_before_end_s=gun.reaction_s + EARLY_S,
    )
    ticket = yield request
    while ticket.signalled_s is None and not ticket.done:  # Wait(Act->MoveSignal)
        yield None
    if ticket.done and ticket.outcome == "fault":
        raise ticket.error if ticket.error is not None else BehaviourError("the move failed")
    # The reference ends REACTION after the signal; the arm stands still a little later (its servo and gears
    # settle). With the settling measured on an earlier weld of the same kind (ShortMove or not), the gun is
    # closed that much later, so it closes as the TCP stops; the first weld of each kind closes it when the TCP
    # is seen still and measures the settling.
    # (a motion shorter than REACTION signals at its end)
    reference_end_s = ticket.signalled_s + (0.0 if ticket.done else gun.reaction_s + EARLY_S)
    positions = [(robot.time_s(), _position(robot.tcp_pose(call.tool)))]
    still_s: float | None = None

    slow_from: list[float] = []  # the start of the cycle since which the TCP has been slow

    def watch() -> None:
        nonlocal still_s
        positions.append((robot.time_s(), _position(robot.tcp_pose(call.tool))))
        if still_s is not None or positions[-1][0] < reference_end_s - EARLY_S - 1e-9:
            return
        if _speed_before(positions, 1e-6) >= STILL_SHARE * gun.max_speed_m_s:
            slow_from.clear()
        elif not slow_from:
            slow_from.append(positions[-2][0])
        if slow_from and positions[-1][0] - slow_from[0] >= STILL_WINDOW_S - 1e-9:
            still_s = slow_from[0]  # slow over a welder's window: the TCP stood still from there on
    settle_s = gun.settle_s.get(short)
    if settle_s is None:
        while still_s is None and robot.time_s() < reference_end_s + SETTLE_WAIT_S:
            yield None
            watch()
    else:
        while robot.time_s() < reference_end_s - gun.reaction_s + settle_s - 1e-9:
            yield None
            watch()
    gun.Close()  # the gun closes REACTION from now: when the TCP stands still
    gun.signals.append(robot.time_s())
    closes_at = robot.time_s() + gun.reaction_s
    while robot.time_s() < closes_at - 1e-9:
        yield None
        watch()
    closed = positions[-1][1]
    yield None  # the TCP over the first cycle the gun holds the sheet: its speed and where it is
    watch()
    last = positions[-1][1]
    while still_s is None and robot.time_s() < reference_end_s + SETTLE_WAIT_S:
        yield None
        watch()
    if still_s is not None:  # what this motion's settling was: the next weld's prediction
        gun.settle_s[short] = max(-EARLY_S, still_s - reference_end_s)
        gun.stops.append(still_s)
    speed = math.dist(last, closed) / robot.dt_s
    log = process_log(robot)
    offset = math.dist(last, (target.x, target.y, target.z)) if type(target) is Pose else 0.0
    reason = ""
    if speed > gun.max_speed_m_s:
        reason = f"the TCP moved at {1000 * speed:.1f} mm/s (MAX_SPEED {1000 * gun.max_speed_m_s:.1f} mm/s)"
    elif offset > gun.max_offset_m:
        reason = f"the TCP was {1000 * offset:.2f} mm off the spot (MAX_OFFSET {1000 * gun.max_offset_m:.2f} mm)"
    if reason:
        gun.Open()  # abort the weld: the welder gives no WELD_OK
        log.welds.append(WeldRecord(gun.name, robot.time_s(), last, speed, offset, False, reason))
        while not ticket.done:
            yield None
        raise log.fault(WeldFault(f"{gun.name}: bad weld, the gun closed while {reason}; the weld was aborted"),
                        robot.time_s())
    while not ticket.done:
        yield None
    if ticket.outcome == "fault":
        gun.Open()
        raise ticket.error if ticket.error is not None else BehaviourError("the move failed")
    deadline = robot.time_s() + gun.reaction_s + gun.weld_time_s + WELD_OK_MARGIN_S
    while not gun.weld_ok():  # Gun->WaitWelding()
        if robot.time_s() > deadline:
            gun.Open()
            log.welds.append(WeldRecord(gun.name, closes_at, last, speed, offset, False, "no WELD_OK"))
            raise log.fault(Timeout(
                f"WELDMOVE: {gun.name} gave no WELD_OK within "
                f"{1000 * (gun.reaction_s + gun.weld_time_s + WELD_OK_MARGIN_S):.0f} ms of the motion's end "
                f"(REACTION {1000 * gun.reaction_s:.0f} ms + WELD_TIME {1000 * gun.weld_time_s:.0f} ms "
                f"+ {1000 * WELD_OK_MARGIN_S:.0f} ms): the welder failed or rejected the weld (a gun that closes "
                f"before the robot stands still, i.e. faster than REACTION, makes a bad weld); check the welder, "
                f"its WELD_OK input and the gun's REACTION"), robot.time_s())
        yield None
    gun.Open()
    gun.welds += 1
    log.welds.append(WeldRecord(gun.name, closes_at, last, speed, offset, True))


def _speed_before(positions: list[tuple[float, tuple[float, float, float]]], window_s: float = STILL_WINDOW_S) -> float:
    """The TCP's speed over the last `window_s` (m/s); infinite until that much has been watched."""
    now_s, here = positions[-1]
    for then_s, there in reversed(positions[:-1]):
        if now_s - then_s >= window_s - 1e-9:
            return math.dist(here, there) / (now_s - then_s)
    return math.inf



def _position(pose: Pose) -> tuple[float, float, float]:
    return (pose.x, pose.y, pose.z)


def _as_move(call: MotionCall) -> MotionCall:
    """The statement as a standard joint move (SPEED, ACCEL, TIME, LOAD... read the same way)."""
    from dataclasses import replace

    return replace(call, keyword="MOVE")


def register_behaviour(registry: Any) -> None:
    """Fill the behaviour slots of SpotGun and WELDMOVE."""
    import dataclasses

    kind = registry.install_kinds.get("SpotGun")
    if kind is not None and kind.factory is None:
        registry.install_kinds["SpotGun"] = dataclasses.replace(kind, factory=SpotGun)
    spec = registry.motions.get("WELDMOVE")
    if spec is not None and spec.execute is None:
        registry.motions["WELDMOVE"] = dataclasses.replace(spec, execute=weldmove)
