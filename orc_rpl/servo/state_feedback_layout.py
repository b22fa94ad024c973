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
    at = 0
    vectors = []
    for size in (n, n, n, m, m, m, m, m, m, m, 5 * m):
        vectors.append(buffer[at : at + size])
        at += size
    matrices = []
    for rows, cols in ((m, m), (m, 4 * m), (5 * m, 2 * m), (5 * m, 5 * m), (5 * m, 2 * m), (4 * m, 4 * m),
                       (5 * m, 5 * m), (2 * m, 2 * m), (4 * m, 4 * m), (5 * m, 5 * m), (m, m), (m, 4 * m),
                       (5 * m, 2 * m)):
        matrices.append(buffer[at : at + rows * cols].reshape((rows, cols)))
        at += rows * cols
    return (vectors[0], vectors[1], vectors[2], vectors[3], vectors[4], vectors[5], vectors[6], vectors[7], vectors[8],
            vectors[9], vectors[10], matrices[0], matrices[1], matrices[2], matrices[3], matrices[4], matrices[5],
            matrices[6], matrices[7], matrices[8], matrices[9], matrices[10], matrices[11], matrices[12])
