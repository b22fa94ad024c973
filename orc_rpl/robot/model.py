"""The robot room's model: Pinocchio kinematics and dynamics behind a small numpy API."""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any

import numpy as np

from orc_rpl.robot.robots import ROBOTS, RobotSpec
from orc_rpl.errors import JointLimit, UsageError

GRAVITY_M_S2 = 9.81


def _skew(v: np.ndarray) -> np.ndarray:
    x, y, z = v.tolist()  # Python floats: a third of the time of indexing the array nine times
    return np.array(((0.0, -z, y), (z, 0.0, -x), (-y, x, 0.0)))


class ArmModel:
    """One robot's kinematics and rigid-body dynamics (the controller's model; the plant reads the same MJCF)."""

    def __init__(self, spec: RobotSpec) -> None:
        import pinocchio as pin  # the only place Pinocchio is imported

        self._pin = pin
        self.spec = spec
        self.name: str = spec.name
        self.mjcf_path: Path = spec.mjcf_path
        try:
            self._model = pin.buildModelFromMJCF(str(self.mjcf_path))
        except Exception as exc:  # Pinocchio raises bare RuntimeError/ValueError
            raise UsageError(f"cannot read robot model {self.mjcf_path}: {exc}") from None
        self.n_joints: int = int(self._model.nv)
        if self._model.nq != self.n_joints or self.n_joints != len(spec.q_min_rad):
            raise UsageError(
                f"robot {self.name!r}: {self.mjcf_path.name} has nq={self._model.nq}, nv={self._model.nv}, "
                f"but the robot spec lists {len(spec.q_min_rad)} joints (every joint must be a limited hinge)"
            )
        if not self._model.existFrame(spec.flange_frame):
            raise UsageError(f"robot {self.name!r}: no site {spec.flange_frame!r} in {self.mjcf_path.name}")
        self._data = self._model.createData()
        self._flange_id = self._model.getFrameId(spec.flange_frame)
        self._last_joint = int(self._model.frames[self._flange_id].parentJoint)
        self._flange_in_joint = self._model.frames[self._flange_id].placement
        self._bare_inertia = self._model.inertias[self._last_joint].copy()
        self._payload: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
        self._pool: Any = None  #: a copy of the model for the batched RNEA, made again when the payload changes
        #: rigid_body_rows()'s rows and the payload they were made with (the payload is the only part of the
        #: model that changes after it is made: `_apply_payload` puts a new tuple in `_payload` when it does)
        self._rows: np.ndarray | None = None
        self._rows_of: Any = None
        self._model.gravity.linear = np.array([0.0, 0.0, -GRAVITY_M_S2])
        self._lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

        self.q_min = np.array(spec.q_min_rad, dtype=float)
        self.q_max = np.array(spec.q_max_rad, dtype=float)
        self.qd_max = np.array(spec.qd_max_rad_s, dtype=float)
        self.qdd_max = np.array(spec.qdd_max_rad_s2, dtype=float)
        self.tau_max = np.array(spec.tau_max_nm, dtype=float)
        self.home_q = np.array(spec.home_q_rad, dtype=float)
        self.flange_frame: str = spec.flange_frame
        for array in (self.q_min, self.q_max, self.qd_max, self.qdd_max, self.tau_max, self.home_q):
            array.setflags(write=False)

    def __repr__(self) -> str:
        return f"ArmModel({self.name!r}, n_joints={self.n_joints})"

    # -- input checks -------------------------------------------------------

    def vector(self, value: Any, what: str = "q") -> np.ndarray:
        """`value` as a float vector of n_joints finite numbers, or a UsageError naming `what`."""
        try:
            v = np.asarray(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise UsageError(f"{what} must be {self.n_joints} numbers, got {value!r}") from None
        if v.shape != (self.n_joints,):
            raise UsageError(f"{what} must have {self.n_joints} values for robot {self.name!r}, got {v.size}")
        if not np.all(np.isfinite(v)):
            raise UsageError(f"{what} contains NaN or infinity: {np.array2string(v, precision=4)}")
        return v

    @staticmethod
    def transform(value: Any, what: str = "tool") -> np.ndarray:
        """`value` as a finite homogeneous 4x4 transform, or a UsageError naming `what`."""
        try:
            t = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise UsageError(f"{what} must be a 4x4 transform, got {value!r}") from None
        if t.shape != (4, 4):
            raise UsageError(f"{what} must be a 4x4 transform, got shape {t.shape}")
        if not np.all(np.isfinite(t)):
            raise UsageError(f"{what} contains NaN or infinity")
        r = t[:3, :3]
        if np.abs(r.T @ r - np.eye(3)).max() > 1e-6 or abs(np.linalg.det(r) - 1.0) > 1e-6:
            raise UsageError(f"{what} has a rotation part that is not a proper rotation matrix")
        return t

    def check_limits(self, q: Any, tolerance_rad: float = 1e-9) -> None:
        """Raise JointLimit naming the first joint (1-based) outside its range, in degrees."""
        q = self.vector(q)
        bad = np.flatnonzero((q < self.q_min - tolerance_rad) | (q > self.q_max + tolerance_rad))
        if bad.size:
            i = int(bad[0])
            raise JointLimit(
                f"joint {i + 1} of {self.name} at {math.degrees(q[i]):.3f} deg is outside its range "
                f"{math.degrees(self.q_min[i]):.1f}..{math.degrees(self.q_max[i]):.1f} deg"
            )

    def within_limits(self, q: np.ndarray, tolerance_rad: float = 1e-9) -> bool:
        """True when every joint of a (checked) q is inside its range."""
        return bool(np.all(q >= self.q_min - tolerance_rad) and np.all(q <= self.q_max + tolerance_rad))

    # -- kinematics -----------------------------------------------------------

    def fk(self, q: Any, tool: Any = None) -> np.ndarray:
        """Pose of the TCP in the base (world) frame as a 4x4; `tool` is flange->TCP, None for the bare flange."""
        q = self.vector(q)
        t_tool = None if tool is None else self.transform(tool)
        return self._fk(q, t_tool)

    def jacobian(self, q: Any, tool: Any = None) -> np.ndarray:
        """Geometric Jacobian (6, n) at the TCP: linear rows then angular rows, world-aligned."""
        q = self.vector(q)
        t_tool = None if tool is None else self.transform(tool)
        return self._fk_jacobian(q, t_tool)[1]

    def fk_unchecked(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
        """fk for a float array of n_joints and a checked tool, without checking them (per-cycle loggers)."""
        return self._fk(q, tool)

    def pose_and_jacobian(self, q: np.ndarray, tool: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """TCP pose and Jacobian from one kinematics pass, inputs unchecked (the inner loops of IK)."""
        return self._fk_jacobian(q, tool)

    def linear_jacobian_unchecked(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
        """The (3, n) linear rows of the TCP Jacobian, inputs unchecked (TCP speed bounds at every grid point)."""
        pin = self._pin
        j = pin.computeFrameJacobian(self._model, self._data, q, self._flange_id, self._lwa)
        if tool is None:
            return j[:3]
        t = pin.updateFramePlacement(self._model, self._data, self._flange_id).homogeneous
        return j[:3] - _skew(t[:3, :3] @ tool[:3, 3]) @ j[3:]  # as in _fk_jacobian

    def _fk(self, q: np.ndarray, tool: np.ndarray | None) -> np.ndarray:
        pin = self._pin
        pin.forwardKinematics(self._model, self._data, q)
        t = pin.updateFramePlacement(self._model, self._data, self._flange_id).homogeneous
        return t if tool is None else t @ tool

    def _fk_jacobian(self, q: np.ndarray, tool: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        """TCP pose and Jacobian from one kinematics pass (unchecked inputs; IK's inner loop)."""
        pin = self._pin
        j = pin.computeFrameJacobian(self._model, self._data, q, self._flange_id, self._lwa)
        t = pin.updateFramePlacement(self._model, self._data, self._flange_id).homogeneous
        if tool is None:
            return t, j
        r_world = t[:3, :3] @ tool[:3, 3]
        # The TCP moves with the flange's twist: v_tcp = v_flange + w x r = v_flange - [r]x w.
        j = j.copy()
        j[:3] -= _skew(r_world) @ j[3:]
        return t @ tool, j

    # -- dynamics -------------------------------------------------------------

    def _apply_payload(self, payload_kg: float, payload_com: Any) -> None:
        """Put a point mass on the last link (cached: the model only changes when the payload does)."""
        if payload_com is None:
            com = (0.0, 0.0, 0.0)
        else:
            c = np.asarray(payload_com, dtype=float).reshape(-1)
            if c.shape != (3,) or not np.all(np.isfinite(c)):
                raise UsageError(f"payload_com must be 3 finite numbers (m, flange frame), got {payload_com!r}")
            com = (float(c[0]), float(c[1]), float(c[2]))
        key = (float(payload_kg), *com)
        if key == self._payload:
            return
        if not math.isfinite(key[0]) or key[0] < 0.0:
            raise UsageError(f"payload_kg must be a finite mass >= 0, got {payload_kg!r}")
        pin = self._pin
        inertia = self._bare_inertia.copy()
        if key[0] > 0.0:
            lever = self._flange_in_joint.act(np.array(com))
            inertia = inertia + pin.Inertia(key[0], lever, np.zeros((3, 3)))
        self._model.inertias[self._last_joint] = inertia
        self._payload = key
        self._pool = None

    def inverse_dynamics(
        self, q: Any, qd: Any, qdd: Any, payload_kg: float = 0.0, payload_com: Any = None
    ) -> np.ndarray:
        """Joint torques (N m) for q, qd, qdd (RNEA, armature included); payload a point mass at `payload_com` in the flange frame."""
        q, qd, qdd = self.vector(q), self.vector(qd, "qd"), self.vector(qdd, "qdd")
        self._apply_payload(payload_kg, payload_com)
        return self._pin.rnea(self._model, self._data, q, qd, qdd).copy()

    def inverse_dynamics_unchecked(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        """RNEA with the current payload and no input checks: for the 1 kHz servo loop, which checks once."""
        return self._pin.rnea(self._model, self._data, q, qd, qdd)

    @property
    def payload(self) -> tuple[float, float, float, float]:
        """The payload the unchecked calls include: (kg, com x, y, z in the flange frame, m)."""
        return self._payload

    def inverse_dynamics_function(self) -> Any:
        """The RNEA as a bare callable f(q, qd, qdd) on this model, payload changes included, no checks.

        For the 1 kHz servo loop: one C call without a Python frame around it (about 0.1 us a step).
        """
        return functools.partial(self._pin.rnea, self._model, self._data)

    def inverse_dynamics_rows_function(self) -> Any:
        """The RNEA of k states at once as a bare callable f(q, qd, qdd, out) on (k, n) arrays, payload changes
        included, no checks: a motion cycle's servo steps in one C call (Pinocchio's batched RNEA on one
        thread, the same numbers as k calls of `inverse_dynamics_function`'s, a third cheaper)."""
        pin = self._pin

        def rows(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, out: np.ndarray) -> None:
            pool = self._pool
            if pool is None:
                pool = self._pool = pin.ModelPool(self._model, 1)
            pin.rneaInParallel(1, pool, q.T, qd.T, qdd.T, out.T)

        return rows

    def flange_in_last_joint(self) -> np.ndarray | None:
        """The flange frame in the last joint's frame (4x4), for compiled kinematics on `rigid_body_rows`; None when
        the flange does not hang on the chain's last joint."""
        if self._last_joint != self.n_joints:
            return None
        return np.array(self._flange_in_joint.homogeneous)

    def rigid_body_rows(self) -> np.ndarray | None:
        """The chain's rigid-body parameters with the current payload, a row per joint, for a compiled RNEA
        (servo/rnea_kernel.py): the joint's placement in its parent (rotation row-major 0:9, translation 9:12),
        its axis (12:15), the body's mass (15), centre of mass (16:19), rotational inertia about it (19:28,
        row-major) and the rotor's armature (28); None when the model is not a chain of revolute joints.
        Made once per payload: the same array until the payload changes (a new one then; callers only read it)."""
        if self._rows_of is not self._payload:
            self._rows, self._rows_of = self._rigid_body_rows(), self._payload
        return self._rows

    def _rigid_body_rows(self) -> np.ndarray | None:
        """`rigid_body_rows` made from the model now."""
        m = self._model
        rows = np.zeros((self.n_joints, 29))
        for i in range(1, m.njoints):
            name, joint = m.joints[i].shortname(), m.joints[i].extract()
            axis = {"JointModelRX": (1.0, 0.0, 0.0), "JointModelRY": (0.0, 1.0, 0.0), "JointModelRZ": (0.0, 0.0, 1.0)}.get(name)
            if axis is None and name == "JointModelRevoluteUnaligned":
                axis = tuple(joint.axis)
            if axis is None or m.parents[i] != i - 1 or joint.idx_v != i - 1 or i > self.n_joints:
                return None
            placement, inertia = m.jointPlacements[i], m.inertias[i]
            rows[i - 1, 0:9], rows[i - 1, 9:12] = placement.rotation.reshape(-1), placement.translation
            rows[i - 1, 12:15], rows[i - 1, 15] = axis, inertia.mass
            rows[i - 1, 16:19], rows[i - 1, 19:28] = inertia.lever, inertia.inertia.reshape(-1)
            rows[i - 1, 28] = m.armature[i - 1]
        if m.njoints - 1 != self.n_joints or np.any(m.damping != 0.0):
            return None
        return rows

    @property
    def gravity_m_s2(self) -> np.ndarray:
        """The model's gravity (m/s^2, base frame)."""
        return np.array(self._model.gravity.linear)

    def set_payload(self, payload_kg: float = 0.0, payload_com: Any = None) -> None:
        """Make a payload current for the unchecked servo-loop calls."""
        self._apply_payload(payload_kg, payload_com)

    def mass_matrix_diagonal_unchecked(self, q: np.ndarray) -> np.ndarray:
        """Diagonal of the mass matrix with the current payload, no input checks (servo gain scheduling)."""
        return self._pin.crba(self._model, self._data, q).diagonal().copy()

    def mass_matrix(self, q: Any, payload_kg: float = 0.0, payload_com: Any = None) -> np.ndarray:
        """Joint-space inertia matrix (symmetric, armature included)."""
        q = self.vector(q)
        self._apply_payload(payload_kg, payload_com)
        m = self._pin.crba(self._model, self._data, q)
        # crba fills only the upper triangle.
        return np.triu(m) + np.triu(m, 1).T

    def gravity(self, q: Any, payload_kg: float = 0.0, payload_com: Any = None) -> np.ndarray:
        """Joint torques that hold q against gravity (N m)."""
        q = self.vector(q)
        self._apply_payload(payload_kg, payload_com)
        return self._pin.computeGeneralizedGravity(self._model, self._data, q).copy()


def load_robot(name: str = "irb2400") -> ArmModel:
    """The controller's model of a registered robot (Pinocchio, built from its MJCF)."""
    return ArmModel(ROBOTS.get(name))
