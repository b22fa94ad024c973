"""The servo room's state feedback compiled: a motion cycle's model and gains, and the 1 ms step's law, in numba.

The numpy code in servo/state_feedback.py is the reference: the kernels build the same sampled
model, the same weights and noises, run the same Riccati iterations, and the step's references,
torques and filter the same expressions (the sums of the matrix products in their own order:
tests/servo/test_state_feedback_kernels.py compares the two on a recorded run, to 1e-10). Profiled on
bench_motion's program (elastic, state feedback): the schedule was about half of the servo's time, a
hundred small numpy calls a motion cycle on matrices of 15 x 15 at most; the step's three calls
(`references`, `update`, `applied`) about a fifth, some forty numpy calls a step.
"""

from __future__ import annotations

import numpy as np

from orc_rpl.plant.compiled import inlined_kernel, kernel
from orc_rpl.servo.rnea_kernel import mass_matrix_block
from orc_rpl.servo.state_feedback_layout import KEPT, SCHEDULED, SETTLING, law_views

#: Entries of the `tuning` array (`TwoMassStateFeedback._tuning`): the kernel reads the design's constants by these
#: (the schedule's tolerances as the module's constants were when the law was made).
(BANDWIDTH, MOTOR_WEIGHT, ROTOR_NOISE, LINK_NOISE, WALK, REST_WALK, ANGLE_NOISE, SPEED_NOISE, PERIOD, EXPM_TERMS,
 FRICTION_GAIN, FRICTION_SMOOTH, INERTIA_TOLERANCE, GAINS_SETTLED, MOVING, REST_TO_LINK, ITERATIONS) = range(17)
TUNING_SIZE = 17

#: `law_views` compiled: a kernel finds the law's arrays in its buffer.
compiled_law_views = inlined_kernel(law_views)


@kernel
def sampled_model(link_inertia: np.ndarray, rotor: np.ndarray, stiffness: np.ndarray, damping: np.ndarray,
                  moving: np.ndarray, tuning: np.ndarray, ad: np.ndarray, bd: np.ndarray, weights: np.ndarray,
                  process: np.ndarray, measurement: np.ndarray) -> None:  # pragma: no cover - compiled
    """`_model`: `slow_joints_model` into ad (5m x 5m) and bd (5m x 2m), `lqr_weights` and `noise_covariances`.

    The exponential's series as the numpy code sums it, on the rows that are not zero: [A B; 0 0] has its
    last 3m rows zero (w and the inputs are constant over a step), and so has each power of it, whose
    rows 4m..5m are zero too; the others have at most 6m entries (a joint's own, or the links' coupled
    ones), which the products take one by one (some 40 times fewer sums than the dense 7m x 7m products)."""
    m = rotor.shape[0]
    period = tuning[PERIOD]
    inv_link, low = np.empty((m, m)), np.empty((m, m))
    _solve_spd(link_inertia, np.eye(m), low, inv_link)   # the links' inertia is symmetric positive definite
    width = 7 * m
    a = np.zeros((4 * m, width))   # the rows of [A B] * period that are not zero
    for i in range(m):
        inv_rotor = 1.0 / rotor[i]
        a[i, m + i] = period
        a[2 * m + i, 3 * m + i] = period
        a[m + i, i] = -(inv_rotor * stiffness[i]) * period
        a[m + i, m + i] = -(inv_rotor * damping[i]) * period
        a[m + i, 2 * m + i] = (inv_rotor * stiffness[i]) * period
        a[m + i, 3 * m + i] = (inv_rotor * damping[i]) * period
        a[m + i, 4 * m + i] = (inv_rotor * (0.0 if moving[i] else 1.0)) * period
        a[m + i, 5 * m + i] = inv_rotor * period
        for j in range(m):
            a[3 * m + i, j] = (inv_link[i, j] * stiffness[j]) * period
            a[3 * m + i, m + j] = (inv_link[i, j] * damping[j]) * period
            a[3 * m + i, 2 * m + j] = -(inv_link[i, j] * stiffness[j]) * period
            a[3 * m + i, 3 * m + j] = -(inv_link[i, j] * damping[j]) * period
            a[3 * m + i, 4 * m + j] = (inv_link[i, j] * (1.0 if moving[j] else 0.0)) * period
            a[3 * m + i, 6 * m + j] = -inv_link[i, j] * period
    columns, count = np.empty((4 * m, width), dtype=np.int64), np.zeros(4 * m, dtype=np.int64)
    for r in range(4 * m):
        for c in range(width):
            if a[r, c] != 0.0:
                columns[r, count[r]] = c
                count[r] += 1
    e, term, product = np.zeros((4 * m, width)), a.copy(), np.empty((4 * m, width))
    for r in range(4 * m):
        for c in range(width):
            e[r, c] = a[r, c]
    for i in range(2, int(tuning[EXPM_TERMS]) + 1):   # term = term @ a / i, rows 0..4m (the others stay zero)
        product[:, :] = 0.0
        for r in range(4 * m):
            for k in range(4 * m):
                factor = term[r, k]
                if factor != 0.0:
                    for z in range(count[k]):
                        c = columns[k, z]
                        product[r, c] += factor * a[k, c]
        for r in range(4 * m):
            for c in range(width):
                term[r, c] = product[r, c] / i
                e[r, c] += term[r, c]
    ad[:, :] = 0.0
    bd[:, :] = 0.0
    for r in range(5 * m):
        ad[r, r] = 1.0
    for r in range(4 * m):
        for c in range(5 * m):
            ad[r, c] += e[r, c]
        for c in range(2 * m):
            bd[r, c] = e[r, 5 * m + c]
    # lqr_weights and noise_covariances
    w = tuning[BANDWIDTH]
    weights[:, :] = 0.0
    process[:, :] = 0.0
    measurement[:, :] = 0.0
    for j in range(m):
        whole = rotor[j] + link_inertia[j, j]
        angle, speed = (whole * w * w) ** 2, 0.5 * (whole * w) ** 2
        weights[j, j], weights[m + j, m + j] = tuning[MOTOR_WEIGHT] * angle, tuning[MOTOR_WEIGHT] * speed
        weights[2 * m + j, 2 * m + j], weights[3 * m + j, 3 * m + j] = angle, speed
        process[m + j, m + j] = (tuning[ROTOR_NOISE] / rotor[j]) ** 2 * period
        process[3 * m + j, 3 * m + j] = (tuning[LINK_NOISE] / link_inertia[j, j]) ** 2 * period
        process[4 * m + j, 4 * m + j] = (tuning[WALK] if moving[j] else tuning[REST_WALK]) ** 2 * period
        measurement[j, j] = tuning[ANGLE_NOISE] ** 2
        measurement[m + j, m + j] = tuning[SPEED_NOISE] ** 2


@kernel
def _product(a: np.ndarray, b: np.ndarray, out: np.ndarray, transpose_a: bool) -> None:  # pragma: no cover - compiled
    """out = a @ b (or a.T @ b): rows of out as sums of rows of b (the inner loop runs along rows: it vectorises),
    two rows of out at a time: each row of b loaded once for both, every entry summed in the same order as one
    row at a time (the same bits; `riccati_gains` about 15.7 -> 12.9 us on the IRB 2400's three slow joints)."""
    rows, inner, cols = out.shape[0], b.shape[0], out.shape[1]
    out[:, :] = 0.0
    i = 0
    while i + 1 < rows:
        for k in range(inner):
            f0 = a[k, i] if transpose_a else a[i, k]
            f1 = a[k, i + 1] if transpose_a else a[i + 1, k]
            for j in range(cols):
                v = b[k, j]
                out[i, j] += f0 * v
                out[i + 1, j] += f1 * v
        i += 2
    if i < rows:
        for k in range(inner):
            factor = a[k, i] if transpose_a else a[i, k]
            for j in range(cols):
                out[i, j] += factor * b[k, j]


@kernel
def _solve_spd(a: np.ndarray, b: np.ndarray, low: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover - compiled
    """out = a^-1 b for a symmetric positive definite a (Cholesky, low: its factor's work array)."""
    n = a.shape[0]
    for i in range(n):
        for j in range(i + 1):
            total = a[i, j]
            for k in range(j):
                total -= low[i, k] * low[j, k]
            low[i, j] = np.sqrt(total) if i == j else total / low[j, j]
    # forward, then back substitution, a row of every right-hand side at a time (sums along rows: no chain of
    # dependent sums, one division a row)
    cols = b.shape[1]
    for i in range(n):
        for c in range(cols):
            out[i, c] = b[i, c]
        for k in range(i):
            factor = low[i, k]
            for c in range(cols):
                out[i, c] -= factor * out[k, c]
        inverse = 1.0 / low[i, i]
        for c in range(cols):
            out[i, c] *= inverse
    for i in range(n - 1, -1, -1):
        for k in range(i + 1, n):
            factor = low[k, i]
            for c in range(cols):
                out[i, c] -= factor * out[k, c]
        inverse = 1.0 / low[i, i]
        for c in range(cols):
            out[i, c] *= inverse


@inlined_kernel
def _measured_gain(s: np.ndarray, measurement: np.ndarray, innovation: np.ndarray, low: np.ndarray,
                   x: np.ndarray) -> None:  # pragma: no cover - compiled
    """x = (c s c' + measurement)^-1 c s, c = [I 0] measuring the first rows of the state (the rotors' angles and
    speeds): c s c' and c s are blocks of s; innovation and low are work arrays of measurement's shape."""
    measured = measurement.shape[0]
    for i in range(measured):
        for j in range(measured):
            innovation[i, j] = s[i, j] + measurement[i, j]
    _solve_spd(innovation, s[:measured, :], low, x)


@kernel
def riccati_gains(ad: np.ndarray, bd: np.ndarray, weights: np.ndarray, process: np.ndarray, measurement: np.ndarray,
                  iterations: int, p: np.ndarray, s: np.ndarray, k: np.ndarray,
                  l: np.ndarray) -> None:  # pragma: no cover - compiled
    """`_iterate_numpy`: `iterations` Riccati iterations from p (the LQR's, 4m x 4m) and s (the filter's, 5m x 5m),
    both updated in place, and the gains k (m x 4m) and l (5m x 2m). The filter measures the rotors' angles and
    speeds (c = [I 0]): c s c^T, s c^T and c s are blocks of s, taken as such; the products in loops on work arrays
    and the solves by Cholesky (both matrices are symmetric positive definite): BLAS and LAPACK calls on matrices
    this small cost more in their set-up than in their sums."""
    m = k.shape[0]
    a4, b4 = np.ascontiguousarray(ad[: 4 * m, : 4 * m]), np.ascontiguousarray(bd[: 4 * m, :m])
    bp, small, rhs, low_m = np.empty((m, 4 * m)), np.empty((m, m)), np.empty((m, 4 * m)), np.empty((m, m))
    closed, work4, p_new = np.empty((4 * m, 4 * m)), np.empty((4 * m, 4 * m)), np.empty((4 * m, 4 * m))
    innovation, low_2m, x = np.empty((2 * m, 2 * m)), np.empty((2 * m, 2 * m)), np.empty((2 * m, 5 * m))
    post, work5, ad_t = np.empty((5 * m, 5 * m)), np.empty((5 * m, 5 * m)), np.ascontiguousarray(ad.T)
    gain, s_measured = np.empty((m, 4 * m)), np.empty((5 * m, 2 * m))
    for it in range(iterations + 1):   # the last pass makes the gains only
        # the LQR: gain = (r + b' p b)^-1 b' p a, p = weights + a' p (a - b gain)
        _product(b4, p, bp, True)
        _product(bp, b4, small, False)
        for i in range(m):
            small[i, i] += 1.0
        _product(bp, a4, rhs, False)
        if it == iterations:
            _solve_spd(small, rhs, low_m, k)
            break
        _solve_spd(small, rhs, low_m, gain)
        _product(b4, gain, closed, False)
        for i in range(4 * m):
            for j in range(4 * m):
                closed[i, j] = a4[i, j] - closed[i, j]
        _product(p, closed, work4, False)
        _product(a4, work4, p_new, True)
        for i in range(4 * m):
            for j in range(4 * m):
                p[i, j] = weights[i, j] + p_new[i, j]
        # the filter: s = ad (s - s c' (c s c' + measurement)^-1 c s) ad' + process
        _measured_gain(s, measurement, innovation, low_2m, x)
        s_measured[:, :] = s[:, : 2 * m]
        _product(s_measured, x, post, False)
        for i in range(5 * m):
            for j in range(5 * m):
                post[i, j] = s[i, j] - post[i, j]
        _product(ad, post, work5, False)
        _product(work5, ad_t, post, False)   # (ad post) ad' as rows of ad' summed: no chain of dependent sums
        for i in range(5 * m):
            for j in range(5 * m):
                s[i, j] = post[i, j] + process[i, j]
    # l = s c' (c s c' + measurement)^-1: the transpose of (c s c' + measurement)^-1 c s (both symmetric)
    _measured_gain(s, measurement, innovation, low_2m, x)
    for i in range(5 * m):
        for j in range(2 * m):
            l[i, j] = x[j, i]


@kernel
def link_inertia_at(body: np.ndarray, q: np.ndarray, joints: np.ndarray, rotor: np.ndarray, scheduled: np.ndarray,
                    inertia: np.ndarray, qd_ref: np.ndarray, moving_rad_s: float, moving: np.ndarray,
                    moving_now: np.ndarray) -> tuple[float, bool]:  # pragma: no cover - compiled
    """`_link_inertia_at`: the slow joints' block of M(q) less the rotors into inertia, and its largest change from
    `scheduled` over sqrt(M_ii M_jj) of the latter; the slow joints moving faster than moving_rad_s at the reference
    speeds into moving_now, and whether that differs from `moving`."""
    mass_matrix_block(body, q, joints, inertia)
    m, moved, changed = joints.shape[0], 0.0, False
    for i in range(m):
        inertia[i, i] = inertia[i, i] - rotor[i]
        moving_now[i] = abs(qd_ref[joints[i]]) > moving_rad_s
        changed = changed or moving_now[i] != moving[i]
    for i in range(m):
        for j in range(m):
            moved = max(moved, abs(inertia[i, j] - scheduled[i, j]) / np.sqrt(scheduled[i, i] * scheduled[j, j]))
    return moved, changed


@inlined_kernel
def _switch(state: np.ndarray, moving: np.ndarray, moving_now: np.ndarray, held_link: np.ndarray,
            held_rotor: np.ndarray, rest_to_link: float) -> None:  # pragma: no cover - compiled
    """`switch`: the joints that start moving take rest_to_link of their w to the link, those that stop hold it."""
    m = moving.shape[0]
    for i in range(m):
        if moving_now[i] == moving[i]:
            continue
        w = state[4 * m + i]
        if moving_now[i]:
            held_rotor[i], state[4 * m + i] = (1.0 - rest_to_link) * w, held_link[i] + rest_to_link * w
        else:
            held_link[i], state[4 * m + i] = w, held_rotor[i]
        moving[i] = moving_now[i]


@inlined_kernel
def _largest_change(now: np.ndarray, before: np.ndarray) -> float:  # pragma: no cover - compiled
    """max |now - before| / max |now|."""
    change, scale = 0.0, 0.0
    for i in range(now.shape[0]):
        for j in range(now.shape[1]):
            change = max(change, abs(now[i, j] - before[i, j]))
            scale = max(scale, abs(now[i, j]))
    return change / scale


@kernel
def law_schedule(body: np.ndarray, q: np.ndarray, qd_ref: np.ndarray, joints: np.ndarray, buffer: np.ndarray,
                 moving: np.ndarray, flags: np.ndarray, tuning: np.ndarray) -> None:  # pragma: no cover - compiled
    """`TwoMassStateFeedback.schedule(q, qd_ref)` of a law whose Riccati equations are solved: the law's arrays in
    `buffer` (servo/state_feedback_layout.py), `moving` and the `flags` in place."""
    schedule_on_views(body, q, qd_ref, joints, compiled_law_views(buffer, q.shape[0], joints.shape[0]), moving, flags,
                      tuning)


@inlined_kernel
def schedule_on_views(body: np.ndarray, q: np.ndarray, qd_ref: np.ndarray, joints: np.ndarray, views: tuple,
                      moving: np.ndarray, flags: np.ndarray, tuning: np.ndarray) -> None:  # pragma: no cover - compiled
    """`law_schedule` on the law's arrays as `compiled_law_views` gives them (a motion cycle's kernel makes them once
    for its schedule and its steps)."""
    m = joints.shape[0]
    (_, _, _, held_link, held_rotor, _, rotor, stiffness, damping, _, state, link_inertia, k, l, ad, bd, weights,
     process, measurement, p, s, inertia_now, k_before, l_before) = views
    moving_now = np.empty(m, dtype=np.bool_)
    moved, changed = link_inertia_at(body, q, joints, rotor, link_inertia, inertia_now, qd_ref, tuning[MOVING], moving,
                                     moving_now)
    if changed:
        _switch(state, moving, moving_now, held_link, held_rotor, tuning[REST_TO_LINK])
    remodel = changed or moved > tuning[INERTIA_TOLERANCE]
    if not (remodel or flags[SETTLING]):
        flags[KEPT] += 1
        return
    k_before[:, :] = k
    l_before[:, :] = l
    if remodel:   # else the iterations go on for the model they were started on
        link_inertia[:, :] = inertia_now
        sampled_model(link_inertia, rotor, stiffness, damping, moving, tuning, ad, bd, weights, process, measurement)
    riccati_gains(ad, bd, weights, process, measurement, int(tuning[ITERATIONS]), p, s, k, l)
    flags[SCHEDULED] += 1
    flags[SETTLING] = max(_largest_change(k, k_before), _largest_change(l, l_before)) > tuning[GAINS_SETTLED]


@inlined_kernel
def law_references(q_ref: np.ndarray, qd_ref: np.ndarray, qdd_ref: np.ndarray, tau_ff: np.ndarray, joints: np.ndarray,
                   rotor_all: np.ndarray, stiffness_all: np.ndarray, state: np.ndarray, moving: np.ndarray,
                   held_link: np.ndarray, link_inertia: np.ndarray, tuning: np.ndarray, twist_rad: np.ndarray,
                   link_other: np.ndarray, theta_ref: np.ndarray, theta_d_ref: np.ndarray,
                   work: np.ndarray) -> None:  # pragma: no cover - compiled
    """`references`: the rotors' reference row into theta_ref and theta_d_ref, the twist into twist_rad (in place,
    its last row's read first), the slow joints' other link torques into link_other. work: scratch, at least
    max(n, 7m) floats (these three kernels' only memory: they run every 1 ms step)."""
    n, m = q_ref.shape[0], joints.shape[0]
    link_torque = work[:n]
    for j in range(n):
        link_torque[j] = tau_ff[j] - rotor_all[j] * qdd_ref[j]
    for i in range(m):
        w_link = state[4 * m + i] if moving[i] else held_link[i]
        link_torque[joints[i]] = link_torque[joints[i]] - w_link
    for j in range(n):
        twist = link_torque[j] / stiffness_all[j]
        rate = (twist - twist_rad[j]) / tuning[PERIOD]
        twist_rad[j] = twist
        theta_ref[j], theta_d_ref[j] = q_ref[j] + twist, qd_ref[j] + rate
    for i in range(m):
        inertia = 0.0
        for c in range(m):
            inertia += link_inertia[i, c] * qdd_ref[joints[c]]
        w_link = state[4 * m + i] if moving[i] else 0.0
        link_other[i] = (link_torque[joints[i]] + w_link) - inertia


@inlined_kernel
def law_update(q_ref: np.ndarray, qd_ref: np.ndarray, theta_ref: np.ndarray, theta_d_ref: np.ndarray,
               tau_ff: np.ndarray, theta: np.ndarray, theta_d: np.ndarray, joints: np.ndarray, state: np.ndarray,
               l: np.ndarray, k: np.ndarray, moving: np.ndarray, held_link: np.ndarray, held_rotor: np.ndarray,
               friction: bool, coulomb: np.ndarray, viscous: np.ndarray, tuning: np.ndarray, demand: np.ndarray,
               ff: np.ndarray, work: np.ndarray) -> None:  # pragma: no cover - compiled
    """`update`: the filter's correction of `state` (in place), the demanded torques and their feed-forward
    (the slow joints') into demand and ff; work: scratch (`law_references`)."""
    m = joints.shape[0]
    innovation = work[: 2 * m]
    for i in range(m):
        innovation[i] = theta[joints[i]] - state[i]
        innovation[m + i] = theta_d[joints[i]] - state[m + i]
    for r in range(5 * m):
        correction = 0.0
        for c in range(2 * m):
            correction += l[r, c] * innovation[c]
        state[r] = state[r] + correction
    error = work[2 * m : 6 * m]
    for i in range(m):
        j = joints[i]
        error[i] = state[i] - theta_ref[j]
        error[m + i] = state[m + i] - theta_d_ref[j]
        error[2 * m + i] = state[2 * m + i] - q_ref[j]
        error[3 * m + i] = state[3 * m + i] - qd_ref[j]
    for i in range(m):
        j, w = joints[i], state[4 * m + i]
        total = (tau_ff[j] - (w if moving[i] else held_link[i])) - (held_rotor[i] if moving[i] else w)
        if friction:
            demand_speed = theta_d_ref[j] + tuning[FRICTION_GAIN] * (theta_ref[j] - theta[j])
            total = (total + coulomb[j] * np.tanh(demand_speed / tuning[FRICTION_SMOOTH])) + viscous[j] * theta_d_ref[j]
        feedback = 0.0
        for c in range(4 * m):
            feedback += k[i, c] * error[c]
        ff[i] = total
        demand[i] = total - feedback


@inlined_kernel
def law_predict(tau: np.ndarray, theta_d: np.ndarray, joints: np.ndarray, state: np.ndarray, ad: np.ndarray,
                bd: np.ndarray, moving: np.ndarray, held_rotor: np.ndarray, link_other: np.ndarray, friction: bool,
                coulomb: np.ndarray, viscous: np.ndarray, tuning: np.ndarray,
                work: np.ndarray) -> None:  # pragma: no cover - compiled
    """`applied`: the filter's prediction over the step, `state` in place; work: scratch (`law_references`)."""
    m = joints.shape[0]
    inputs = work[: 2 * m]
    for i in range(m):
        j = joints[i]
        u = tau[j] + (held_rotor[i] if moving[i] else 0.0)
        if friction:
            u = u - (coulomb[j] * np.tanh(theta_d[j] / tuning[FRICTION_SMOOTH]) + viscous[j] * theta_d[j])
        inputs[i], inputs[m + i] = u, link_other[i]
    before = work[2 * m : 7 * m]
    before[:] = state
    for r in range(5 * m):
        total = 0.0
        for c in range(5 * m):
            total += ad[r, c] * before[c]
        for c in range(2 * m):
            total += bd[r, c] * inputs[c]
        state[r] = total
