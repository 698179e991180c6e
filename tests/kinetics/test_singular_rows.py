"""Singular equilibrium rows and the edges of self-locked zones.

The case: tests/hard/slider_crank_slider_driven.yaml, the shipped slider-crank
with no offset (a = 100 mm, b = 350 mm), its crank's motion prescribed and the
effort balanced at the slide, friction circles ρ_O = 1.5, ρ_A = 1.2,
ρ_B = 1.0 mm and Coulomb f = 0.1 at the slide, analysed on a 1° grid that
holds both dead centres (0° and 180°).

Independent truth for the edges of the locked zone around 0° (friction-circle
geometry).  Where the consistent reactions diverge, the finite loads (inertia,
gravity, resistance) are negligible beside them, so at an edge the linkage is
in equilibrium under friction alone.  Then crank and rod are two-force members
along one line F = |F|(cos φ, sin φ): the crank's moment about O, the rod's
about A (friction couple M = −s ρ |F| of link i on link j, s the sign of
ω_j − ω_i) give

    a sin(φ − ψ) = −s_O ρ_O + s_A ρ_A,     b sin(φ − β) = −s_A ρ_A + s_B ρ_B,

ψ the crank angle, β the rod's.  The slider only fixes the effort (its Coulomb
friction f|N| does not enter).  Near 0° the crank turns CCW (s_O = +1) and the
rod CW, slower (s_A = −1, s_B = +1), so the angle between crank and rod
γ = ψ − β at the two edges is ±(asin((ρ_O + ρ_A)/a) + asin((ρ_A + ρ_B)/b)),
and with e = 0 (B on the crank's axis of x) ψ = atan2(b sin γ, a + b cos γ).
"""

import re
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics.stages import full_summary

CASE = "tests/hard/slider_crank_slider_driven.yaml"
A, B = 100.0, 350.0
RHO_O, RHO_A, RHO_B = 1.5, 1.2, 1.0


def _edge_deg(rho_o=RHO_O, rho_a=RHO_A, rho_b=RHO_B) -> float:
    """Upper edge of the locked zone around crank 0° (the lower is its negative)."""
    g = np.arcsin((rho_o + rho_a) / A) + np.arcsin((rho_a + rho_b) / B)
    return float(np.degrees(np.arctan2(B * np.sin(g), A + B * np.cos(g))))


def _model(**subs) -> ks.Model:
    text = open(CASE).read()
    for old, new in subs.items():
        text, n = re.subn(old, new, text)
        assert n == 1, old
    return ks.loads(text, file="slider_crank_slider_driven.yaml")


def _quiet(model, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ks.analyze(model, **kw)


@pytest.fixture(scope="module")
def grid():
    with pytest.warns(UserWarning, match=r"singular at motor = 0°, 180°") as rec:
        r = ks.analyze(ks.load(CASE))
    assert any(type(w.message).__name__ == "SingularEquilibriumWarning" for w in rec)
    return r


def test_dead_centres_are_flagged_rows_not_a_crash(grid):
    dead = [0, 180]
    assert list(grid["angle"][dead]) == [0.0, 180.0]
    others = np.setdiff1d(np.arange(len(grid)), dead)
    for name in ("motor.force", "O.Fx", "A.Fy", "B.Fx", "slide.N", "slide.M"):
        assert np.isnan(grid[name][dead]).all(), name
        assert np.isfinite(grid[name][others]).all(), name
    # the flag: a singular position per row (group 'equilibrium'), friction.status 2
    sing = [(s.group, round(float(np.degrees(s.coordinate)) % 360, 9)) for s in grid.singular]
    assert sing == [("equilibrium", 0.0), ("equilibrium", 180.0)]
    assert not grid.indeterminate
    assert list(grid["friction.status"][dead]) == [2, 2]
    assert np.isnan(grid["motor.force_friction"][dead]).all()
    summary = grid.summary()
    assert [s["group"] for s in summary["singular_positions"]] == ["equilibrium"] * 2
    assert np.isfinite(summary["reaction_peaks"]["O"]["peak"])
    from kinetostatics.batch.variants import summary_row

    assert np.isfinite(summary_row(grid)["O.reaction_peak"])


def test_other_rows_are_intact(grid):
    # the effort of every other row closes the power balance (an energy identity,
    # not the reactions' own equations) ...
    ok = np.isfinite(grid["power.residual"])
    assert ok.sum() == len(grid) - 2
    scale = np.nanmax(np.abs(grid["power.input"]))
    assert np.max(np.abs(grid["power.residual"][ok])) < 1e-9 * scale
    # ... and does not depend on the singular rows being in the same run
    rows = [1, 2, 179, 181, 270]
    alone = _quiet(ks.load(CASE), positions=np.radians(grid["angle"][rows]))
    for name in ("motor.force", "O.Fx", "motor.force_friction", "friction.status"):
        np.testing.assert_allclose(alone[name], grid[name][rows], rtol=1e-12, atol=1e-9)


def test_frictionless_run_flags_the_same_rows():
    with pytest.warns(UserWarning, match=r"singular at motor = 0°, 180°"):
        r = ks.analyze(ks.load(CASE), friction=False)
    assert "friction.status" not in r.columns
    assert np.isnan(r["motor.force"][[0, 180]]).all()
    assert np.isfinite(np.delete(r["motor.force"], [0, 180])).all()
    assert [s.group for s in r.singular] == ["equilibrium"] * 2 and not r.indeterminate


def test_locked_rows_on_the_grid_match_the_closed_form(grid):
    e = _edge_deg()  # 1.4835°: rows 359, 0, 1 locked
    ang = grid["angle"]
    inside = (ang < e) | (ang > 360 - e)
    locked = grid["friction.status"] == 2
    assert np.array_equal(locked[inside], np.ones(inside.sum(), bool))
    # around 180° the slide absorbs power: the branch stays finite through
    # the dead centre, where only the singular row itself is flagged
    assert (grid["power.input"][[178, 179, 181]] < 0).all()
    near = np.abs(ang - 180) <= 3
    assert list(np.nonzero(locked & near)[0]) == [180]
    assert locked.sum() == inside.sum() + 1


@pytest.mark.parametrize("slide_f", [None, "0.30"])
@pytest.mark.parametrize("eps", [1e-4, 1e-6, 1e-7])
def test_rows_beside_the_edges_are_solved_or_locked_as_the_closed_form_says(eps, slide_f):
    model = (
        ks.load(CASE)
        if slide_f is None
        else _model(**{r"coefficient: 0.10": f"coefficient: {slide_f}"})
    )
    e = _edge_deg()  # the slide's friction does not move it
    outside = np.array([e + eps, -e - eps])
    inside = np.array([e - eps, -e + eps])
    r = _quiet(model, positions=np.radians(np.concatenate((outside, inside))))
    st = r["friction.status"]
    assert list(st[:2]) == [1, 1] and list(st[2:]) == [2, 2]
    # solved: finite, balanced (energy), and diverging like 1/distance to the edge
    f = r["motor.force_friction"][:2]
    assert np.isfinite(f).all()
    loss = np.abs(r["power.friction"][:2])
    assert np.all(np.abs(r["power.residual_friction"][:2]) <= 1e-8 * loss)
    far = _quiet(model, positions=np.radians([e + 10 * eps, -e - 10 * eps]))
    np.testing.assert_allclose(far["motor.force_friction"] * 10, f, rtol=2e-3)


def test_friction_only_at_the_slide_locks_only_the_dead_centres():
    # reduced case: ρ = 0 at O, A, B; then γ = 0: the edges are the dead centres
    model = _model(
        **{
            r"radius: 1.5\}": "radius: 0.0}",
            r"radius: 1.2\}": "radius: 0.0}",
            r"radius: 1.0\}": "radius: 0.0}",
        }
    )
    assert _edge_deg(0.0, 0.0, 0.0) == 0.0
    ang = np.array([-1e-4, 1e-4, 0.0, 180 - 1e-4, 180 + 1e-4, 180.0])
    r = _quiet(model, positions=np.radians(ang))
    st = r["friction.status"]
    assert list(st[[2, 5]]) == [2, 2] and (st[[0, 1, 3, 4]] < 2).all()
    assert np.isfinite(r["motor.force_friction"][[0, 1, 3, 4]]).all()


def test_reported_zone_edges_match_the_closed_form(grid):
    zones = full_summary(grid)["self_locking"]
    e = _edge_deg()
    zero = [z for z in zones if z["rows"] == 3]
    assert len(zero) == 1 and zero[0]["unit"] == "deg"
    assert zero[0]["from"] == pytest.approx(360 - e, abs=1e-8)
    assert zero[0]["to"] == pytest.approx(e, abs=1e-8)
    # 180°: the singular row alone, with the positions where the slide's speed per unit
    # crank speed, ẋ_B/(ω L_ref) = a sin δ (1 − a cos δ/√(b² − a² sin² δ))/L_ref ≈ a δ (1 − a/b)
    # /L_ref (L_ref = b), is at most reactions.EFFORT_SPEED_TOL: no effort to round-off there
    from kinetostatics.kinetics.reactions import EFFORT_SPEED_TOL

    half = np.degrees(EFFORT_SPEED_TOL * B / (A * (1 - A / B)))  # 2.8e-5°
    dead = [z for z in zones if z["rows"] == 1]
    assert (
        len(dead) == 1
        and dead[0]["from"] == pytest.approx(180 - half, abs=1e-6)
        and dead[0]["to"] == pytest.approx(180 + half, abs=1e-6)
    )


def test_run_reports_the_rows_and_zones(tmp_path, capsys):
    from kinetostatics.cli import main

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["run", CASE, "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "singular position: equilibrium at 0.0000°" in out
    assert "singular position: equilibrium at 180.0000°" in out
    e = _edge_deg()
    assert f"self-locked zone from {360 - e:.9g}° to {e:.9g}° (3 rows)" in out
    lines = (tmp_path / "results.csv").read_text().splitlines()
    header = lines[1].split(",")
    row0 = dict(zip(header, lines[2].split(",")))
    assert row0["motor.force"] == "" and row0["friction.status"] == "2.0"
