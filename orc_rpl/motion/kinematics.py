"""The motion layer's view of the arm: the arm services it uses (FK, Jacobian, IK, dynamics) behind one Protocol."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np
from scipy.linalg.lapack import dgesv

from orc_rpl.errors import JointLimit, OrcError, Unreachable
from orc_rpl.plant import compiled


class ArmLike(Protocol):
    """What the motion layer needs from `orc_rpl.arm` (an `ArmModel` satisfies it)."""

    q_min: np.ndarray
    q_max: np.ndarray
    qd_max: np.ndarray
    qdd_max: np.ndarray
    tau_max: np.ndarray

    def fk(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray: ...

    def jacobian(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray: ...

    def pose_and_jacobian(self, q: np.ndarray, tool: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]: ...

    def fk_unchecked(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray: ...

    def linear_jacobian_unchecked(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray: ...

    def transform(self, value: object, what: str = "tool") -> np.ndarray: ...

    def inverse_dynamics(
        self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, payload_kg: float = 0.0
    ) -> np.ndarray: ...


IkSolver = Callable[[ArmLike, np.ndarray, np.ndarray, np.ndarray | None], np.ndarray]


class Kinematics:
    """Arm services as the planners use them; errors from the arm come out as the project's errors."""

    def __init__(self, arm: ArmLike, ik: IkSolver, joint_step_limit_rad: float = 0.35) -> None:
        self.arm = arm
        self._ik = ik
        self.n = len(arm.q_min)
        #: largest joint change between neighbouring IK samples before we call it a configuration flip
        self.joint_step_limit_rad = joint_step_limit_rad
        self._chain: tuple | None = None  #: (kernels, the chain's kinematic rows, flange in the last joint), or ()
        #: IK along paths tracked by the compiled Newton steps (ik_kernels.py) where numba is there; False: the
        #: Python steps, their reference. A switch of its own, not compiled.use_kernels': the per-cycle kernels
        #: give their numpy code's bits (tests compare whole runs), these the reference's to about 1e-15 rad
        self.compiled_tracking = True

    def _compiled_chain(self) -> tuple:
        """(ik_kernels, the chain's rows, the flange in its last joint) for the compiled tracking (six revolute axes
        in a chain, numba there), else (): looked up once (the kinematic columns do not change with the payload)."""
        if self._chain is None:
            rows_of = getattr(self.arm, "rigid_body_rows", None)
            flange_of = getattr(self.arm, "flange_in_last_joint", None)
            rows = None if rows_of is None or self.n != 6 else rows_of()
            flange = None if rows is None or flange_of is None else flange_of()
            kernels = None if flange is None else compiled.kernels("orc_rpl.motion.ik_kernels")
            self._chain = () if kernels is None else (kernels, np.ascontiguousarray(rows[:, :15]), flange)
        return self._chain

    def fk(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
        """TCP pose (4x4) at q."""
        return self.arm.fk(np.asarray(q, dtype=float), tool)

    def tcp_positions(self, qs: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
        """TCP positions (N, 3) of joint samples (N, n)."""
        qs = np.asarray(qs, dtype=float)
        if qs.ndim != 2 or len(qs) == 0 or not np.isfinite(qs).all():
            return np.array([self.arm.fk(q, tool)[:3, 3] for q in qs])  # the checked calls say what is wrong
        # One checked call for the joint count and the tool; the other samples go unchecked (they are
        # every path's samples: the checks cost more than the kinematics).
        first = self.arm.fk(qs[0], tool)[:3, 3]
        fk, tool = self.arm.fk_unchecked, None if tool is None else self.arm.transform(tool)
        return np.array([first] + [fk(q, tool)[:3, 3] for q in qs[1:]])

    def check_limits(self, q: np.ndarray, what: str) -> None:
        """Raise JointLimit naming the joint if q leaves the joint ranges."""
        q = np.asarray(q, dtype=float)
        if not np.all(np.isfinite(q)):
            raise JointLimit(f"{what}: joint values are not finite numbers: {q.tolist()}")
        low = q < self.arm.q_min - 1e-9
        high = q > self.arm.q_max + 1e-9
        if low.any() or high.any():
            j = int(np.argmax(low | high))
            bound = self.arm.q_min[j] if low[j] else self.arm.q_max[j]
            raise JointLimit(
                f"{what}: joint {j + 1} at {np.degrees(q[j]):.2f} deg is beyond its limit "
                f"{np.degrees(bound):.2f} deg"
            )

    def ik(self, target: np.ndarray, q_seed: np.ndarray, tool: np.ndarray | None = None, what: str = "target") -> np.ndarray:
        """A joint solution near q_seed for the 4x4 TCP pose `target`."""
        try:
            q = np.asarray(self._ik(self.arm, target, np.asarray(q_seed, dtype=float), tool), dtype=float)
        except (Unreachable, JointLimit):
            raise
        except OrcError:
            raise
        except Exception as exc:  # the IK library's own failure: translate it here, at the one call site
            raise Unreachable(f"{what}: inverse kinematics failed ({exc})") from exc
        self.check_limits(q, what)
        return q

    def _track(self, target: np.ndarray, q: np.ndarray, tool: np.ndarray | None) -> np.ndarray | None:
        """Newton steps from a nearby solution (the previous path sample): a few times faster than a full IK."""
        # q and tool come checked from ik_along: one unchecked kinematics pass gives pose and Jacobian.
        # The error is formed in Python floats (the same IEEE operations as numpy's, without a
        # numpy call per element): this loop runs for every sample of every Cartesian path.
        if self.n < 6:
            return None  # a square Newton step needs six axes; fewer go through the full (least-squares) IK
        pose_and_jacobian = self.arm.pose_and_jacobian
        target_r = target[:3, :3]
        x, y, z = target[:3, 3].tolist()
        for _ in range(8):
            t, jac = pose_and_jacobian(q, tool)
            # rotation still to go; its vee part is the angle error for small angles
            (_, e01, e02), (e10, _, e12), (e20, e21, _) = (target_r @ t[:3, :3].T).tolist()
            px, py, pz = t[:3, 3].tolist()
            err = (x - px, y - py, z - pz, 0.5 * (e21 - e12), 0.5 * (e02 - e20), 0.5 * (e10 - e01))
            if max(map(abs, err)) < 1e-10:
                return q
            # LAPACK dgesv (what np.linalg.solve runs) called directly: numpy's wrapper is two thirds of the call
            step, info = dgesv(jac, err)[2:]
            if info != 0:  # singular: np.linalg.solve would raise LinAlgError
                return None
            q = q + step
        return None

    def ik_along(self, poses: np.ndarray, q_start: np.ndarray, tool: np.ndarray | None, what: str) -> np.ndarray:
        """Joint samples (N, n) for TCP poses (N, 4, 4), each IK seeded from the previous; flips are errors."""
        qs = np.empty((len(poses), self.n))
        qs[0] = q_start
        prev = np.asarray(q_start, dtype=float)
        self.arm.fk(prev, tool)  # checks q_start and the tool once: _track's inner loop does not
        q_min, q_max, limit, n = self.arm.q_min, self.arm.q_max, self.joint_step_limit_rad, self.n
        chain = self._compiled_chain() if self.compiled_tracking else ()
        if chain:
            kernels, rows, flange = chain
            tip = flange if tool is None else flange @ self.arm.transform(tool)
            poses = np.ascontiguousarray(poses, dtype=float)
        i = 1
        while i < len(poses):
            if chain:  # the samples the Newton steps settle, compiled; the first they do not is the full IK's below
                i = kernels.track_along(rows, tip, poses, qs, i, q_min, q_max, limit)
                if i == len(poses):
                    break
                prev = qs[i - 1]
                q = None
            else:
                q = self._track(poses[i], prev, tool)
            # (count_nonzero of the in-range test: a NaN counts as out of range, as with np.all)
            if (q is None or float(np.abs(q - prev).max()) > limit
                    or np.count_nonzero((q >= q_min) & (q <= q_max)) != n):
                try:
                    q = self.ik(poses[i], prev, tool, what=f"{what} at {100.0 * i / (len(poses) - 1):.0f} % of the path")
                except Unreachable as exc:
                    raise Unreachable(f"{exc}; the path leaves the workspace") from None
            jump = float(np.abs(q - prev).max())
            if jump > limit:
                j = int(np.argmax(np.abs(q - prev)))
                raise Unreachable(
                    f"{what}: configuration flip at {100.0 * i / (len(poses) - 1):.0f} % of the path "
                    f"(joint {j + 1} jumps {np.degrees(jump):.1f} deg between neighbouring points); "
                    "the straight path passes a singularity; use a joint motion or a via point"
                )
            qs[i] = q
            prev = q
            i += 1
        return qs

    def jacobian_linear(self, q: np.ndarray, tool: np.ndarray | None = None) -> np.ndarray:
        """The (3, n) linear part of the world-aligned Jacobian at q."""
        return self.arm.jacobian(q, tool)[:3]

    def inverse_dynamics(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, payload_kg: float = 0.0) -> np.ndarray:
        """Joint torques for a motion state, payload included."""
        return self.arm.inverse_dynamics(q, qd, qdd, payload_kg)
