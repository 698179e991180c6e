"""Tests for kinetostatics.base.units."""

import math

import pytest

from kinetostatics.base.units import (
    QUANTITY_KINDS,
    SI_UNITS,
    UNITS,
    UnitError,
    factor,
    is_angular_speed,
    unit_table,
)


def test_kinds_and_si_units():
    assert QUANTITY_KINDS == (
        "length",
        "angle",
        "speed",
        "time",
        "mass",
        "force",
        "torque",
        "inertia",
    )
    assert set(SI_UNITS) == set(QUANTITY_KINDS) == set(UNITS)
    for kind, unit in SI_UNITS.items():
        assert factor(kind, unit) == 1.0


@pytest.mark.parametrize(
    ("kind", "unit", "expected"),
    [
        ("length", "mm", 1e-3),
        ("length", "cm", 1e-2),
        ("length", "km", 1e3),
        ("length", "um", 1e-6),
        ("length", "µm", 1e-6),
        ("length", "in", 0.0254),
        ("length", "ft", 0.3048),
        ("angle", "deg", math.pi / 180),
        ("angle", "rev", 2 * math.pi),
        ("speed", "rpm", 2 * math.pi / 60),
        ("speed", "deg/s", math.pi / 180),
        ("speed", "rev/s", 2 * math.pi),
        ("speed", "rps", 2 * math.pi),
        ("speed", "mm/s", 1e-3),
        ("speed", "cm/s", 1e-2),
        ("time", "ms", 1e-3),
        ("time", "min", 60.0),
        ("time", "h", 3600.0),
        ("mass", "g", 1e-3),
        ("mass", "t", 1e3),
        ("mass", "lb", 0.45359237),
        ("force", "kN", 1e3),
        ("force", "mN", 1e-3),
        ("force", "kgf", 9.80665),
        ("force", "lbf", 4.4482216152605),
        ("torque", "N·m", 1.0),
        ("torque", "Nm", 1.0),
        ("torque", "kN*m", 1e3),
        ("torque", "N*mm", 1e-3),
        ("torque", "N·mm", 1e-3),
        ("torque", "Nmm", 1e-3),
        ("inertia", "kg·m²", 1.0),
        ("inertia", "kg*mm^2", 1e-6),
        ("inertia", "kg·mm²", 1e-6),
        ("inertia", "kg*cm^2", 1e-4),
        ("inertia", "g*cm^2", 1e-7),
        ("inertia", "kg mm^2", 1e-6),
        ("inertia", " kg * m ^ 2 ", 1.0),
        ("torque", "N m", 1.0),
        ("inertia", "kg*mm**2", 1e-6),
    ],
)
def test_factors(kind, unit, expected):
    assert factor(kind, unit) == pytest.approx(expected, rel=1e-15)


def test_unknown_unit_with_suggestion():
    with pytest.raises(UnitError) as info:
        factor("length", "mmm")
    assert str(info.value) == (
        "unknown length unit 'mmm' (did you mean 'mm'?); known: cm, ft, in, km, m, mm, um"
    )
    with pytest.raises(UnitError, match="did you mean 'rpm'"):
        factor("speed", "rpmm")
    with pytest.raises(UnitError, match="unknown force unit 'zzzz'; known"):
        factor("force", "zzzz")
    with pytest.raises(UnitError, match="must be a string"):
        factor("length", 3)


def test_unknown_kind_with_suggestion():
    with pytest.raises(
        UnitError, match=r"^unknown quantity kind 'lenght' \(did you mean 'length'\?\)"
    ):
        factor("lenght", "m")
    with pytest.raises(UnitError, match="unknown quantity kind 'acceleration'"):
        factor("acceleration", "m/s^2")


def test_is_angular_speed():
    assert is_angular_speed("rpm")
    assert is_angular_speed("rad/s")
    assert not is_angular_speed("mm/s")
    assert not is_angular_speed("m/s")
    with pytest.raises(UnitError):
        is_angular_speed("mm")


def test_unit_table():
    assert unit_table(None) == {kind: 1.0 for kind in QUANTITY_KINDS}
    table = unit_table({"length": "mm", "speed": "rpm", "inertia": "kg·mm²"})
    assert list(table) == list(QUANTITY_KINDS)
    assert table["length"] == 1e-3
    assert table["speed"] == pytest.approx(2 * math.pi / 60)
    assert table["inertia"] == 1e-6
    assert table["torque"] == 1.0  # not derived from length
    with pytest.raises(UnitError, match="did you mean 'length'"):
        unit_table({"lenght": "mm"})
    with pytest.raises(UnitError, match="unknown mass unit"):
        unit_table({"mass": "kgg"})
    with pytest.raises(UnitError, match="mapping"):
        unit_table(["mm"])
