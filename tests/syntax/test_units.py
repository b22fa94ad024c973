"""Units: literals become SI quantities; arithmetic checks dimensions and names both in errors."""

from __future__ import annotations

import math

import pytest

from orc_rpl.syntax import units as u

LITERALS = [
    ("100mm/s", 0.1, u.VELOCITY),
    ("90deg", math.pi / 2, u.ANGLE),
    ("80ms", 0.08, u.TIME),
    ("0.5s", 0.5, u.TIME),
    ("20N", 20.0, u.FORCE),
    ("1.5mps", 1.5, u.VELOCITY),
    ("300mm", 0.3, u.LENGTH),
    ("2m/s2", 2.0, u.ACCELERATION),
    ("7Nm", 7.0, u.TORQUE),
    ("12kg", 12.0, u.MASS),
]


@pytest.mark.parametrize("text, value, dim", LITERALS, ids=[c[0] for c in LITERALS])
def test_literal_is_si_quantity(text: str, value: float, dim: u.Dimension) -> None:
    q = u.parse_literal(text)
    assert isinstance(q, u.Quantity) and q.dim == dim and q.value == pytest.approx(value, rel=1e-15)


def test_plain_numbers_and_percent_are_dimensionless() -> None:
    assert u.parse_literal("12") == 12 and isinstance(u.parse_literal("12"), int)
    assert u.parse_literal("1.5e-3") == 0.0015
    assert u.parse_literal("50%") == 0.5


def test_mixing_dimensions_names_both() -> None:
    with pytest.raises(u.DimensionError, match=r"cannot add time \(s\) and length \(m\)"):
        u.add(u.parse_literal("1s"), u.parse_literal("2mm"))


def test_products_derive_dimensions_and_cancel_to_numbers() -> None:
    speed = u.divide(u.parse_literal("3m"), u.parse_literal("2s"))
    assert speed == u.Quantity(1.5, u.VELOCITY)
    assert u.divide(u.parse_literal("3m"), u.parse_literal("1m")) == 3.0


@pytest.mark.parametrize("value, text", [(3, "3"), (3.0, "3"), (0.25, "0.25"), (0.1 + 0.2, "0.30000000000000004"), (-2.5, "-2.5")])
def test_number_formatting_is_shortest_round_trip(value: float, text: str) -> None:
    assert u.format_number(value) == text


def test_quantity_prints_in_si_with_unit() -> None:
    assert str(u.parse_literal("100mm")) == "0.1 m"
    assert str(u.parse_literal("1.5mps")) == "1.5 m/s"
