"""A population of designs evaluated as one vectorised analysis, computing only what the
expressions name (docs/batch.md, *What a row computes*): each design's value is that of
its own single analysis, and the search is the one that computes every quantity."""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.batch import designs as designs_module
from kinetostatics.batch import variants
from kinetostatics.batch.variants import RowNeeds, Template, analyze_variants, row_needs
from tests.helpers import ROOT

SLOTTER = ROOT / "mechanisms" / "slotting_machine.yaml"
# a population over the rod and the frame distance: all assemble, some self-lock nowhere
POPULATION = [
    {"BC_ratio": b, "L_O2O3": d}
    for b, d in zip(np.linspace(0.8, 1.2, 4), np.linspace(130.0, 170.0, 4)[::-1])
]
POSITIONS = 24


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(x * x)))


@pytest.fixture(scope="module")
def template():
    return Template.load(SLOTTER)


@pytest.fixture(scope="module")
def singles(template):
    """Each design's own analysis (``ks.analyze``), with both friction solutions."""
    return [ks.analyze(template.model(ov, positions=POSITIONS)) for ov in POPULATION]


@pytest.mark.parametrize(
    "name, column",
    [("motor.torque_friction_rms", "motor.torque_friction"), ("motor.torque_rms", "motor.torque")],
)
def test_a_population_row_is_its_single_run(template, singles, name, column):
    """The population's values (one stacked analysis, only what ``name`` needs) are each
    design's single analysis, the RMS taken here over its column, to 1e-10 of their
    scale."""
    rows = analyze_variants(template, POPULATION, positions=POSITIONS, needs=[name])
    expected = np.array([_rms(r[column]) for r in singles])
    got = np.array([r[name] for r in rows])
    assert all(r["status"] == "ok" for r in rows)
    scale = np.max(np.abs(expected))
    assert np.max(np.abs(got - expected)) <= 1e-10 * scale
    if "friction" not in name:  # no friction solution was computed for it
        assert all("motor.torque_friction_rms" not in r for r in rows)


NAMED = ["motor.torque_friction_peak", "O2.reaction_peak", "guide.v_peak"]


def _peak(x: np.ndarray) -> float:
    return float(np.max(np.abs(x[np.isfinite(x)])))


@pytest.mark.parametrize(
    "name, truth",
    [
        ("motor.torque_friction_approx_peak", lambda r: _peak(r["motor.torque_friction_approx"])),
        ("motor.efficiency_min", lambda r: float(np.nanmin(r["motor.efficiency"]))),
        (
            "O3.reaction_peak_friction",
            lambda r: _peak(np.hypot(r["O3.Fx_friction"], r["O3.Fy_friction"])),
        ),
        ("guide.reaction_peak", lambda r: _peak(np.hypot(r["guide.Fx"], r["guide.Fy"]))),
    ],
)
def test_a_population_row_of_another_group_is_its_single_run(template, singles, name, truth):
    """Quantities of the other groups a row reduces (the approximate friction solution, the
    efficiency, the reactions with and without friction), each alone in ``needs``: each
    design's value is that of its single analysis, reduced here from its columns, to
    1e-10 of their scale."""
    rows = analyze_variants(template, POPULATION, positions=POSITIONS, needs=[name])
    expected = np.array([truth(r) for r in singles])
    got = np.array([r[name] for r in rows])
    assert all(r["status"] == "ok" for r in rows)
    assert np.max(np.abs(got - expected)) <= 1e-10 * np.max(np.abs(expected))


def test_a_row_of_what_is_named_agrees_with_the_whole_row(template):
    """Leaving parts out changes none of the quantities left (1e-12 of each column's
    largest value); the strokes left out are empty, the located zones absent, and the
    groups of quantities no name has a word of (the shaking, the pressure angles) too."""
    whole = analyze_variants(template, POPULATION, positions=POSITIONS)
    named = analyze_variants(template, POPULATION, positions=POSITIONS, needs=NAMED)
    assert all("friction.self_locking" in r for r in whole)
    assert all("friction.self_locking" not in r for r in named)
    assert all(math.isnan(r["guide.stroke"]) for r in named)
    for gone in ("shaking.force_peak", "rod_ram.pressure_angle_max"):
        assert gone in whole[0] and all(gone not in r for r in named), gone
    compared = 0
    for key, value in whole[0].items():
        if not isinstance(value, float) or key.endswith((".stroke", ".time_ratio")):
            continue
        if key not in named[0]:
            assert key.startswith("shaking.") or key.endswith("angle_max"), key
            continue
        a = np.array([r[key] for r in whole])
        b = np.array([r[key] for r in named])
        scale = np.max(np.abs(a[np.isfinite(a)]), initial=0.0)
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * scale, err_msg=key)
        compared += 1
    assert compared > 20
    assert len(whole) == len(named) == len(POPULATION)


def test_every_quantity_left_out_is_brought_back_by_its_name(template):
    """A row of nothing named lacks (or leaves empty) some quantities of the whole row;
    each is one whose name ``row_needs`` flags, and naming them all gives them back."""
    whole = analyze_variants(template, POPULATION, positions=POSITIONS)
    bare = analyze_variants(template, POPULATION, positions=POSITIONS, needs=[])
    left = sorted(
        {
            k
            for w, b in zip(whole, bare)
            for k, v in w.items()
            if k not in b or (isinstance(v, float) and math.isnan(b[k]) and not math.isnan(v))
        }
    )
    assert {"motor.torque_friction_rms", "guide.stroke", "friction.self_locking"} <= set(left)
    for key in left:
        assert row_needs([key]) != RowNeeds(False, False, False), key
    again = analyze_variants(template, POPULATION, positions=POSITIONS, needs=left)
    for w, a in zip(whole, again):
        for key in left:
            if isinstance(w[key], str):
                assert a[key] == w[key], key
            else:
                assert a[key] == pytest.approx(w[key], rel=1e-12, abs=0, nan_ok=True), key


def test_a_misspelt_name_is_matched_against_the_whole_row(tmp_path):
    """'motor.torque_frictoin_rms' needs no friction by its words, yet the nearest name
    offered is the friction quantity of the whole row."""
    with pytest.raises(ks.KinetostaticsError, match="did you mean 'motor.torque_friction_rms'"):
        ks.optimize(
            SLOTTER,
            {"BC_ratio": (0.8, 1.2)},
            "motor.torque_frictoin_rms",
            popsize=2,
            maxiter=0,
            positions=12,
            polish=False,
            progress=False,
        )


def test_what_a_name_needs():
    assert row_needs(None) == RowNeeds(True, True, True)
    bare = row_needs(["shaking.force_rms", "x1"])
    assert (bare.friction, bare.strokes, bare.zones) == (False, False, False)
    assert bare.parts == {"shaking", "efforts"}  # 'force': on the safe side
    assert row_needs([]).parts == frozenset()
    assert row_needs(["O2.reaction_peak", "link.alpha_peak"]).parts == {"reactions", "outputs"}
    assert row_needs(["rod_ram.pressure_angle_max"]).parts == {"angles"}
    for name in variants.QUANTITIES:  # a group for every quantity a group computes
        assert name.startswith("flywheel.") or row_needs([name]).parts, name
    for name in (
        "motor.torque_friction_rms",
        "motor.torque_friction_approx_peak",
        "motor.efficiency_min",
        "O3.reaction_peak_friction",
        "friction.self_locking_positions",
    ):
        assert row_needs([name]).friction, name
    assert row_needs(["guide.time_ratio"]).strokes
    assert row_needs(["friction.self_locking"]).zones


SEARCH = dict(popsize=3, maxiter=2, positions=18, seed=1, local_maxiter=4, progress=False)


@pytest.mark.parametrize(
    "objective, constraints",
    [
        ("motor.torque_rms", ["guide.stroke >= 0.099"]),
        ("motor.torque_friction_peak", ["rod_ram.pressure_angle_max <= 12"]),
    ],
)
def test_the_search_is_the_one_that_computes_every_quantity(monkeypatch, objective, constraints):
    """The designs, their order, status and values, and the best design are those of the
    search whose rows hold every quantity (``row_needs`` made to say "all"); the best
    design's row is whole either way."""
    vary = {"BC_ratio": (0.7, 1.3), "L_O2O3": (120.0, 180.0)}
    pruned = ks.optimize(SLOTTER, vary, objective, constraints, **SEARCH)
    monkeypatch.setattr(variants, "row_needs", lambda names: RowNeeds())
    whole = ks.optimize(SLOTTER, vary, objective, constraints, **SEARCH)
    assert len(pruned.designs) == len(whole.designs)
    for a, b in zip(pruned.designs, whole.designs):
        assert [a[n] for n in vary] == [b[n] for n in vary]
        assert a["status"] == b["status"]
        assert a["objective"] == pytest.approx(b["objective"], rel=1e-12, abs=0, nan_ok=True)
    assert pruned.parameters == whole.parameters
    assert set(pruned.row) == set(whole.row)  # the best design's whole row
    assert "motor.torque_friction_rms" in pruned.row and "guide.stroke" in pruned.row
    assert pruned.alone == 0 and "one by one" not in pruned.message


def test_designs_analysed_one_by_one_are_counted_and_reported(monkeypatch):
    """A population the vectorised analysis cannot take (here: a flywheel to size) is
    analysed design by design; the result says how many."""
    vary = {"BC_ratio": (0.8, 1.2)}
    small = dict(popsize=3, maxiter=0, positions=12, polish=False, progress=False)
    calls = []
    rows = designs_module.analyze_chunk

    def counted(chunk):
        calls.append(len(chunk.overrides))
        return rows(chunk)

    monkeypatch.setattr(designs_module, "analyze_chunk", counted)
    best = ks.optimize(SLOTTER, vary, "flywheel.inertia", **small)
    population = calls[:-1]  # the last: the best design's whole row
    assert best.alone == sum(population) > 0
    assert f"{best.alone} designs analysed one by one" in best.message
