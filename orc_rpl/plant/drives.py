"""The plant room's drives: the realistic plant's motors as MuJoCo PID actuators, so the servo law runs in C."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.sim import mj_step

#: The drives' inputs (MuJoCo's input signature of a pid actuator): position, velocity and feed-forward set-points.
DRIVE_INPUTS = 1 | 2 | 4

multiply = np.multiply
add_reduce = np.add.reduce


class PidDrives:
    """The drives of a cell whose robot motors are `pid` actuators: a part the cell (RealisticCell) holds.

    Owns the views on MuJoCo's drive inputs, gains and integral states; the cell it is made for keeps
    the measurements (`noise_rows`, `_measure`), `_after_step` and the thermal bookkeeping
    (`_copper_rows`: the forces of a call's steps), which `drive` calls.
    """

    def __init__(self, cell: Any) -> None:
        """Views on the drives' inputs, gains and integrals (MuJoCo's own arrays: written in place)."""
        self.cell = cell
        m, d, n = cell._model, cell._data, cell.n_joints
        if not (np.array_equal(m.actuator_ctrladr[:n], 3 * np.arange(n)) and np.array_equal(m.actuator_actadr[:n], np.arange(n))):
            raise UsageError(f"robot {cell.robot!r}: its drives must be the cell's first actuators")
        self.n_joints = n
        self._inputs_flat = d.ctrl[: 3 * n]
        self.ff_in = d.ctrl[2 : 3 * n : 3]              #: the feed-forward inputs (the torque in torque mode)
        self.integral_state = d.act[:n]                 #: the integral of the position error (rad s)
        self.force = d.actuator_force[:n]               #: the forces of the last step (N m)
        self.ki = m.actuator_gainprm[:n, 0]             #: the integral gains (N m / (rad s))
        self._minus_kp = m.actuator_biasprm[:n, 1]
        self._minus_kd = m.actuator_biasprm[:n, 2]
        self._integral_state_max = m.actuator_dynprm[:n, 0]
        self._inputs, self._forces = np.zeros((0, n, 3)), np.zeros((0, n))
        #: the mean of each motor's torque over the last `drive` call (N m): the current a drive reports
        self.mean_force = np.zeros(n)
        self._input_rows = self._inputs.reshape(0, 3 * n)
        # what a kernel reads and writes of the plant, after the caller's own arguments (MuJoCo's arrays, in place)
        self._kernel_arrays = (d.ctrl, d.act, d.actuator_force, m.actuator_gainprm, m.actuator_biasprm,
                               m.actuator_dynprm, d.qpos, d.qvel, cell._qpos, cell._qvel, cell._count_per_rad,
                               cell._rad_per_count, cell._q_meas, cell._qd_meas, cell._tau_sq_sum)
        #: the part of them a cycle with the drives as torque motors reads and writes (no gains, no integrals)
        self._torque_kernel_arrays = (d.ctrl, d.actuator_force, d.qpos, d.qvel, cell._qpos, cell._qvel,
                                      cell._count_per_rad, cell._rad_per_count, cell._q_meas, cell._qd_meas,
                                      cell._tau_sq_sum)
        self._addresses = (m._address, d._address)

    def torque_mode(self) -> None:
        """Drives as torque motors: gains and integral at zero, the force is the feed-forward input."""
        for view in (self.ki, self._minus_kp, self._minus_kd, self._integral_state_max, self.integral_state):
            view[:] = 0.0

    def set_drive_gains(self, kp_nm_rad: np.ndarray, kd_nm_s: np.ndarray, ki_nm_rad_s: np.ndarray,
                        integral_max_nm: np.ndarray, integral_nm: np.ndarray | None = None) -> None:
        """The drives' PID gains from the next step (per joint): tau = kp e + kd (qd_ref - qd) + ki * int(e) + ff.

        The integral torque ki * int(e) becomes `integral_nm` (None: it is kept across the change of
        ki) and is limited to +-integral_max_nm; a joint with ki = 0 has none.
        """
        ki, state, state_max = self.ki, self.integral_state, self._integral_state_max
        if integral_nm is None:
            multiply(state, ki, state)  # the integral torque, kept
        else:
            state[:] = integral_nm
        ki[:] = ki_nm_rad_s
        np.negative(kp_nm_rad, out=self._minus_kp)
        np.negative(kd_nm_s, out=self._minus_kd)
        if True in (ki <= 0.0).tolist():
            positive = ki > 0.0
            np.divide(state, ki, out=state, where=positive)
            state[~positive] = 0.0
            np.divide(integral_max_nm, ki, out=state_max, where=positive)
            state_max[~positive] = 0.0
        else:
            np.divide(state, ki, state)
            np.divide(integral_max_nm, ki, state_max)

    def integral_nm(self) -> np.ndarray:
        """The drives' integral torque ki * int(e) now (N m)."""
        return self.integral_state * self.ki

    def set_integral_nm(self, torque_nm: np.ndarray) -> None:
        """Set the drives' integral torque (a hand-over from the Python servo law); zero where ki is."""
        state = self.integral_state
        state[:] = 0.0
        np.divide(torque_nm, self.ki, out=state, where=self.ki > 0.0)

    def kernel_fits(self) -> bool:
        """True when nothing must run between the steps (contacts to watch, process models, pacing):
        a motion cycle may then be one compiled kernel (`run_kernel`)."""
        cell = self.cell
        return not (cell._watch_contacts or cell.io.processes or cell.realtime)

    def kernel_arrays(self) -> tuple[Any, ...]:
        """What a compiled motion cycle reads and writes of the plant, its last arguments (`run_kernel`)."""
        return self._kernel_arrays

    def torque_kernel_arrays(self) -> tuple[Any, ...]:
        """`kernel_arrays` less the drives' gains and integrals, for a cycle that runs them as torque motors:
        ctrl, the forces, qpos, qvel, the joints' addresses in them, the encoder's counts per rad and rad per
        count, the measured angles and speeds, the copper sums."""
        return self._torque_kernel_arrays

    def run_kernel(self, cycle: Any, head: tuple[Any, ...], tail: tuple[Any, ...]) -> None:
        """`cycle(model, data, *head, *tail)`: a compiled motion cycle (servo/drive_kernels.py) that steps
        the plant len(head[0]) times through `drive_kernels.drive_rows` and measures
        (`drive_kernels.measure`); `tail` ends with `kernel_arrays()` (or `torque_kernel_arrays()`). Then the
        cell's bookkeeping as after `drive`: the noise rows used, the thermal model's steps."""
        cycle(*self._addresses, *head, *tail)
        cell, n_steps = self.cell, len(head[0])
        cell._noise_row += n_steps
        cell._count_steps(n_steps)

    def drive(self, position_rows: np.ndarray, velocity_rows: np.ndarray, ff_rows: np.ndarray,
              each_step: Any = None) -> None:
        """Run the drives' loops in C for len(position_rows) steps with these set-points, one row a step.

        What the servo measures is updated at the end (and after every step when `each_step`, a
        callable, is given: it is called after every step).
        """
        n_steps, cell = len(position_rows), self.cell
        cell.noise_rows(n_steps)  # the rows the measurements of these steps read exist
        inputs, forces = self._inputs, self._forces
        if inputs.shape[0] != n_steps:
            inputs = self._inputs = np.zeros((n_steps, self.n_joints, 3))
            forces = self._forces = np.zeros((n_steps, self.n_joints))
            self._input_rows = inputs.reshape(n_steps, -1)  # a view: one row of ctrl a step
        inputs[:, :, 0], inputs[:, :, 1], inputs[:, :, 2] = position_rows, velocity_rows, ff_rows
        model, data, flat, force = cell._model, cell._data, self._inputs_flat, self.force
        after = None if self.kernel_fits() else cell._after_step
        for row, applied in zip(self._input_rows, forces):
            flat[:] = row
            mj_step(model, data)
            applied[:] = force
            if after is not None:
                after(data)
            if each_step is not None:
                cell._noise_row += 1
                cell._measure()
                each_step()
        np.multiply(add_reduce(forces, 0), 1.0 / n_steps, self.mean_force)
        cell._copper_rows(forces)
        if each_step is None:
            cell._noise_row += n_steps
            cell._measure()
