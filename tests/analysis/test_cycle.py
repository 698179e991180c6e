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

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis import cuts, cycle
from tests.helpers import ROOT


def _stats(name: str, columns, nodes: int, pieces: int, monkeypatch, **off):
    monkeypatch.setattr(cycle, "NODES", nodes)
    monkeypatch.setattr(cycle, "PIECES", pieces)
    # the fixed rule: halving the pieces where the efforts look unresolved would make up
    # for a missing break (at the cost of more nodes), and these tests are about the breaks
    monkeypatch.setattr(cycle, "SPLITS", 0)
    for fn in off:
        monkeypatch.setattr(cuts, fn, lambda result: [])
    if off:  # the nodes would find what the rows' cuts lack (cuts.missed_cuts)
        monkeypatch.setattr(cycle, "missed_cuts", lambda *args: [])
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
    ("slotting_machine", ["motor.torque_friction"], "friction_rates", 1e-6),
    ("slider_crank", ["motor.torque_friction"], "_friction_kinks", 1e-8),
    ("shaper", ["motor.torque_friction"], "friction_rates", 1e-6),
    ("jaw_crusher", ["motor.torque_friction"], "friction_rates", 1e-5),
    # the roller's friction reverses 1.4e-6 s from each segment end (the zero-speed band's
    # edges, where a dwell starts or ends): those cuts alone would leave the segment ends
    # unseen by the nodes, so both are removed
    ("cam_roller", ["motor.torque"], "_motion_breaks friction_rates", 1e-8),
    ("cam_roller", ["motor.torque_friction"], "_motion_breaks friction_rates", 1e-7),
    ("cam_roller", ["motor.torque_friction"], "_friction_kinks", 1e-8),
]


@pytest.mark.parametrize(("name", "columns", "brk", "without"), CASES)
def test_two_orders_agree_with_the_breaks_and_not_without(name, columns, brk, without, monkeypatch):
    # with every break: round-off, or the 1e-9·speed dead band of a friction reversal
    # (docs/conventions.md: no friction effort where |ċ| ≤ 1e-9 of its reference)
    assert _disagreement(name, columns, monkeypatch) < 1e-9
    assert _disagreement(name, columns, monkeypatch, **dict.fromkeys(brk.split())) > without


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
    from tests.net import relations as R

    doc = _net_case("sharp_peak_near_singular.yaml")
    assert R.relation_cycle_means(doc, 0) <= 1e-12
    monkeypatch.setattr(cycle, "SPLITS", 0)
    assert R.relation_cycle_means(doc, 0) > 1e-11


def test_the_flywheel_swing_at_an_extreme_inside_a_piece_is_exact(monkeypatch):
    """ΔW at an extreme inside a piece: the interpolant's integral up to it is only as
    exact as the interpolation (5e-12 of the work between the orders here, on the fixed
    pieces); the quadrature on the piece's part up to the extreme is exact."""
    from tests.net import relations as R

    monkeypatch.setattr(cycle, "SPLITS", 0)
    assert R.relation_cycle_means(_net_case("extreme_inside_a_piece.yaml"), 0) <= 1e-12


def test_the_flywheel_swing_near_a_dead_point_stays_on_the_branch():
    """Seed 1006188: the driving torque peaks at ~10⁴ times its mean near a dead point, where
    the two branches of a dyad come close.  ΔW at the extreme inside a piece was integrated
    at positions continued from the run's nearest row, 0.13 rad away: some took the other
    branch and the swing was 2 % off (9 % with the 16-point rule).  Checked against the
    work between the design's two extremes by Simpson's rule on 40,001 positions of the
    run's own continuation (the branch tracked from the start), and the two orders."""
    from scipy.integrate import simpson

    from kinetostatics.dynamics.flywheel import design
    from tests.net import relations as R

    doc = _net_case("branch_near_a_dead_point.yaml")
    res = R.analyze(doc)
    fw = design(res, delta=0.05, friction=False)
    w, start = fw.omega_m, doc["analysis"]["start"]
    t = np.linspace(fw.at_max - start, fw.at_min - start, 40_001) / w
    run = ks.analyze(res.system, times=t, friction=False, events=False)
    work = simpson(w * (np.asarray(run["motor.torque"]) - fw.mean_torque), x=t)
    assert fw.energy_swing == pytest.approx(work, rel=1e-7)
    assert R.relation_cycle_means(doc, 0) <= 1e-12


def test_the_flywheel_of_a_parallelogram_stays_on_its_branch_past_the_change_points():
    """A parallelogram four-bar passes two change points (crank at 0° and 180°), where its
    closed form's branch changes; positions between the nodes continued from the nearest
    row with the sketch's branch took the crossed four-bar after them, and ΔW came out
    5.02 J (5.90 with 16 nodes).  With gravity, the rocker's centre of mass off its axis
    and a torque of 5 N·m on it (tests/base/test_strict_json.py's parallelogram, 24
    positions).  Exact: the coupler translates and crank and rocker turn
    at the crank's speed, so the kinetic energy is constant and M − M_d = dV/dφ: ΔW is the
    potential energy's range, 2g·|Σ m r| = 2·9.81·√(0.33² + 0.01²) J, and M_d = −5 N·m
    (the rocker's torque)."""
    import warnings

    import yaml

    from kinetostatics.dynamics.flywheel import design
    from tests.base.test_strict_json import PARALLELOGRAM

    doc = yaml.safe_load(PARALLELOGRAM)
    doc["gravity"] = [0, -9.81]
    doc["links"]["rocker"]["com"] = [80, 10]
    doc["loads"] = {"T": {"type": "torque", "link": "rocker", "value": 5}}
    doc["analysis"]["positions"] = 24
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ks.NearSingularWarning)
        res = ks.analyze(ks.loads(yaml.safe_dump(doc)), friction=False)
        fw = design(res, delta=0.05, friction=False)
    assert len(res.singular) == 2
    assert fw.energy_swing == pytest.approx(2 * 9.81 * np.hypot(0.33, 0.01), rel=1e-9)
    assert fw.mean_torque == pytest.approx(-5.0, rel=1e-9)


def test_an_effort_zero_just_after_a_cam_segment_end_is_cut():
    """Seed 1005308: at a cam law's segment end the follower's acceleration jumps, and the
    driving torque with it, from +0.030 to −0.0092 N·m; it crosses zero 3.5e-5 s later, a
    kink of the motor's torque behind the reduction.  The rows on either side have the same
    sign, so the zero was bracketed only by the nodes of the finer rule (the orders
    disagreed by 2.6e-8 of the motor's peak).  The segment ends are now found first and the
    efforts' zeros sought on each side of them, as at a load's switch."""
    from tests.net import relations as R

    assert R.relation_cycle_means(_net_case("effort_zero_after_a_cam_segment_end.yaml"), 0) <= 1e-12


def test_an_effort_dipping_through_zero_between_two_nodes_is_cut(monkeypatch):
    """Seed 1005331: the driving torque dips 5e-5 of its scale below zero and back within
    7e-4 s, between two nodes: no node changes sign, but the piece's interpolant has the
    two roots; sampled between them, the pair is bracketed and cut (without: 6.4e-9 of the
    motor's peak power between the orders)."""
    from tests.net import relations as R

    doc = _net_case("effort_dip_between_nodes.yaml")
    assert R.relation_cycle_means(doc, 0) <= 1e-12
    monkeypatch.setattr(cuts, "_dips", lambda *args: np.zeros(0))
    assert R.relation_cycle_means(doc, 0) > 1e-10


def test_the_means_near_a_dead_point_agree_on_the_scale_of_the_values_summed():
    """Seed 1004622: near a dead point the driving torque reaches 2.3e6 N·m at the nodes and
    689 N·m at the rows; its RMS (5.6e4) differs by 1.4e-9 between the orders, round-off of
    the values summed (6e-16 of the largest), not of the rows' 689 (2e-12).  The net's scale
    is now the largest |value| at the rows and the nodes."""
    from tests.net import relations as R

    doc = _net_case("effort_peak_between_rows.yaml")
    res = R.analyze(doc)
    nodes = cycle.cycle_quadrature(res, friction=False).nodes
    assert np.max(np.abs(nodes["motor.torque"])) > 1e3 * np.max(np.abs(res["motor.torque"]))
    assert R.relation_cycle_means(doc, 0) <= 1e-12


@pytest.mark.parametrize(
    ("case", "without"),
    [
        ("effort_zero_pair_between_rows.yaml", 1e-9),  # two kinks of the motor's torque
        ("rocker_reversal_pair_between_rows.yaml", 1e-10),  # two jumps of a resisting torque
    ],
)
def test_a_pair_of_cuts_between_two_rows_is_found_by_the_nodes(case, without, monkeypatch):
    """A sign change and its return between two rows leave the rows' signs equal: no bracket,
    no cut, and the two orders disagree (the net's generated mechanisms: 2.9e-8 and 2e-9 of
    the scale).  The quadrature nodes, 8 on every 1/36 of the span, see the pair; it is
    located as the rows' cuts are and the nodes placed again: the orders agree to
    round-off."""
    from tests.net import relations as R

    doc = _net_case(case)
    assert R.relation_cycle_means(doc, 0) <= 1e-12
    monkeypatch.setattr(cycle, "missed_cuts", lambda *args: [])
    monkeypatch.setattr(cycle, "SPLITS", 0)  # halving comes closer (5e-12) but cuts nothing
    assert R.relation_cycle_means(doc, 0) > without


def test_a_small_near_kink_on_a_large_effort_is_resolved_by_halving(monkeypatch):
    """A pin's friction torque through a sharp minimum (its force passes near zero), ~10⁴
    times smaller than the driving torque it rides on: the Legendre coefficients of a piece
    fall fast from the head and then stay on a plateau, so their decay from the head
    predicted 4e-14 and the piece was not halved, while 8- and 16-point Gauss differed by
    1.2e-7 of the RMS (seed 1003614, relation quadrature).  The tail's own decay now counts
    too."""
    from tests.net import relations as R

    doc = _net_case("near_kink_on_a_large_effort.yaml")
    assert R.relation_quadrature(doc, 0) <= 1e-12
    monkeypatch.setattr(cycle, "SPLITS", 0)
    assert R.relation_quadrature(doc, 0) > 1e-8


def test_a_moving_load_is_cut_where_its_speed_leaves_the_zero_speed_band(monkeypatch):
    """After a cam's dwell the follower's speed leaves 0 slowly: a load with a ``moving``
    condition comes on (for the rows and the nodes) 1.4e-4 s after the speed's zero, where
    it leaves the zero-speed band (docs/conventions.md).  Cut at the zero only, the two
    orders disagreed by 7e-11 of the scale; cut at the band's edge too, to round-off."""
    from tests.net import relations as R

    doc = _net_case("moving_load_after_a_dwell.yaml")
    assert R.relation_cycle_means(doc, 0) <= 1e-12
    monkeypatch.setattr(cuts, "condition_rates", lambda result: [])
    assert R.relation_cycle_means(doc, 0) > 1e-11


def test_a_switch_after_a_dwell_is_refined_off_the_dwell():
    """Refined from a row inside a cam's dwell, where the follower's acceleration is exactly
    0, Newton took the zero step for convergence and put the resistance's switch at the
    row, 5.4e-5 s before the follower's speed leaves the zero-speed band: the two orders of
    the cycle integral disagreed by 7e-6 of the RMS (with the zero step refused: round-off)."""
    from tests.net import relations as R

    assert R.relation_quadrature(_net_case("resistance_after_a_dwell.yaml"), 0) <= 1e-12
