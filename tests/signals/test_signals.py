"""Tests of the logger and recordings: sampling, growth, NPZ/CSV round trips and plots."""

from __future__ import annotations

import numpy as np
import pytest

from orc_rpl.errors import UsageError
from orc_rpl.signals import Logger, Recording


class _Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def _recorded(samples: int = 100) -> Recording:
    clock = _Clock()
    state = {"q": np.zeros(3), "speed": 0.0}
    logger = Logger(clock, capacity=16)  # small: forces the arrays to grow
    logger.submit("q", lambda: state["q"])
    logger.submit("speed_m_s", lambda: state["speed"])
    logger.submit("tcp", lambda: np.array([1.0 + state["speed"], state["q"][0], 0.5]))
    for k in range(samples):
        clock.t = 0.001 * k
        state["q"] = np.array([k, -k, 0.5 * k]) / 7.0
        state["speed"] = np.sin(0.1 * k)
        logger.update()
    return logger.recording()


def test_logger_samples_every_signal_with_the_clocks_time() -> None:
    rec = _recorded(100)
    assert len(rec) == 100
    assert rec.names == ["q", "speed_m_s", "tcp"]
    np.testing.assert_array_equal(rec.time_s, 0.001 * np.arange(100))
    np.testing.assert_array_equal(rec["q"][10], np.array([10, -10, 5]) / 7.0)
    assert rec["speed_m_s"].shape == (100,)


def test_logger_refuses_duplicates_and_late_submissions() -> None:
    logger = Logger(_Clock())
    logger.submit("a", lambda: 1.0)
    with pytest.raises(UsageError, match="already submitted"):
        logger.submit("a", lambda: 2.0)
    logger.update()
    with pytest.raises(UsageError, match="before the first update"):
        logger.submit("b", lambda: 2.0)


def test_npz_round_trip_is_exact(tmp_path) -> None:
    rec = _recorded()
    back = Recording.from_npz(rec.to_npz(tmp_path / "run.npz"))
    assert back.names == rec.names
    for name in rec.names:
        np.testing.assert_array_equal(back[name], rec[name])
    np.testing.assert_array_equal(back.time_s, rec.time_s)


def test_csv_round_trip_is_exact_and_columns_count_from_one(tmp_path) -> None:
    rec = _recorded()
    path = rec.to_csv(tmp_path / "run.csv")
    assert path.read_text().splitlines()[0] == "time_s,q[1],q[2],q[3],speed_m_s,tcp[1],tcp[2],tcp[3]"
    back = Recording.from_csv(path)
    for name in rec.names:
        np.testing.assert_array_equal(back[name], rec[name])


def test_plot_png_draws_signals_and_the_tcp_path(tmp_path) -> None:
    path = _recorded().plot_png(tmp_path / "run.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert path.stat().st_size > 5000


def test_unknown_signal_lists_the_known_ones() -> None:
    with pytest.raises(UsageError, match="no signal 'tau'.*q, speed_m_s, tcp"):
        _recorded()["tau"]


def test_a_derived_signal_is_its_function_of_the_recorded_samples_in_submission_order() -> None:
    clock, state = _Clock(), {"q": np.zeros(3)}
    logger = Logger(clock, capacity=16)
    logger.submit("q", lambda: state["q"])
    logger.derive("norm", "q", lambda q: np.array([np.linalg.norm(q), q[0]]))
    logger.submit("t2", lambda: 2.0 * clock.t)
    assert logger.recording()["norm"].shape == (0, 2), "an empty recording keeps the signal's width"
    for k in range(40):
        clock.t, state["q"] = 0.001 * k, np.array([k, -k, 0.5 * k]) / 7.0
        logger.update()
    rec = logger.recording()
    assert rec.names == ["q", "norm", "t2"]
    np.testing.assert_array_equal(rec["norm"][:, 0], np.linalg.norm(rec["q"], axis=1))
    np.testing.assert_array_equal(rec["norm"][:, 1], rec["q"][:, 0])
    with pytest.raises(UsageError, match="not a submitted signal"):
        logger.derive("twice", "norm", lambda x: x)
    with pytest.raises(UsageError, match="already submitted"):
        logger.derive("q", "t2", lambda x: x)
