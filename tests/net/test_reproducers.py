"""Minimal reproducers of defects the verification net found (docs/verification.md)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import yaml

import kinetostatics as ks

from . import relations as R

CASES = Path(__file__).resolve().parent / "cases"


def _analyze(doc):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ks.analyze(ks.loads(yaml.safe_dump(doc)), friction=False)


def test_refine_case_runs_without_its_switching_conditions():
    doc = yaml.safe_load((CASES / "refine_jumps.yaml").read_text(encoding="utf-8"))
    res = _analyze(R.without_conditions(doc))
    assert len(res["angle"]) == 12 and np.all(np.isfinite(res["motor.torque"]))


def test_refine_case_with_its_switching_conditions():
    """The travel extremes and switches of this mechanism (rows 30° apart) were refined by an
    unbracketed Newton on t, which stepped 158° away and failed to assemble; the
    refinement now keeps to the sample interval of each root."""
    doc = yaml.safe_load((CASES / "refine_jumps.yaml").read_text(encoding="utf-8"))
    res = _analyze(doc)
    assert len(res["angle"]) == 12 and np.all(np.isfinite(res["motor.torque"]))


def test_angle_band_edges_of_a_crank_that_cannot_turn_fully():
    """Angle-band switches of a crank with an unreachable zone are taken within its reachable
    range (or dropped where it never gets): they were placed in the first turn, outside the
    range's span, and refined from a far sample ('cannot assemble')."""
    doc = yaml.safe_load((CASES / "reachable_angle_bands.yaml").read_text(encoding="utf-8"))
    assert R.relation_power_fd(doc, 600009) <= R.TOLERANCE["power_fd"]
    assert R.relation_power(doc, 600009) <= R.TOLERANCE["power"]


def test_pressure_angle_near_zero_is_computed_to_full_precision():
    """The pressure (and transmission) angle was the arccos of a cosine, which loses half the
    digits near 0°: a pressure angle of 0.0007° came out 5e-10° apart from the same pose in a
    grid and alone, 7e-7 of itself (seed 1005175, relation grid). It is now the atan2 of the
    cross and dot products."""
    doc = yaml.safe_load((CASES / "pressure_angle_near_zero.yaml").read_text(encoding="utf-8"))
    assert R.relation_grid(doc, 1005175) <= R.TOLERANCE["grid"]


def test_derivatives_of_a_sharp_motion():
    """The central differences' O(h²) truncation error of this sharp motion was 1.8e-3 of the
    column's scale at h/2, above the tolerance though the exact derivatives are right (seed
    1005196, relation derivatives); the relation now compares the Richardson extrapolation of
    the two steps (O(h⁴)) and still requires the h² convergence."""
    doc = yaml.safe_load((CASES / "sharp_accelerations.yaml").read_text(encoding="utf-8"))
    R.DERIV.clear()
    assert R.relation_derivatives(doc, 1005196) <= R.TOLERANCE["derivatives"]
    h, half = R.DERIV[0][:2]
    assert half > R.TOLERANCE["derivatives"] and 3.9 < h / half < 4.1  # the case: pure h²


def test_derivatives_where_the_step_does_not_resolve_the_motion():
    """At a toggle (seed 1002072: t3.alpha from -12,614 to 44,201 within 0.02 rad) the
    differences were not yet O(h²) and the relation reported inf; at a narrow peak (seed
    1003449, b25.ax) the extrapolation of h and h/2 kept an O(h⁴) term of 4.4e-3. The exact
    derivatives are right in both; the relation now halves the step until two successive
    extrapolations agree, and still flags an exact derivative that is off."""
    for name, seed in (
        ("toggle_accelerations.yaml", 1002072),
        ("narrow_acceleration_peak.yaml", 1003449),
    ):
        doc = yaml.safe_load((CASES / name).read_text(encoding="utf-8"))
        R.DERIV.clear()
        assert R.relation_derivatives(doc, seed) <= R.TOLERANCE["derivatives"]
        assert max(len(e) for e in R.DERIV) > 3  # it took steps below h/4


def test_derivatives_round_off_of_small_steps_is_no_error():
    """Seed 1005742: the crank's exact alpha is 0; at h/128 (needed by other columns) the
    second difference of its angle is round-off, 4 eps|theta|/dt^2, which grew 4x per
    halving and failed the h^2 check (inf). The round-off floor is now taken off."""
    doc = yaml.safe_load((CASES / "roundoff_at_small_steps.yaml").read_text(encoding="utf-8"))
    assert R.relation_derivatives(doc, 1005742) <= R.TOLERANCE["derivatives"]


def test_derivatives_with_an_acceleration_jump_in_the_stencil():
    """Seed 1006298: a sample lies within 3.1e-4 rad of a cam law's segment end, where the
    follower's acceleration jumps; the second difference straddling it is off by O(1) (0.07
    of the scale at 3.1e-4 rad) and right once the step no longer reaches it (h/128), and
    extrapolating across that change reported 0.024.  The difference that agrees is now
    compared as it is."""
    doc = yaml.safe_load(
        (CASES / "acceleration_jump_in_the_stencil.yaml").read_text(encoding="utf-8")
    )
    R.DERIV.clear()
    assert R.relation_derivatives(doc, 1006298) <= R.TOLERANCE["derivatives"]
    errs = max(R.DERIV, key=len)
    assert errs[-2] > 0.05 and errs[-1] < 1e-4  # the jump left the stencil at the last step


def test_slide_moment_and_friction_method_near_a_dead_point():
    """A slide's moment reaction is a force times an offset: near a dead point (reactions of
    3.7e14 N) its round-off is that of the forces times the mechanism's size, and the
    friction status says solved whether the fixed point or the homotopy found the solution
    (seed 1004917, relations subset, rigid, units)."""
    doc = yaml.safe_load((CASES / "near_dead_point_friction.yaml").read_text(encoding="utf-8"))
    for name in ("subset", "rigid", "units"):
        relation = getattr(R, f"relation_{name}")
        assert relation(doc, 1004917) <= R.TOLERANCE[name], name


def test_efficiency_where_the_effort_with_friction_is_near_zero():
    """η = T/T_f carries the round-off of T and T_f divided by T_f (seed 1005557)."""
    doc = yaml.safe_load((CASES / "efficiency_near_zero_effort.yaml").read_text(encoding="utf-8"))
    assert R.relation_units(doc, 1005557) <= R.TOLERANCE["units"]


def test_compare_still_sees_a_wrong_slide_moment_or_efficiency():
    """The scales above do not blind the comparison on ordinary machines: a slide moment off
    by 1e-5 of its column, or an efficiency off by 1e-5 of itself where the effort with
    friction is at its peak, fails it."""
    root = Path(__file__).resolve().parents[2] / "mechanisms"
    for name, c, den in (
        ("inverted_slider_crank.yaml", "slot.M", None),
        ("rack_rocker.yaml", "guide.M", None),
        ("slotting_machine.yaml", "motor.efficiency", "motor.torque_friction"),
    ):
        base = R.analyze(R.shipped(root / name))
        cols = {n: np.asarray(base[n], float).copy() for n in base.names}
        if den is None:
            k = int(np.nanargmax(np.abs(cols[c])))
            cols[c][k] += 1e-5 * np.abs(cols[c][k])
        else:
            k = int(np.nanargmax(np.abs(cols[den])))
            cols[c][k] *= 1.0 + 1e-5
        assert R.compare(R._Cols(cols), base) > 1e-7, (name, c)


def test_a_motion_that_does_not_close_after_one_turn_says_so():
    """Seed 1007280: the triad's branch, followed once round, comes back elsewhere (link t3
    1.1 rad off), without a singular row on the way. The one-turn result now fails its
    closure self-check, naming the link; the shipped machines close to round-off."""
    doc = yaml.safe_load((CASES / "open_cycle_triad.yaml").read_text(encoding="utf-8"))
    res = _analyze(doc)
    closure = res.checks.closure
    assert closure is not None and not closure.ok and closure.value > 0.1
    assert "t3" in closure.where and "closure" in res.checks.warning()
    shipped = Path(__file__).resolve().parents[2] / "mechanisms" / "slotting_machine.yaml"
    assert ks.analyze(ks.load(shipped)).checks.closure.value < 1e-12


def test_cam_status_in_a_dwell_with_no_force():
    """In the dwells of this cam nothing presses the follower: the contact force is 0 in
    exact arithmetic (±6e-15 N computed), and the follower does not leave the cam (status
    0) on any row: a reaction within round-off (1e-12) of the run's largest is 0 for the
    joints' columns and warnings.  Its dwell rows read 1, 0, 1, 1, 0, 1 before."""
    doc = yaml.safe_load((CASES / "cam_status_roundoff.yaml").read_text(encoding="utf-8"))
    res = _analyze(doc)
    lift = np.asarray(res["contact.lift"])
    dwell = (np.abs(lift - np.max(lift)) < 1e-12) | (np.abs(lift) < 1e-12)
    assert dwell.sum() >= 8
    assert np.all(np.asarray(res["contact.status"])[dwell] == 0)


def test_a_cut_far_from_its_row_is_reached_by_steps():
    """A cut of the cycle integral (a load condition's switch) between rows 30° apart is
    refined by Newton from the nearest row's Taylor guess; for this triad the guess at
    306.35° lay outside Newton's basin and the cycle stage refused a mechanism that
    assembles there (seed 1002226, relation batch_row). The state is now walked to the
    root in steps; the cycle's means are those of a run at 72 rows (the cuts make them
    independent of the rows, docs/conventions.md)."""
    from kinetostatics.dynamics.stages import cycle_stage

    doc = yaml.safe_load((CASES / "triad_root_far_from_row.yaml").read_text(encoding="utf-8"))
    means = []
    for n in (12, 72):
        doc["analysis"]["positions"] = n
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = ks.analyze(ks.loads(yaml.safe_dump(doc)), friction=False)
            stats = cycle_stage(res).drivers
        means.append({k: (v["mean"], v["rms"]) for k, v in stats.items()})
        scale = float(np.max(np.abs(res["motor.torque"])))
    assert means[0].keys() == means[1].keys() and means[0]
    for k, (mean, rms) in means[0].items():
        assert abs(mean - means[1][k][0]) <= 1e-10 * scale
        assert abs(rms - means[1][k][1]) <= 1e-10 * scale


def test_the_efficiency_of_an_idle_drive_is_undefined_in_every_run():
    """Where the drive idles (every effort a round-off zero, ±1e-16 N·m) η was 0 in one
    run and undefined in a subset of its rows, by the sign of a round-off zero (seeds
    1000434, 1000669, 1001090, 1002730: relations subset, rigid, units, mirror, grid).
    An effort with friction below 1e-12 of the row's largest reaction (times the size,
    docs/friction.md) now counts as none."""
    doc = yaml.safe_load((CASES / "efficiency_idle_drive.yaml").read_text(encoding="utf-8"))
    assert R.relation_subset(doc, 1000434) <= R.TOLERANCE["subset"]
    res = R.analyze(doc)
    tau = np.asarray(res["motor.torque_friction"])
    eta = np.asarray(res["motor.efficiency"])
    idle = np.abs(tau) < 1e-12 * np.nanmax(np.abs(tau))
    assert idle.any() and np.all(np.isnan(eta[idle]))


def test_a_row_one_turn_later_is_another_state_where_the_cycle_does_not_close():
    """The closure self-check fails on this mechanism (a group changes branch over the
    turn), and its events run ends with a row at the first row's angle, one turn later,
    on the other branch: the subset relation took the two for the same row (seed 1000172).
    The run says so; the relation matches rows by time."""
    doc = yaml.safe_load((CASES / "open_cycle_end_row.yaml").read_text(encoding="utf-8"))
    res = _analyze(doc)
    assert res.checks.closure is not None and not res.checks.closure.ok
    assert R.relation_subset(doc, 1000172) <= R.TOLERANCE["subset"]


def test_a_rest_then_motion_the_other_way_is_no_switch():
    """L1 acts while f1.c2 moves along its axis. The point comes to rest (±1e-17 m/s) and
    then moves the other way: no switch there. The sign of the round-off at rest made one,
    'on' in SI and 'off' in mm/deg/rpm, 1e-4 s apart (seed 1000006). The events are now the
    same in both unit systems, and none lies in the rest."""
    doc = yaml.safe_load((CASES / "rest_then_other_way.yaml").read_text(encoding="utf-8"))
    doc["analysis"]["positions"] = 12
    runs = [_analyze(doc), _analyze(R.G.in_units(doc, "mm", "deg", "rpm"))]
    events = [[(e.load, e.switch, e.t) for e in r.events] for r in runs]
    assert [e[:2] for e in events[0]] == [e[:2] for e in events[1]]
    scale = float(np.ptp(runs[0].t))  # the rows' time span
    for (_, _, ta), (_, _, tb) in zip(*events, strict=True):
        assert abs(ta - tb) <= 1e-9 * scale
    assert R.relation_units(doc, 1000006) <= R.TOLERANCE["units"]


def test_an_idle_tooth_force_makes_no_cuts():
    """The gear's frictionless tooth force is a round-off zero (±1e-15 N against reactions
    of 90 N): its random signs were cut as kinks of the mesh's friction law, at other times
    in mm/deg/rpm than in SI, and the drive's motor power peak, sampled at the nodes, moved
    by 9.5e-5 of itself (seed 1002093). A reaction within 1e-12 of the run's largest is now
    no sign: the two runs have the same cuts."""
    from kinetostatics.analysis.cuts import breaks, span

    doc = yaml.safe_load((CASES / "idle_tooth_force.yaml").read_text(encoding="utf-8"))
    cuts = []
    for d in (doc, R.G.in_units(doc, "mm", "deg", "rpm")):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = ks.analyze(ks.loads(yaml.safe_dump(d)))
            cuts.append(breaks(res, *span(res), friction=True))
    assert len(cuts[0]) == len(cuts[1])
    assert np.max(np.abs(cuts[0] - cuts[1])) <= 1e-9 * (cuts[0][-1] - cuts[0][0])
    assert R.relation_units(doc, 1002093) <= R.TOLERANCE["units"]


def test_a_pin_force_near_zero_is_resolved_in_the_friction_means():
    """Pin J7's force passes within 0.34 N of zero (88 N at most): ρ|F| has a sharp but
    smooth minimum, and the pieces were halved only where the frictionless efforts were
    unresolved; the friction means of the two orders differed by 1.4e-6 of the RMS (seed
    1002276). The efforts with friction are now checked too."""
    doc = yaml.safe_load((CASES / "pin_force_near_zero.yaml").read_text(encoding="utf-8"))
    assert R.relation_quadrature(doc, 1002276) <= R.TOLERANCE["quadrature"]


def test_a_table_corner_that_turns_the_effort_back_through_zero():
    """A table's corner turns the falling driving torque back up 0.4 ms after it passed
    through zero: two zeros between two rows, one each side of the corner, which neither
    the rows nor the nodes (the corner, a cut, between the two that change sign) saw. The
    motor-side torque's kink lay inside a piece: the drive's mean motor power of the two
    orders differed by 9.2e-8 (seed 1002123). The kink functions are now sampled at the
    corners too."""
    doc = yaml.safe_load((CASES / "table_corner_turns_effort.yaml").read_text(encoding="utf-8"))
    assert R.relation_cycle_means(doc, 1002123) <= R.TOLERANCE["cycle_means"]


def test_a_sharp_peak_beside_a_singular_position_is_halved_far_enough():
    """The driving torque peaks at 4.9e5 N·m and passes through zero between its peaks
    within 4e-4 s; five halvings (1/32 of a piece) left it unresolved (seed 1002199): the
    two orders' RMS differ by 9.8e-6 N·m with five.  Pieces are now halved up to eight
    times, and the two agree to 1e-12 of the largest |torque| at the rows and the nodes,
    as the relation reads it since seed 1004622: read against the rows' 2.9e3 N·m
    instead, an SSE-only CPU's round-off (3.4e-9, 7e-15 of the peak; 6.7e-10 with
    AVX-512) failed it."""
    from kinetostatics.analysis.cycle import cycle_quadrature, cycle_stats

    doc = yaml.safe_load((CASES / "sharp_peak_needs_halving.yaml").read_text(encoding="utf-8"))
    res = _analyze(doc)
    quads = [cycle_quadrature(res, friction=False, quadrature=q) for q in R.CONVERGED]
    # the largest |torque| at the rows and at the nodes, as the cycle_means relation: the
    # peak between the rows (4.9e5 N·m against 2.9e3 at the rows) is what the sums round
    scale = max(float(np.max(np.abs(r["motor.torque"]))) for r in (res, *(q.nodes for q in quads)))
    assert scale > 1e5
    a, b = (
        cycle_stats(res, ["motor.torque"], friction=False, quadrature=q, given=g)["motor.torque"]
        for q, g in zip(R.CONVERGED, quads)
    )
    for key in ("mean", "rms"):
        assert abs(a[key] - b[key]) <= R.TOLERANCE["cycle_means"] * scale


def test_power_and_torque_roundoff_in_a_dwell_is_on_the_scale_of_their_factors():
    """The one row of a random run where a load acts lies in a cam's dwell: the powers are a
    torque times a zero speed (±1e-15 W) and the driving torque ±1e-16 N·m, while the run's
    largest power is 5e-3 W and torque 5e-5 N·m, beside reactions of 43 N; a row of the run
    and the pose alone differed by 2.4e-7 of those (seed 1003542, relation grid). A power's
    round-off is a force's times a speed's, a torque's a force's times the size: the
    relation's scales now say so."""
    doc = yaml.safe_load((CASES / "power_roundoff_in_a_dwell.yaml").read_text(encoding="utf-8"))
    assert R.relation_grid(doc, 1003542) <= R.TOLERANCE["grid"]


def test_a_peak_and_a_self_locked_zone_between_the_rows_are_said():
    """Seed 1007872: between two of the 24 rows the driving torque peaks near a dead point
    and the friction solution self-locks; the summary's peaks and self-locked zones are the
    rows', so the run said nothing, while the cycle's nodes saw both.  The cycle stage now
    warns of each, naming where.  Independently of the nodes: the run's own continuation at
    201 positions within ±1° of the named place reaches over twice the rows' peak."""
    import re

    from kinetostatics.dynamics.stages import cycle_stage

    doc = yaml.safe_load((CASES / "peak_and_locking_between_rows.yaml").read_text(encoding="utf-8"))
    model = ks.loads(yaml.safe_dump(doc))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        res = ks.analyze(model)
        cycle_stage(res)
    said = [str(x.message) for x in seen if "between the analysed rows" in str(x.message)]
    assert any(s.startswith("motor.torque_friction: no solution") for s in said)
    peak = next(s for s in said if s.startswith("motor.torque reaches"))
    at = float(re.search(r"at motor = ([-\d.]+)°", peak).group(1))
    rows = float(np.max(np.abs(res["motor.torque"])))
    w_ = doc["drivers"]["motor"]["motion"]["speed"]  # rad/s, start in rad (the file's units)
    near = np.radians(at + np.linspace(-1.0, 1.0, 201)) - doc["analysis"]["start"]
    times = np.sort(np.mod(near / w_, 2 * np.pi / abs(w_)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = ks.analyze(res.system, times=times, friction=False)
    assert np.max(np.abs(run["motor.torque"])) > 2 * rows


def test_a_batch_rows_time_ratio_is_the_single_runs():
    """Seed 1008937: a slide's limit positions over stacked variants were refined by plain
    Newton from the chord between two rows 30° apart, which went to another part of the
    cycle: the batch row's time ratio was 1.142, the single run's 1.0036.  The stacked
    refinement is now bracketed by the rows, as the single run's is."""
    doc = yaml.safe_load((CASES / "stacked_time_ratio.yaml").read_text(encoding="utf-8"))
    assert R.relation_batch_row(doc, 1008937) <= R.TOLERANCE["batch_row"]


def test_a_slide_at_rest_leaves_the_stacked_strokes():
    """Slide S11 comes to rest where the rocker before it dwells: its speed is 0 within
    round-off on rows 30° apart. Once the stacked analysis took mechanisms without closed
    forms (the rocker is a 1-link group), its strokes counted the round-off signs as the two
    crossings and refined a limit position inside the rest: the batch row's time ratio was
    1.1646, the single run's 1.0000 (seed 1300017). A slide at rest on a row now leaves the
    stacked strokes to its own analysis."""
    doc = yaml.safe_load((CASES / "stacked_slide_at_rest.yaml").read_text(encoding="utf-8"))
    assert R.relation_batch_row(doc, 1300017) <= R.TOLERANCE["batch_row"]


def test_a_cycle_efficiency_of_round_off_is_compared_on_its_unit():
    """The idle gear pair's cycle efficiency is a quotient of round-off (−7.08e-8, the tooth
    force 0 in exact arithmetic); stacked and alone it differs by 1.2e-15, 1.7e-8 of itself.
    A batch row's dimensionless quantity is compared on its unit's scale, 1."""
    doc = yaml.safe_load((CASES / "idle_tooth_force.yaml").read_text(encoding="utf-8"))
    assert R.relation_batch_row(doc, 1002093) <= R.TOLERANCE["batch_row"]
