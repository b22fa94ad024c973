"""The plant room's drives: the realistic plant's motors as MuJoCo PID actuators, so the servo law runs in C."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.errors import UsageError
from orc_rpl.plant.sim import mj_step

#: The drives' inputs (MuJoCo's input signature of a pid actuator): position, velocity and feed-forward set-points.
DRIVE_INPUTS = 1 | 2 | 4

multiply = np.multiply


class PidDrives:
    """The drives of a cell whose robot motors are `pid` actuators (mixed into RealisticCell).

    The cell provides the MuJoCo model and data, `n_joints`, its live state views, the speed noise
    (`_noise`, `_noise_row`, `_new_noise`), `_measure`, `_after_step`, the thermal bookkeeping
    (`_copper_rows`: the forces of a call's steps) and calls `_setup_drives` once compiled.
    """

    def _setup_drives(self) -> None:
        """Views on the drives' inputs, gains and integrals (MuJoCo's own arrays: written in place)."""
        m, d, n = self._model, self._data, self.n_joints
        if not (np.array_equal(m.actuator_ctrladr[:n], 3 * np.arange(n)) and np.array_equal(m.actuator_actadr[:n], np.arange(n))):
            raise UsageError(f"robot {self.robot!r}: its drives must be the cell's first actuators")
        self._inputs_flat = d.ctrl[: 3 * n]
        self._ff_in = d.ctrl[2 : 3 * n : 3]
        self._integral_state = d.act[:n]
        self._force = d.actuator_force[:n]
        self._ki = m.actuator_gainprm[:n, 0]
        self._minus_kp = m.actuator_biasprm[:n, 1]
        self._minus_kd = m.actuator_biasprm[:n, 2]
        self._integral_state_max = m.actuator_dynprm[:n, 0]
        self._inputs, self._forces = np.zeros((0, n, 3)), np.zeros((0, n))
        self._old_integral = np.zeros(n)

    def torque_mode(self) -> None:
        """Drives as torque motors: gains and integral at zero, the force is the feed-forward input."""
        for view in (self._ki, self._minus_kp, self._minus_kd, self._integral_state_max, self._integral_state):
            view[:] = 0.0

    def set_drive_gains(self, kp_nm_rad: np.ndarray, kd_nm_s: np.ndarray, ki_nm_rad_s: np.ndarray,
                        integral_max_nm: np.ndarray, integral_nm: np.ndarray | None = None) -> None:
        """The drives' PID gains from the next step (per joint): tau = kp e + kd (qd_ref - qd) + ki * int(e) + ff.

        The integral torque ki * int(e) becomes `integral_nm` (None: it is kept across the change of
        ki) and is limited to +-integral_max_nm; a joint with ki = 0 has none.
        """
        ki, state, state_max = self._ki, self._integral_state, self._integral_state_max
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

    def true_live_state(self) -> tuple[np.ndarray, np.ndarray]:
        """The plant's own (q, qd) as read-only views that follow it step by step (copies if its joints are not contiguous)."""
        if self._q_live is not None:
            return self._q_live, self._qd_live
        return self.true_q, self.true_qd

    def integral_nm(self) -> np.ndarray:
        """The drives' integral torque ki * int(e) now (N m)."""
        return self._integral_state * self._ki

    def set_integral_nm(self, torque_nm: np.ndarray) -> None:
        """Set the drives' integral torque (a hand-over from the Python servo law); zero where ki is."""
        state = self._integral_state
        state[:] = 0.0
        np.divide(torque_nm, self._ki, out=state, where=self._ki > 0.0)

    def noise_rows(self, n_steps: int) -> np.ndarray:
        """The speed noise the servo reads during the next n_steps steps (one row a step, the current first)."""
        end = self._noise_row + n_steps
        if end >= len(self._noise):
            self._noise = np.concatenate([self._noise[self._noise_row:], self._new_noise()])
            self._noise_row, end = 0, n_steps
        return self._noise[self._noise_row:end]

    def drive(self, position_rows: np.ndarray, velocity_rows: np.ndarray, ff_rows: np.ndarray,
              each_step: Any = None) -> None:
        """Run the drives' loops in C for len(position_rows) steps with these set-points, one row a step.

        What the servo measures is updated at the end (and after every step when `each_step`, a
        callable, is given: it is called after every step).
        """
        n_steps = len(position_rows)
        self.noise_rows(n_steps)  # the rows the measurements of these steps read exist
        inputs, forces = self._inputs, self._forces
        if inputs.shape[0] != n_steps:
            inputs = self._inputs = np.zeros((n_steps, self.n_joints, 3))
            forces = self._forces = np.zeros((n_steps, self.n_joints))
        inputs[:, :, 0], inputs[:, :, 1], inputs[:, :, 2] = position_rows, velocity_rows, ff_rows
        model, data, flat, force = self._model, self._data, self._inputs_flat, self._force
        after = self._after_step if (self._watch_contacts or self.io.processes or self.realtime) else None
        for row, applied in zip(inputs.reshape(n_steps, -1), forces):
            flat[:] = row
            mj_step(model, data)
            applied[:] = force
            if after is not None:
                after(data)
            if each_step is not None:
                self._noise_row += 1
                self._measure()
                each_step()
        self._copper_rows(forces)
        if each_step is None:
            self._noise_row += n_steps
            self._measure()
