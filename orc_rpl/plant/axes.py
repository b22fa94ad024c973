"""The plant room's external axes: a track's carriage, a positioner's tilt and turn, a conveyor's belt, as MuJoCo joints with their own drives.

Each axis is a body on a slide or hinge joint, driven by a position servo computed inside MuJoCo (a
`general` actuator: its reference is an integrator state the drive ramps each motion cycle, its law
kp (r - q) - kv q', so a commanded reference r = e + (kv/kp) e' + (m/kp) e'' makes it follow e).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: Prefix of every axis element in the built scene ("axis/turn").
AXIS_PREFIX = "axis/"
#: Closed-loop bandwidth of an axis drive (rad/s): critically damped, kp = m w^2, kv = 2 m w.
DRIVE_BANDWIDTH_RAD_S = 300.0


@dataclass(frozen=True, slots=True)
class AxisDrive:
    """One external axis of the simulated cell."""

    name: str
    rotary: bool
    direction: tuple[float, float, float]           #: unit axis in the body's frame
    parent: str                                     #: the axis body it rides on, "" for the cell
    position_m: tuple[float, float, float]          #: the body's frame at value 0, in its parent's frame
    rotation: tuple[float, ...]                     #: its orientation, 3x3 row by row
    range_si: tuple[float, float]
    home_si: float
    mass_si: float                                  #: moving mass (kg) or inertia about the axis (kg m2) the drive is tuned for
    conveyor_speed_si: float = 0.0                  #: a conveyor's belt speed (m/s): it runs from the start, nothing commands it

    @property
    def conveyor(self) -> bool:
        return self.conveyor_speed_si != 0.0

    @property
    def kp(self) -> float:
        return self.mass_si * DRIVE_BANDWIDTH_RAD_S ** 2

    @property
    def kv(self) -> float:
        return 2.0 * self.mass_si * DRIVE_BANDWIDTH_RAD_S

    @property
    def lag_s(self) -> float:
        """The drive's time lag on a ramp without its lead (kv / kp)."""
        return self.kv / self.kp

    def command(self, e: float, ed: float, edd: float) -> float:
        """The drive reference that makes the axis follow (e, e', e''): the lag and the inertia led away."""
        return e + self.lag_s * ed + self.mass_si / self.kp * edd


def add_axes(mujoco: Any, spec: Any, axes: tuple[AxisDrive, ...]) -> dict[str, Any]:
    """Add the axes' bodies and joints to a scene (parents before children); returns the bodies by name."""
    bodies: dict[str, Any] = {}
    for axis in axes:
        parent = bodies[axis.parent] if axis.parent else spec.worldbody
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.asarray(axis.rotation, dtype=float))
        body = parent.add_body(name=AXIS_PREFIX + axis.name, pos=list(axis.position_m), quat=list(quat))
        # a balanced carriage or table: its mass on the axis, so gravity does not load the drive
        inertia = axis.mass_si if axis.rotary else 1.0
        body.mass = 1.0 if axis.rotary else axis.mass_si
        body.inertia = [inertia, inertia, inertia]
        body.explicitinertial = True
        kind = mujoco.mjtJoint.mjJNT_HINGE if axis.rotary else mujoco.mjtJoint.mjJNT_SLIDE
        body.add_joint(name=AXIS_PREFIX + axis.name, type=kind, axis=list(axis.direction), ref=0.0)
        bodies[axis.name] = body
    return bodies


def add_drives(mujoco: Any, spec: Any, axes: tuple[AxisDrive, ...]) -> None:
    """The axes' drives, added after the robot's motors so that the robot's come first."""
    for axis in axes:
        gain = np.zeros(10)
        gain[0] = axis.kp
        bias = np.zeros(10)
        bias[1], bias[2] = -axis.kp, -axis.kv
        spec.add_actuator(name=AXIS_PREFIX + axis.name, target=AXIS_PREFIX + axis.name,
                          trntype=mujoco.mjtTrn.mjTRN_JOINT, dyntype=mujoco.mjtDyn.mjDYN_INTEGRATOR,
                          gaintype=mujoco.mjtGain.mjGAIN_FIXED, biastype=mujoco.mjtBias.mjBIAS_AFFINE,
                          gainprm=list(gain), biasprm=list(bias))


class AxisDrives:
    """The external axes of a compiled cell: command their references, read where they are."""

    def __init__(self, mujoco: Any, model: Any, data: Any, axes: tuple[AxisDrive, ...]) -> None:
        self.axes = {a.name: a for a in axes}
        self._data = data
        ids = {a.name: (mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, AXIS_PREFIX + a.name),
                        mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, AXIS_PREFIX + a.name),
                        mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, AXIS_PREFIX + a.name)) for a in axes}
        self._qpos = {n: int(model.jnt_qposadr[j]) for n, (j, _, _) in ids.items()}
        self._qvel = {n: int(model.jnt_dofadr[j]) for n, (j, _, _) in ids.items()}
        self._act = {n: int(model.actuator_actadr[a]) for n, (_, a, _) in ids.items()}
        # the ctrl address, not the actuator's index: the robot's drives before the axes take several inputs each
        self._ctrl = {n: int(model.actuator_ctrladr[a]) for n, (_, a, _) in ids.items()}
        self._body = {n: b for n, (_, _, b) in ids.items()}
        self.references: dict[str, float] = {}

    def reset(self) -> None:
        """Every axis at its home, at rest, its drive holding there."""
        for name, axis in self.axes.items():
            self._data.qpos[self._qpos[name]] = axis.home_si
            self._data.act[self._act[name]] = axis.home_si
            self._data.ctrl[self._ctrl[name]] = 0.0
            self.references[name] = axis.home_si
            if axis.conveyor:
                # a running belt: the drive's reference ramps at the belt speed for ever (its integrator's input), led
                # by the drive's lag so that the belt is at speed * t from the first step (kp (r - q) = kv q')
                v = axis.conveyor_speed_si
                self._data.qvel[self._qvel[name]] = v
                self._data.act[self._act[name]] = axis.home_si + axis.lag_s * v
                self._data.ctrl[self._ctrl[name]] = v

    def command(self, ends: dict[str, float], period_s: float) -> None:
        """Ramp each named axis' drive reference from where it is to `ends[name]` over the next period_s."""
        data = self._data
        for name, end in ends.items():
            start = self.references[name]
            data.act[self._act[name]] = start
            data.ctrl[self._ctrl[name]] = (end - start) / period_s
            self.references[name] = end

    def hold(self) -> None:
        """Stop every ramp: the drives hold their last reference."""
        for name, axis in self.axes.items():
            if axis.conveyor:
                continue  # a belt runs on
            self._data.act[self._act[name]] = self.references[name]
            self._data.ctrl[self._ctrl[name]] = 0.0

    def values(self) -> dict[str, float]:
        """Where the axes are (m or rad), measured."""
        return {name: float(self._data.qpos[adr]) for name, adr in self._qpos.items()}

    def body_pose(self, name: str) -> np.ndarray:
        """The frame an axis moves (4x4, in the scene)."""
        t = np.eye(4)
        b = self._body[name]
        t[:3, :3] = self._data.xmat[b].reshape(3, 3)
        t[:3, 3] = self._data.xpos[b]
        return t
