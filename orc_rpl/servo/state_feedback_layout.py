"""The servo room's state feedback in memory: every float array the law keeps as a view of one buffer.

A compiled motion cycle (servo/state_feedback_cycle_kernels.py) then takes the whole law as one
argument (a call's arguments cost some 60 ns each to pass from Python) and finds its arrays with
this same function, compiled; `TwoMassStateFeedback` keeps the views as its attributes and writes
them in place, never rebinding them. `law_views` is plain numpy: the kernels compile it as it is.
"""

from __future__ import annotations

import numpy as np

#: Entries of a law's `flags` (int64): whether its Riccati equations have been solved (the schedule iterates from
#: their solutions), whether the last iterations still moved the gains, and its counts of made and kept gains.
SOLVED, SETTLING, SCHEDULED, KEPT = range(4)
FLAGS_SIZE = 4


def law_size(n: int, m: int) -> int:
    """Floats in the buffer of a law of m slow joints in an arm of n joints (what `law_views` takes of a larger one)."""
    return sum(view.size for view in law_views(np.empty(3 * n + 12 * m + 160 * m * m), n, m))


def law_views(buffer: np.ndarray, n: int, m: int) -> tuple[np.ndarray, ...]:
    """The law's arrays in `buffer` (`law_size(n, m)` floats): twist_rad, rotor_all, stiffness_all (n each);
    held_link, held_rotor, link_other, rotor, stiffness, damping, tau_max (m each); the filter's state (5m); the
    links' inertia (m x m), the gains k (m x 4m) and l (5m x 2m), the sampled model ad (5m x 5m) and bd (5m x 2m),
    the LQR's weights (4m x 4m), the filter's process (5m x 5m) and measurement (2m x 2m) noises, the Riccati
    solutions p (4m x 4m) and s (5m x 5m); the schedule's work: the inertia now (m x m), the gains before
    (m x 4m, 5m x 2m)."""
    # straight-line slices (compiled, lists of arrays would be built on the heap at every call: a microsecond)
    mm, m4, m5 = m * m, 4 * m, 5 * m
    twist_rad, rotor_all, stiffness_all = buffer[0:n], buffer[n : 2 * n], buffer[2 * n : 3 * n]
    at = 3 * n
    held_link, held_rotor, link_other = buffer[at : at + m], buffer[at + m : at + 2 * m], buffer[at + 2 * m : at + 3 * m]
    rotor, stiffness, damping = buffer[at + 3 * m : at + 4 * m], buffer[at + 4 * m : at + 5 * m], buffer[at + 5 * m : at + 6 * m]
    tau_max, state = buffer[at + 6 * m : at + 7 * m], buffer[at + 7 * m : at + 12 * m]
    at += 12 * m
    link_inertia = buffer[at : at + mm].reshape((m, m))
    at += mm
    k = buffer[at : at + m * m4].reshape((m, m4))
    at += m * m4
    l = buffer[at : at + m5 * 2 * m].reshape((m5, 2 * m))
    at += m5 * 2 * m
    ad = buffer[at : at + m5 * m5].reshape((m5, m5))
    at += m5 * m5
    bd = buffer[at : at + m5 * 2 * m].reshape((m5, 2 * m))
    at += m5 * 2 * m
    weights = buffer[at : at + m4 * m4].reshape((m4, m4))
    at += m4 * m4
    process = buffer[at : at + m5 * m5].reshape((m5, m5))
    at += m5 * m5
    measurement = buffer[at : at + 4 * mm].reshape((2 * m, 2 * m))
    at += 4 * mm
    p = buffer[at : at + m4 * m4].reshape((m4, m4))
    at += m4 * m4
    s = buffer[at : at + m5 * m5].reshape((m5, m5))
    at += m5 * m5
    inertia_now = buffer[at : at + mm].reshape((m, m))
    at += mm
    k_before = buffer[at : at + m * m4].reshape((m, m4))
    at += m * m4
    l_before = buffer[at : at + m5 * 2 * m].reshape((m5, 2 * m))
    return (twist_rad, rotor_all, stiffness_all, held_link, held_rotor, link_other, rotor, stiffness, damping, tau_max,
            state, link_inertia, k, l, ad, bd, weights, process, measurement, p, s, inertia_now, k_before, l_before)
