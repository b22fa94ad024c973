"""Fixtures for the motion tests: motion layers on the virtual robot."""

from __future__ import annotations

import pytest

from orc_rpl.motion import MotionLayer, make_virtual_motion_layer


@pytest.fixture
def kinematic() -> MotionLayer:
    return make_virtual_motion_layer(backend="kinematic")


@pytest.fixture
def servo() -> MotionLayer:
    return make_virtual_motion_layer(backend="servo", plant="ideal")
