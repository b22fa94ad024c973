"""The hardware room's motion backend: a real arm on a servo bus, its position loops in the servos (thesis 5.4).

Each motion cycle is one SYNC WRITE of the goal positions and one SYNC READ of the state block
(position, speed, load or current, voltage, temperature, alarms), then a wait for the next cycle on
the wall clock. The servos' own speed and acceleration profiles are switched off so they follow the
streamed references. The class meets the motion layer's `Backend` protocol by its shape.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from orc_rpl.errors import DriveFault, UsageError
from orc_rpl.hardware.bus import ServoBus
from orc_rpl.hardware.droop import SETTLED_COUNTS, DroopCorrection
from orc_rpl.hardware.grip import GripWatch
from orc_rpl.hardware.calibration import Calibration
from orc_rpl.hardware.packets import BusError, Status
from orc_rpl.hardware.registers import CURRENT_BASED_POSITION_MODE, alarm_text

#: The motion period is the 90th percentile of measured bus cycles times this margin, in whole ms
#: (a slower cycle now and then is absorbed: the pacing never rushes to catch up).
PERIOD_MARGIN = 1.5
MIN_PERIOD_S = 0.002
MEASURED_CYCLES = 40
#: Dynamixel bus watchdog: the servos stop by themselves when the host is silent this long (20 ms units).
WATCHDOG_UNITS = 5
READ_ATTEMPTS = 3  #: sync reads of one cycle before a servo that does not answer is a DriveFault
RANGE_SLACK_COUNTS = 4  #: slack of the calibrated range check (the gear play and a count)


class BusBackend:
    """The joints of one robot on one bus; q, qd and the load come from the last sync read."""

    measures_torque = False  #: the servos report load (PWM duty) and current, not joint torque
    real_arm = True          #: what the user sees says so: no "simulated" times, cells or channels

    def __init__(self, bus: ServoBus, calibration: Calibration, motion_period_s: float | None = None) -> None:
        self.bus, self.cal, self.model = bus, calibration, calibration.model
        self.ids = [j.servo_id for j in calibration.joints]
        self._goal = self.model.reg("goal_position")
        self._block = self.model.state_block
        self.settle_rad = SETTLED_COUNTS * self.model.rad_per_count()
        self._droop = DroopCorrection(len(self.ids), self.model.rad_per_count())
        self.settle_rad_s = 0.05
        self.voltage_v = np.zeros(len(self.ids))
        self.temperature_c = np.zeros(len(self.ids))
        self.current_a = np.zeros(len(self.ids))
        self._q = np.zeros(len(self.ids))
        self._qd = np.zeros(len(self.ids))
        self._load = np.zeros(len(self.ids))
        self._counts: dict[int, int] = {}
        self._last_cycle_s = -1e9  #: when the last cycle talked to the bus (the Dynamixel watchdog)
        self._grips: dict[int, GripWatch] = {}  #: the last move of each gripper servo
        self._connect()
        self.cycle_times_s: list[float] = []
        self.servo_period_s = motion_period_s if motion_period_s is not None else self._choose_period()
        self.overruns = 0
        self._cycles = 0
        self._t0 = time.perf_counter()

    # -- the Backend protocol ---------------------------------------------------------------

    def advance(self, q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray) -> None:
        q = q_ref[-1]
        self._check_range(q)
        self._cycle(self.cal.to_counts(self._droop.goal(q, self._q, self._qd)))
        self._cycles += 1
        self._pace()

    def q(self) -> np.ndarray:
        return self._q

    def qd(self) -> np.ndarray:
        return self._qd

    def torque(self) -> np.ndarray:
        """An estimate from the servos' load reading (share of the stall torque): not a torque measurement."""
        return self._load * self.model.stall_torque_nm

    def time_s(self) -> float:
        return self._cycles * self.servo_period_s

    def reset(self, q: np.ndarray) -> None:
        raise UsageError("a real arm cannot be put at a position: move it there")

    # -- safety -----------------------------------------------------------------------------------

    def hold(self, ids: list[int] | None = None) -> None:
        """Goal = the last measured position for the given servos (all by default): they stop and hold."""
        ids = self.ids if ids is None else ids
        data = {i: self._goal.encode(self._counts[i]) for i in ids if i in self._counts}
        if data:
            self.bus.sync_write(self._goal.address, self._goal.size, data)

    def torque_off(self) -> None:
        """Every servo limp (explicit only: the arm falls or rests on its gearboxes)."""
        self.bus.sync_write(self.model.reg("torque_enable").address, 1, {i: b"\x00" for i in self._all_ids()})

    def close(self) -> None:
        self.bus.close()

    # -- cycles -----------------------------------------------------------------------------------

    def _cycle(self, counts: list[int]) -> None:
        try:
            self._keep_watchdog()
            self.bus.sync_write(self._goal.address, self._goal.size,
                                {i: self._goal.encode(c) for i, c in zip(self.ids, counts)})
        except BusError as error:  # the port itself failed
            self._lost(error)
        self._read_state()

    def _keep_watchdog(self) -> None:
        """Before goals are sent: a Dynamixel watchdog that may have fired since the host last talked is set again."""
        now = time.perf_counter()
        if self.model.family == "dynamixel" and now - self._last_cycle_s > 0.5 * WATCHDOG_UNITS * 0.020:
            self._rearm_watchdog()
        self._last_cycle_s = now

    def _rearm_watchdog(self) -> None:
        """After a pause of the host (planning, a WAIT on input), the watchdog may have fired: clear and set it again.

        A fired watchdog stopped the servos where they were; the motion layer held its reference meanwhile
        unless the host itself stalled in the middle of a motion (then the arm catches up with the reference).
        """
        watchdog = self.model.reg("bus_watchdog").address
        self.bus.sync_write(watchdog, 1, {i: b"\x00" for i in self._all_ids()})
        self.bus.sync_write(watchdog, 1, {i: bytes((WATCHDOG_UNITS,)) for i in self._all_ids()})

    def _read_state(self) -> None:
        address, length = self._block
        for attempt in range(READ_ATTEMPTS):
            try:
                replies = self.bus.sync_read(address, length, self.ids)
                break
            except BusError as error:
                # a lost or damaged reply now and then is noise on a desktop wire (or a busy host); the
                # same exchange failing READ_ATTEMPTS times running is a fault
                if attempt == READ_ATTEMPTS - 1:
                    self._lost(error)
        alarms = [(i, s) for i, s in replies.items() if self.bus.codec.alarm(s.error)]
        model = self.model
        counts = []
        for k, servo_id in enumerate(self.ids):
            block = replies[servo_id].params
            count = model.value("present_position", block)
            self._counts[servo_id] = count
            counts.append(count)
            self._qd[k] = self.cal.joints[k].direction * model.value("present_speed", block) * model.speed_rad_s_per_unit
            self.voltage_v[k] = model.value("present_voltage", block) * model.voltage_v_per_unit
            self.temperature_c[k] = model.value("present_temperature", block)
            if model.family == "feetech":
                self._load[k] = self.cal.joints[k].direction * model.value("present_load", block) / 1000.0
            else:
                self.current_a[k] = model.value("present_current", block) * model.current_a_per_unit
                self._load[k] = self.cal.joints[k].direction * self.current_a[k] / model.stall_current_a
        self._q = np.array(self.cal.to_rad(counts))
        if alarms:
            self._alarm(*alarms[0])

    def _lost(self, error: BusError) -> None:
        """A servo did not answer (or answered garbage): the others hold, the program gets a DriveFault."""
        others = [i for i in self.ids if i != error.servo_id]
        try:
            self.hold(others)
        except BusError:
            pass
        if error.servo_id is None:
            raise DriveFault(f"the servo bus: {error.reason}") from None
        raise DriveFault(f"{self._name(error.servo_id)}: {error.reason}; the other joints hold their positions") from None

    def _alarm(self, servo_id: int, status: Status) -> None:
        if self.model.family == "feetech":
            text = alarm_text(status.error)
        else:
            text = alarm_text(self.bus.read(servo_id, self.model.reg("hardware_error").address, 1)[0])
        self.hold([i for i in self.ids if i != servo_id])
        raise DriveFault(f"{self._name(servo_id)} reports {text} on {self.bus.port}: its torque is off; "
                         "the other joints hold their positions")

    def _name(self, servo_id: int | None) -> str:
        if servo_id in self.ids:
            return f"servo {servo_id} (joint {self.ids.index(servo_id) + 1})"
        return "the servo bus" if servo_id is None else f"servo {servo_id}"

    def _check_range(self, q: np.ndarray) -> None:
        # An arm left limp beyond its recorded range (moved there by hand after calibrating) may come back:
        # a reference between where the joint is and its range is allowed, one further out never. A few
        # counts of slack: the gear play and the encoder's count.
        slack = RANGE_SLACK_COUNTS * self.model.rad_per_count()
        for k, joint in enumerate(self.cal.joints):
            if not min(joint.min_rad, self._q[k]) - slack <= q[k] <= max(joint.max_rad, self._q[k]) + slack:
                self.hold()
                raise DriveFault(f"joint {k + 1} reference {math.degrees(q[k]):.2f} deg is outside its calibrated range "
                                 f"{math.degrees(joint.min_rad):.1f}..{math.degrees(joint.max_rad):.1f} deg; holding")

    def _pace(self) -> None:
        deadline = self._t0 + self._cycles * self.servo_period_s
        ahead = deadline - time.perf_counter()
        if ahead > 0:
            time.sleep(ahead)
        elif ahead < -self.servo_period_s:
            self.overruns += 1
            self._t0 -= ahead  # late by more than a cycle: start counting again from now, do not rush

    # -- connecting -------------------------------------------------------------------------------

    def _all_ids(self) -> list[int]:
        return self.ids + ([self.cal.gripper.servo_id] if self.cal.gripper is not None else [])

    def _connect(self) -> None:
        """Every servo answers with the expected model; profiles off, replies at once, goal = present, torque on."""
        model, bus = self.model, self.bus
        for servo_id in self._all_ids():
            # three tries: one lost reply is not yet a missing servo
            found = next((m for m in (bus.ping(servo_id) for _ in range(3)) if m is not None), None)
            if found is None:
                raise DriveFault(f"{self._name(servo_id)} does not answer on {bus.port} (check the cable, the power "
                                 "supply and the ids: orc bus scan)")
            if found != model.model_number:
                raise UsageError(f"{self._name(servo_id)} on {bus.port} is model {found}, expected {model.name} "
                                 f"({model.model_number})")
        reg = model.reg
        for servo_id in self._all_ids():
            if model.family == "feetech":
                bus.write(servo_id, reg("lock").address, b"\x00")
                bus.write(servo_id, reg("return_delay").address, b"\x00")
                bus.write(servo_id, reg("lock").address, b"\x01")
                bus.write(servo_id, reg("acceleration").address, b"\x00")      # 0: no acceleration profile
                bus.write(servo_id, reg("goal_speed").address, b"\x00\x00")    # 0: no speed profile
            else:
                bus.write(servo_id, reg("torque_enable").address, b"\x00")     # EEPROM writes need torque off
                bus.write(servo_id, reg("return_delay").address, b"\x00")
                bus.write(servo_id, reg("profile_acceleration").address, bytes(4))
                bus.write(servo_id, reg("profile_velocity").address, bytes(4))
        self._read_state()
        self.hold()
        gripper = self.cal.gripper
        if gripper is not None:
            if model.family == "dynamixel":
                # current-based position control: the gripper squeezes with its goal current, no harder
                bus.write(gripper.servo_id, reg("operating_mode").address, bytes((CURRENT_BASED_POSITION_MODE,)))
            present = model.value("present_position", bus.read(gripper.servo_id, *self._block))
            bus.write(gripper.servo_id, self._goal.address, self._goal.encode(present))
        bus.sync_write(reg("torque_enable").address, 1, {i: b"\x01" for i in self._all_ids()})

    def _choose_period(self) -> float:
        """Time whole cycles (goal = where the arm is) and take a slow one, with a margin."""
        for _ in range(MEASURED_CYCLES):
            start = time.perf_counter()
            self._cycle(self.cal.to_counts(self._q))
            self.cycle_times_s.append(time.perf_counter() - start)
        typical_ms = 1000.0 * float(np.percentile(self.cycle_times_s, 90))
        return max(MIN_PERIOD_S, math.ceil(PERIOD_MARGIN * typical_ms) / 1000.0)

    # -- a gripper (or any other servo beside the arm's joints) ------------------------------------

    def drive_servo(self, servo_id: int, angle_rad: float, current_limit_a: float) -> None:
        """Send a servo that is not an arm joint to an angle; on STS its torque limit is set from the current limit."""
        if servo_id in self.ids:
            raise UsageError(f"servo {servo_id} is joint {self.ids.index(servo_id) + 1} of the arm, not a gripper")
        gripper = self.cal.gripper
        zero, direction = (gripper.zero_count, gripper.direction) if gripper and gripper.servo_id == servo_id \
            else (self.model.center_count, 1)
        count = zero + direction * int(round(angle_rad / self.model.rad_per_count()))
        try:
            self._keep_watchdog()  # a fired watchdog refuses goals
            model = self.model
            if "torque_limit" in model.registers:
                # the STS limits torque (0.1 % units of its stall torque): the current limit as a share of stall
                share = max(0, min(1000, int(round(1000.0 * current_limit_a / model.stall_current_a))))
                self.bus.write(servo_id, model.reg("torque_limit").address, model.reg("torque_limit").encode(share))
            else:
                # Dynamixel in current-based position mode: the goal current caps the squeeze
                units = max(1, int(round(current_limit_a / model.current_a_per_unit)))
                self.bus.write(servo_id, model.reg("goal_current").address, model.reg("goal_current").encode(units))
            self.bus.write(servo_id, self._goal.address, self._goal.encode(count))
            self.bus.write(servo_id, self.model.reg("torque_enable").address, b"\x01")
        except BusError as error:
            raise DriveFault(f"gripper servo {servo_id}: {error.reason}") from None
        self._grips[servo_id] = GripWatch(count, current_limit_a)

    def servo_arrived(self, servo_id: int) -> bool:
        """True when the servo is within a few counts of its goal, or has stopped (a gripper squeezing a part)."""
        for attempt in range(READ_ATTEMPTS):  # a lost reply now and then is noise, as in the motion cycle
            try:
                block = self.bus.read(servo_id, *self._block)
                break
            except BusError as error:
                if attempt == READ_ATTEMPTS - 1:
                    raise DriveFault(f"gripper servo {servo_id}: {error.reason}") from None
        model = self.model
        count, speed = model.value("present_position", block), model.value("present_speed", block)
        if model.family == "feetech":
            current_a = abs(model.value("present_load", block)) / 1000.0 * model.stall_current_a
        else:
            current_a = abs(model.value("present_current", block)) * model.current_a_per_unit
        grip = self._grips.get(servo_id)
        return True if grip is None else grip.arrived(count, speed, current_a)

    def servo_holding(self, servo_id: int) -> bool:
        """True when the servo's last move stopped on an object, squeezing it at its current cap (a grip)."""
        grip = self._grips.get(servo_id)
        return grip is not None and grip.holding

    def describe(self) -> dict[str, Any]:
        """Figures for the run's summary: the bus, the period chosen and what the cycles measured."""
        return {"port": self.bus.port, "bus": self.model.family, "servo": self.model.name,
                "motion_period_ms": 1000.0 * self.servo_period_s, "overruns": self.overruns}
