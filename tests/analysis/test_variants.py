"""Variants: parameter overrides, stacking, and the vectorised analysis of many
variants against the per-variant analysis (an independent code path: one
``analyze`` per variant) — rows equal to 1e-12 relative (a dimensionless value to
1e-12 of 1 at least: a cycle efficiency of a cycle without net work is a quotient
of round-off, and the two paths may invert the group blocks differently)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.batch.variants import ROW_UNITS, Template, analyze_variants, summary_row
from kinetostatics.errors import ModelError
from kinetostatics.model.stacking import TopologyMismatch, stack
from tests.helpers import MECHANISMS

MECH = Path(__file__).resolve().parents[2] / "mechanisms"


def _same(a: dict, b: dict, rtol: float = 1e-12) -> list[str]:
    """Keys whose values differ (numbers relative to the larger, a dimensionless one
    relative to 1 at least; NaN equals NaN)."""
    bad = [k for k in set(a) ^ set(b)]
    for k in set(a) & set(b):
        x, y = a[k], b[k]
        if isinstance(x, (float, int, np.floating)) and not isinstance(x, bool):
            floor = 1.0 if ROW_UNITS.get(k.rpartition(".")[2]) == "1" else 1e-300
            if (math.isnan(x) and math.isnan(y)) or abs(x - y) <= rtol * max(abs(x), abs(y), floor):
                continue
            bad.append(k)
        elif x != y:
            bad.append(k)
    return bad


def _perturbed(tpl: Template, rng, n: int, spread: float = 0.03) -> list[dict]:
    """n variants, each parameter scaled by a random factor within ±spread."""
    base = tpl.parameters
    return [{k: v * (1 + spread * rng.uniform(-1, 1)) for k, v in base.items()} for _ in range(n)]


def test_override_recomputes_the_parameters_that_depend_on_it():
    tpl = Template.load(MECH / "slotting_machine.yaml")
    m = tpl.model({"K": 1.5})
    theta = 180 * 0.5 / 2.5
    assert m.parameters["theta"] == pytest.approx(theta, rel=1e-15)
    assert m.parameters["L_O2A"] == pytest.approx(
        150 * math.sin(math.radians(theta / 2)), rel=1e-15
    )
    crank_pin = m.joint("A").p_i
    assert np.hypot(*crank_pin) == pytest.approx(m.parameters["L_O2A"] / 1e3, rel=1e-15)


def test_unknown_parameter_is_named_with_a_suggestion():
    tpl = Template.load(MECH / "slotting_machine.yaml")
    with pytest.raises(
        ModelError, match=r"parameters: a variant sets the parameter 'KK'.*did you mean 'K'"
    ):
        tpl.model({"KK": 2})


def test_a_variant_that_breaks_the_file_is_a_model_error_at_its_key():
    tpl = Template.load(MECH / "slotting_machine.yaml")
    with pytest.raises(ModelError, match=r"links\.bar\.weight: must be zero or positive"):
        tpl.model({"G3": -1})


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_a_variant_value_that_is_not_finite_is_named_at_its_parameter(value):
    tpl = Template.load(MECH / "slotting_machine.yaml")
    with pytest.raises(
        ModelError, match=r"slotting_machine.yaml:\d+:\d+: parameters\.K: number is not finite"
    ):
        tpl.model({"K": value})


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_a_kept_tree_builds_what_a_fresh_one_builds(path):
    """A template keeps its tree's entries, key locations and plain-number vectors from
    one variant's build to the next: each variant's model (or error) is the one a tree
    composed afresh builds, byte for byte, on every shipped mechanism."""
    import pickle

    from kinetostatics.base.document import compose, read_text
    from kinetostatics.outputs.loading import build

    def built(make, ov):
        try:
            return pickle.dumps(make(ov))
        except ModelError as exc:
            return str(exc)

    tpl = Template.load(path)
    fresh = lambda ov: build(compose(read_text(path), str(path)), ov or None)  # noqa: E731
    for ov in [{}, *_perturbed(tpl, np.random.default_rng(5), 3, spread=0.2)]:
        assert built(tpl.model, ov) == built(fresh, ov), ov


def test_variants_built_from_one_tree_in_threads_are_their_own():
    """A tree's entries are kept from one build to the next (Entry.rebuilt): builds from
    threads (a thread executor, Dask's workers) take turns, and each model and error is
    that of a build alone."""
    import pickle
    import sys
    from concurrent.futures import ThreadPoolExecutor

    tpl = Template.load(MECH / "slotting_machine.yaml")
    rng = np.random.default_rng(3)
    ovs = _perturbed(tpl, rng, 40, spread=0.3) + [{"G3": -1.0}, {"KK": 2.0}] * 5

    def built(ov):
        try:
            return pickle.dumps(tpl.model(ov))
        except ModelError as exc:
            return str(exc)

    alone = [built(ov) for ov in ovs]
    switch = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)  # threads change as often as they can
    try:
        with ThreadPoolExecutor(4) as ex:
            threaded = list(ex.map(built, ovs))
    finally:
        sys.setswitchinterval(switch)
    assert threaded == alone


def test_a_models_arrays_are_its_own(fixed_sketch):
    """Numbers written without names are read once per tree; each model still gets arrays
    of its own: one changed in place does not change the next variant's."""
    tpl = Template.load(fixed_sketch)
    a = tpl.model({"K": 2.1})
    a.gravity[:] = 0.0
    a.sketch["C"][:] = 0.0
    b = tpl.model({"K": 2.2})
    np.testing.assert_array_equal(b.gravity, [0.0, -10.0])
    np.testing.assert_array_equal(b.sketch["C"], [0.0933, 0.150])


def test_stack_keeps_equal_numbers_and_stacks_the_others():
    tpl = Template.load(MECH / "slotting_machine.yaml")
    a, b = tpl.model({"K": 1.6}), tpl.model({"K": 2.0})
    s = stack([a, b])
    assert s.joint("O2").p_i is a.joint("O2").p_i  # the frame pivot does not move
    assert s.joint("A").p_i.shape == (2, 1, 2)
    np.testing.assert_array_equal(s.joint("A").p_i[1, 0], b.joint("A").p_i)
    with pytest.raises(TopologyMismatch):
        stack([a, ks.load(MECH / "slider_crank.yaml")])


@pytest.mark.parametrize(
    "name",
    [
        "slider_crank",
        "slotting_machine",
        "watt_sixbar",
        "inverted_slider_crank",
        "stephenson_sixbar",
    ],
)
def test_vectorised_rows_equal_single_runs(name):
    tpl = Template.load(MECH / f"{name}.yaml")
    rng = np.random.default_rng(7)
    ovs = _perturbed(tpl, rng, 6)
    fast = analyze_variants(tpl, ovs, positions=36, flywheel=False)
    slow = analyze_variants(tpl, ovs, positions=36, flywheel=False, vectorise=False)
    for v, (a, b) in enumerate(zip(fast, slow)):
        assert not _same(a, b), (v, _same(a, b))


def test_a_fast_machines_time_ratio_is_its_single_runs():
    """The micrometre slider-crank at 20,000 rpm: its limit positions were refined until
    Newton's step was 1e-14 s, 3e-12 of a turn there, and a batch row's time ratio
    differed from its single run's by 1.1e-11. The tolerance is now of the time the crank
    takes to turn 1 rad: the rows agree to 1e-12 at any speed."""
    tpl = Template.load(Path(__file__).resolve().parents[1] / "hard" / "slider_crank_micro.yaml")
    ovs = _perturbed(tpl, np.random.default_rng(3), 5, spread=0.01)
    fast = analyze_variants(tpl, ovs, positions=36, flywheel=False)
    slow = analyze_variants(tpl, ovs, positions=36, flywheel=False, vectorise=False)
    for v, (a, b) in enumerate(zip(fast, slow)):
        assert not _same(a, b), (v, _same(a, b))


def _counting_single_runs(monkeypatch) -> list:
    """A list that gets an item for each variant analysed on its own (``pipeline.analyze``
    called by the batch: the vectorised path left it)."""
    from kinetostatics.analysis import pipeline

    calls: list = []
    real = pipeline.analyze  # where analyze_variants takes it from, at its call
    monkeypatch.setattr(pipeline, "analyze", lambda *a, **k: calls.append(1) or real(*a, **k))
    return calls


@pytest.mark.parametrize(
    ("name", "keys"),
    [
        ("stephenson_sixbar", None),  # a triad
        ("geared_fivebar", ("a1", "a2", "b1", "b2")),  # a link closed by a gear pair
        ("rack_rocker", ("a", "b", "l")),  # a link closed by a rack
        ("cam_flat_oscillating", ("l",)),  # a follower closed by its cam
    ],
)
def test_variants_without_closed_forms_are_stacked_and_equal_single_runs(monkeypatch, name, keys):
    """A mechanism with a group that has no closed form: its variants in one stacked
    analysis (the rows by Newton along the path), none on its own, each row that of its
    single run to 1e-12."""
    tpl = Template.load(MECH / f"{name}.yaml")
    rng = np.random.default_rng(11)
    base = tpl.parameters
    ovs = [{k: base[k] * (1 + 0.03 * rng.uniform(-1, 1)) for k in keys or base} for _ in range(5)]
    alone = _counting_single_runs(monkeypatch)
    fast = analyze_variants(tpl, ovs, positions=36, flywheel=False)
    assert not alone and all(r["status"] == "ok" for r in fast)
    slow = analyze_variants(tpl, ovs, positions=36, flywheel=False, vectorise=False)
    for v, (a, b) in enumerate(zip(fast, slow)):
        assert not _same(a, b), (v, _same(a, b))


@pytest.mark.parametrize(
    "name", ["slider_crank", "slotting_machine", "watt_sixbar", "inverted_slider_crank"]
)
def test_the_newton_path_gives_the_closed_forms_rows(monkeypatch, name):
    """The stacked rows by Newton along the path (the closed forms withheld) equal those by
    the closed forms to 1e-12, every variant stacked."""
    from kinetostatics.analysis import vectorised

    tpl = Template.load(MECH / f"{name}.yaml")
    ovs = _perturbed(tpl, np.random.default_rng(5), 4)
    closed = analyze_variants(tpl, ovs, positions=36, flywheel=False)
    alone = _counting_single_runs(monkeypatch)
    monkeypatch.setattr(vectorised, "closed_forms", lambda *a: None)
    newton = analyze_variants(tpl, ovs, positions=36, flywheel=False)
    assert not alone
    for v, (a, b) in enumerate(zip(newton, closed)):
        assert not _same(a, b), (v, _same(a, b))


def test_a_variant_whose_newton_path_passes_a_singular_position_is_analysed_alone(
    monkeypatch,
):
    """Four-bars by Newton along the path (the closed forms withheld): the one at the
    Grashof change point (1 + 3 = 2.5 + 1.5, its group singular at 180°) leaves the stacked
    analysis and is analysed alone, reporting the singular position as its single run
    does; the crank-rockers beside it stay stacked; one that cannot turn fully fails as
    alone.  Every row is its single run's."""
    from kinetostatics.analysis import vectorised

    text = (Path(__file__).resolve().parents[1] / "hard" / "fourbar_change_point.yaml").read_text()
    text = text.replace("links:\n", "parameters: {d: 3}\nlinks:\n", 1)
    text = text.replace("D: [3, 0]", "D: [d, 0]")
    tpl = Template.loads(text, "fourbars.yaml")
    ovs = [{"d": 2.9}, {"d": 3.0}, {"d": 2.95}, {"d": 3.1}, {"d": 2.92}]
    monkeypatch.setattr(vectorised, "closed_forms", lambda *a: None)
    alone = _counting_single_runs(monkeypatch)
    rows = analyze_variants(tpl, ovs, positions=36, flywheel=False)
    assert [r["status"] for r in rows] == ["ok", "ok", "ok", "failed", "ok"]
    assert len(alone) == 2  # the change point and the one that cannot turn fully
    slow = analyze_variants(tpl, ovs, positions=36, flywheel=False, vectorise=False)
    for v, (a, b) in enumerate(zip(rows, slow)):
        assert not _same(a, b), (v, _same(a, b))


def test_formulas_that_do_not_broadcast_stacked_numbers_leave_the_chunk_to_single_runs(
    monkeypatch,
):
    """A joint type whose formulas meet a stacked number with a Python ``if`` or ``math``
    call raises ``TypeError`` or ``ValueError`` in the stacked analysis: the chunk's
    variants are analysed one by one, with their own rows (docs/extending.md)."""
    from kinetostatics.analysis import vectorised

    tpl = Template.load(MECH / "slider_crank.yaml")
    ovs = _perturbed(tpl, np.random.default_rng(2), 3)
    want = analyze_variants(tpl, ovs, positions=24, vectorise=False)
    for error in (TypeError, ValueError):

        def refuse(*a, error=error, **k):
            raise error("only length-1 arrays can be converted to Python scalars")

        monkeypatch.setattr(vectorised, "analyze_stacked", refuse)
        alone = _counting_single_runs(monkeypatch)
        rows = analyze_variants(tpl, ovs, positions=24)
        assert len(alone) == 3
        for v, (a, b) in enumerate(zip(rows, want)):
            assert not _same(a, b), (error, v, _same(a, b))
        monkeypatch.undo()


def test_a_subset_of_stacked_variants_analyses_as_those_variants_stacked_afresh():
    """``subset`` takes variants out of a stacked model (a variant that leaves the path)
    without stacking again; a number that differs in all the variants but not in the
    subset stays stacked there: the rows are those of the subset stacked afresh, to the
    bit."""
    from kinetostatics.analysis import vectorised
    from kinetostatics.model.stacking import subset

    tpl = Template.load(MECH / "slotting_machine.yaml")
    ovs = [{"K": 1.8, "G3": 150.0}, {"K": 2.1}, {"K": 1.8, "H": 95.0}, {"G5": 300.0}]
    models = [tpl.model(ov, positions=24) for ov in ovs]
    members = [0, 2]
    taken = subset(stack(models), models, members)
    assert taken.parameters == models[0].parameters
    assert np.ndim(taken.joint("A").p_i) == 3  # K: equal in the members, still stacked

    def rows(stacked):
        st = vectorised.analyze_stacked([models[v] for v in members], stacked=stacked)
        strokes = vectorised.output_strokes(st)
        return summary_row(vectorised.as_result(st), flywheel=False, strokes=strokes)

    a, b = rows(taken), rows(None)
    assert a.keys() == b.keys()
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)


def test_vectorised_path_is_taken_for_the_slotting_machine(monkeypatch):
    """No variant is analysed on its own: the one-by-one path takes over silently when the
    vectorised one raises, so only this count shows that the vectorised one ran."""
    from kinetostatics.analysis import pipeline

    calls = []
    real = pipeline.analyze  # where analyze_variants takes it from, at its call
    monkeypatch.setattr(pipeline, "analyze", lambda *a, **k: calls.append(1) or real(*a, **k))
    tpl = Template.load(MECH / "slotting_machine.yaml")
    rows = analyze_variants(
        tpl, _perturbed(tpl, np.random.default_rng(1), 5), positions=24, flywheel=False
    )
    assert all(r["status"] == "ok" for r in rows) and not calls


def test_variants_off_the_path_leave_the_others_in_one_pass(monkeypatch, fixed_sketch):
    """A variant that assembles far from its sketch, at the start and where the sketch is,
    is taken out of the stacked analysis, which goes on with the others in the same pass;
    its row has the error its own analysis raises, without that analysis, and the others
    the rows of theirs."""
    from kinetostatics.analysis import pipeline, vectorised

    tpl = Template.load(fixed_sketch)
    far = {"K": 2.261, "H": 81.026, "L_O2O3": 135.699, "BC_ratio": 0.909}  # C ~54 mm off
    variants = [{}, far, {"K": 1.9}, {"H": 95.0}]
    passes, alone = [], []
    real_stacked, real_one = vectorised.analyze_stacked, pipeline.analyze
    monkeypatch.setattr(
        vectorised, "analyze_stacked", lambda m, **k: passes.append(len(m)) or real_stacked(m, **k)
    )
    monkeypatch.setattr(pipeline, "analyze", lambda *a, **k: alone.append(1) or real_one(*a, **k))
    rows = analyze_variants(tpl, variants, positions=24, flywheel=False)
    assert passes == [4] and not alone
    with pytest.raises(ModelError) as own:
        ks.analyze(tpl.model(far, positions=24))
    assert rows[1] == {"status": "failed", "reason": str(own.value).splitlines()[0]} | {
        "full_cycle": False
    }
    assert "C is assembled 5" in rows[1]["reason"]  # ~54 mm
    for v in (0, 2, 3):
        one = summary_row(ks.analyze(tpl.model(variants[v], positions=24)), flywheel=False)
        for k, x in one.items():
            if isinstance(x, float) and math.isfinite(x):
                assert rows[v][k] == pytest.approx(x, rel=1e-11, abs=1e-11), (v, k)


def test_a_variant_started_away_from_its_sketch_is_carried_there_alone(monkeypatch):
    """The analysis starts at 180°; a variant whose sketch is of the crank at 0° assembles
    far from it there, assembles where the sketch is, and is analysed alone (carried along
    its branch to the start) as a single run does; the others, sketched at 180°, in one
    pass."""
    from kinetostatics.analysis import pipeline

    text = (MECH / "slider_crank.yaml").read_text()
    text = text.replace("analysis: {start: 0,", "analysis: {start: 180,")
    text = text.replace(
        "  r2: 120", "  r2: 120\n  s: -1  # the sketched crank: 1 at 0°, -1 at 180°"
    )
    text = text.replace("A: [a, 0]\n  B: [a + b - 10, e]", "A: [s*a, 0]\n  B: [s*a + b - 10, e]")
    tpl = Template.loads(text, "started.yaml")
    alone = []
    real = pipeline.analyze
    monkeypatch.setattr(pipeline, "analyze", lambda *a, **k: alone.append(1) or real(*a, **k))
    ovs = [{"b": 340.0}, {"s": 1.0}, {"a": 95.0}]
    rows = analyze_variants(tpl, ovs, positions=24)
    assert len(alone) == 1 and all(r["status"] == "ok" for r in rows)
    monkeypatch.setattr(pipeline, "analyze", real)
    for ov, row in zip(ovs, rows):
        assert not _same(row, summary_row(ks.analyze(tpl.model(ov, positions=24))))


def test_stacked_group_conditions_are_each_variants_own():
    """The condition number of a group over stacked variants (L_ref ``(V, 1)``) against
    each variant's system alone, at the same positions."""
    from kinetostatics.kinematics.newton import group_condition
    from kinetostatics.structure.system import build_system

    tpl = Template.load(MECH / "slotting_machine.yaml")
    models = [tpl.model({}, positions=12), tpl.model({"K": 1.8, "H": 90.0}, positions=12)]
    results = [ks.analyze(m, kinematics_only=True) for m in models]
    stacked = build_system(stack(models))
    q = np.stack([r.q for r in results])
    for plan in stacked.plans[1:]:
        got = group_condition(stacked, q, plan)
        for v, m in enumerate(models):
            own = build_system(m)
            want = group_condition(own, results[v].q, own.plans[stacked.plans.index(plan)])
            np.testing.assert_allclose(got[v], want, rtol=1e-12)


def test_a_variant_that_cannot_assemble_is_a_row_with_its_reason():
    tpl = Template.load(MECH / "slider_crank.yaml")
    ovs = [{"b": 350}, {"b": 60}, {"b": 400}]  # a rod shorter than the crank (a = 100)
    rows = analyze_variants(tpl, ovs, positions=36)
    assert [r["status"] for r in rows] == ["ok", "failed", "ok"]
    assert "RRP dyad" in rows[1]["reason"] and "cannot reach" in rows[1]["reason"]
    single = analyze_variants(tpl, [ovs[2]], positions=36)[0]
    assert not _same(rows[2], single)


def test_row_matches_the_independent_slider_crank_closed_form():
    from tests.oracles import slider_crank_closed_form as oracle

    tpl = Template.load(MECH / "slider_crank.yaml")
    rows = analyze_variants(
        tpl, [{"a": 90.0, "b": 300.0}, {"a": 110.0, "b": 420.0}], positions=72, friction=False
    )
    for (a, b), row in zip(((0.09, 0.3), (0.11, 0.42)), rows):
        e = tpl.base.parameters["e"] / 1e3
        stroke = math.sqrt((a + b) ** 2 - e**2) - math.sqrt((b - a) ** 2 - e**2)
        slide = next(k for k in row if k.endswith(".stroke"))
        assert row[slide] == pytest.approx(stroke, rel=1e-12)
    assert oracle is not None


def _scalable(doc: dict) -> str:
    """A generated mechanism with a parameter ``s`` (1) scaling every link's points and
    centre of mass and every sketched position (similar linkages: every length differs
    between variants, the branch is the same), 24 positions, no event rows."""
    import copy

    import yaml

    d = copy.deepcopy(doc)
    d["parameters"] = {**d.get("parameters", {}), "s": 1.0}
    scaled = lambda p: [f"{float(c)!r} * s" for c in p]  # noqa: E731
    for link in d["links"].values():
        link["points"] = {k: scaled(p) for k, p in link["points"].items()}
        if isinstance(link.get("com"), list):
            link["com"] = scaled(link["com"])
    d["sketch"] = {k: scaled(p) for k, p in d.get("sketch", {}).items()}
    d["analysis"] = {**d.get("analysis", {}), "positions": 24, "events": False}
    d["analysis"].pop("at", None)
    return yaml.safe_dump(d)


def _scaled_generated_rows(monkeypatch, seeds) -> int:
    """Batch rows of the net's generated mechanisms, each as five similar variants, against
    their single runs (1e-12); the number of mechanisms whose stacked rows came by Newton
    along the path (a group without a closed form)."""
    from kinetostatics.analysis import vectorised
    from tests.net import generate as gen

    calls: list = []
    real = vectorised.newton_path
    monkeypatch.setattr(vectorised, "newton_path", lambda *a: calls.append(1) or real(*a))
    used = 0
    for seed in seeds:
        try:
            tpl = Template.loads(_scalable(gen.generate(seed)), f"generated {seed}.yaml")
        except ModelError:
            continue
        ovs = [{"s": f} for f in (1.0, 0.97, 1.03, 0.99, 1.02)]
        calls.clear()
        fast = analyze_variants(tpl, ovs, flywheel=False)
        slow = analyze_variants(tpl, ovs, flywheel=False, vectorise=False)
        for v, (a, b) in enumerate(zip(fast, slow)):
            assert not _same(a, b), (seed, v, _same(a, b))
        used += bool(calls)
    return used


def test_scaled_generated_mechanisms_by_newton_stacked_are_their_single_runs(monkeypatch):
    """Two of the net's generated mechanisms with a group that has no closed form."""
    assert _scaled_generated_rows(monkeypatch, (1016, 1041)) == 2


@pytest.mark.slow
def test_scaled_generated_mechanisms_stacked_are_their_single_runs(monkeypatch):
    """130 of the net's generated mechanisms (~3 min), ≥ 5 of them by Newton along the path."""
    assert _scaled_generated_rows(monkeypatch, range(1000, 1130)) >= 5
