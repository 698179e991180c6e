"""The cycle integrator (analysis/cycle.py) is exact between its breaks: Gauss–Legendre of
order 8 and of order 16 on twice as many pieces agree to round-off only if every jump and
kink of the integrand is a break.  Each kind of break is checked by removing it: the two
orders then disagree by orders of magnitude more (the check can fail).

The breaks: load events, load reversals, friction reversals (the friction effort jumps),
kinks of the friction laws (a normal force through zero), a cam law's segment ends (an
acceleration jumps) and the zeros of the driving effort (a motor's torque behind a
reduction has a kink there).
"""

from __future__ import annotations

import pytest

import kinetostatics as ks
from kinetostatics.analysis import cuts, cycle

from .helpers import ROOT


def _stats(name: str, columns, nodes: int, pieces: int, monkeypatch, **off):
    monkeypatch.setattr(cycle, "NODES", nodes)
    monkeypatch.setattr(cycle, "PIECES", pieces)
    # the fixed rule: halving the pieces where the efforts look unresolved would make up
    # for a missing break (at the cost of more nodes), and these tests are about the breaks
    monkeypatch.setattr(cycle, "SPLITS", 0)
    for fn in off:
        monkeypatch.setattr(cuts, fn, lambda result: [])
    path = ROOT / "mechanisms" / f"{name}.yaml"
    if not path.exists():
        path = ROOT / "tests" / "drive" / f"{name}.yaml"
    r = ks.analyze(ks.load(path))
    return cycle.cycle_stats(r, columns)


def _disagreement(name, columns, monkeypatch, **off) -> float:
    """Largest |mean or RMS (order 8) − (order 16)| over the RMS, among ``columns``."""
    a = _stats(name, columns, 8, 36, monkeypatch, **off)
    b = _stats(name, columns, 16, 72, monkeypatch, **off)
    return max(abs(a[c][k] - b[c][k]) / abs(b[c]["rms"]) for c in columns for k in ("mean", "rms"))


CASES = [  # (file, columns, the break that matters there, its disagreement without it)
    ("slotting_machine", ["motor.torque_friction"], "_friction_kinks", 1e-7),
    ("slotting_machine", ["motor.torque_friction"], "_friction_reversals", 1e-6),
    ("slider_crank", ["motor.torque_friction"], "_friction_kinks", 1e-8),
    ("shaper", ["motor.torque_friction"], "_friction_reversals", 1e-6),
    ("jaw_crusher", ["motor.torque_friction"], "_friction_reversals", 1e-5),
    ("cam_roller", ["motor.torque"], "_motion_breaks", 1e-8),
    ("cam_roller", ["motor.torque_friction"], "_motion_breaks", 1e-7),
    ("cam_roller", ["motor.torque_friction"], "_friction_kinks", 1e-8),
]


@pytest.mark.parametrize(("name", "columns", "brk", "without"), CASES)
def test_two_orders_agree_with_the_breaks_and_not_without(name, columns, brk, without, monkeypatch):
    # with every break: round-off, or the 1e-9·speed dead band of a friction reversal
    # (docs/conventions.md: no friction effort where |ċ| ≤ 1e-9 of its reference)
    assert _disagreement(name, columns, monkeypatch) < 1e-9
    assert _disagreement(name, columns, monkeypatch, **{brk: None}) > without


def test_the_motor_torque_behind_a_reduction_is_exact(monkeypatch):
    """The drive's motor-side mean and RMS (a kink where the power turns) agree between the
    two orders; without the zeros of the driving torque as breaks they do not."""
    from kinetostatics.dynamics.drive import size

    def motor(off):
        out = []
        for nodes, pieces in ((8, 36), (16, 72)):
            monkeypatch.setattr(cycle, "NODES", nodes)
            monkeypatch.setattr(cycle, "PIECES", pieces)
            monkeypatch.setattr(cycle, "SPLITS", 0)  # the fixed rule (see _stats)
            if off:
                monkeypatch.setattr(cuts, "effort_zeros", lambda result: [])
            r = ks.analyze(ks.load(ROOT / "tests" / "drive" / "slotting_machine_drive.yaml"))
            out.append(size(r).motor["torque"])
        (a, b) = out
        return max(abs(a[k] - b[k]) / abs(b["rms"]) for k in ("mean", "rms"))

    assert motor(off=False) < 1e-8
    assert motor(off=True) > 1e-8


def _net_case(name: str):
    """A mechanism the net's generator made before it changed, kept as written."""
    import yaml

    return yaml.safe_load((ROOT / "tests" / "net" / "cases" / name).read_text(encoding="utf-8"))


def test_a_sharp_peak_is_resolved_by_halving_the_pieces(monkeypatch):
    """A generated linkage passing near a singular position: its driving torque peaks at
    400 times its median, smooth but sharp, and 8-point Gauss on the fixed pieces leaves
    5e-10 of the peak against 16-point; the pieces whose Legendre tails say so are halved,
    and the two orders agree to round-off."""
    from .net import relations as R

    doc = _net_case("sharp_peak_near_singular.yaml")
    assert R.relation_cycle_means(doc, 0) <= 1e-12
    monkeypatch.setattr(cycle, "SPLITS", 0)
    assert R.relation_cycle_means(doc, 0) > 1e-11


def test_the_flywheel_swing_at_an_extreme_inside_a_piece_is_exact(monkeypatch):
    """ΔW at an extreme inside a piece: the interpolant's integral up to it is only as
    exact as the interpolation (5e-12 of the work between the orders here, on the fixed
    pieces); the quadrature on the piece's part up to the extreme is exact."""
    from .net import relations as R

    monkeypatch.setattr(cycle, "SPLITS", 0)
    assert R.relation_cycle_means(_net_case("extreme_inside_a_piece.yaml"), 0) <= 1e-12
