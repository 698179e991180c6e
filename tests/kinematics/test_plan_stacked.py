"""The kinematic plan of stacked variants (kinematics/plan.py) against the general stage.

A stacked model (model/stacking.py) carries the parameters that differ between its
variants on a leading axis.  Its plan reads the parameters alike in every variant as
numbers, as one model's plan does, and the others from a table, one value per variant:
q̇, q̈, the blocks' inverses and every column of the stacked analysis equal the general
path's to 1e-12 of their scale, and a population with other values but the same
pattern of parameters (a search's next generation) runs the same compiled source with
its own table and constraints; the same on generated mechanisms scaled into variants."""

import warnings
from collections import defaultdict

import numpy as np
import pytest

from kinetostatics.analysis import vectorised
from kinetostatics.batch.variants import Template
from kinetostatics.errors import KinetostaticsError
from kinetostatics.kinematics import plan
from kinetostatics.kinematics.derivatives import derivatives
from kinetostatics.model.stacking import stack
from kinetostatics.structure.system import build_system

VARIED = {  # a few lengths of each file, ±1 % about the file's value
    "slotting_machine": ("BC_ratio", "L_O2O3", "H"),
    "slider_crank": None,
    "shaper": None,
    "watt_sixbar": None,
    "inverted_slider_crank": None,
}


def _models(name: str, seed: int, n: int = 6):
    template = Template.load(f"mechanisms/{name}.yaml")
    names = VARIED[name] or [k for k, v in template.parameters.items() if v][:4]
    rng = np.random.default_rng(seed)
    return [
        template.model({k: template.parameters[k] * rng.uniform(0.99, 1.01) for k in names})
        for _ in range(n)
    ]


def _stacked(models, enabled: bool):
    old = plan.ENABLED
    plan.ENABLED = enabled
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return vectorised.analyze_stacked(models, stacked=stack(models))
    finally:
        plan.ENABLED = old


def _worst(a, b) -> float:
    """Largest |Δ| of the stacked results' columns over the largest |value| of their
    unit's columns, and of q̇ and q̈ over theirs."""
    ra, rb = vectorised.as_result(a), vectorised.as_result(b)
    scale, worst = defaultdict(float), 0.0
    for c in ra.columns:
        x = np.asarray(ra[c], dtype=float)
        if np.isfinite(x).any():
            scale[ra.units[c]] = max(scale[ra.units[c]], float(np.nanmax(np.abs(x))))
    for c in ra.columns:
        x, y = np.asarray(ra[c], dtype=float), np.asarray(rb[c], dtype=float)
        assert np.array_equal(np.isfinite(x), np.isfinite(y)), c
        if np.isfinite(x).any() and scale[ra.units[c]] > 0 and not c.endswith("residual"):
            worst = max(worst, float(np.nanmax(np.abs(x - y))) / scale[ra.units[c]])
    for x, y in ((a.qd, b.qd), (a.qdd, b.qdd)):
        worst = max(worst, float(np.max(np.abs(x - y)) / np.max(np.abs(x))))
    return worst


@pytest.fixture(autouse=True)
def _plans_at_once(monkeypatch):
    """The plans made at once, and for every system, a triad's too (PLANNED_BLOCKS)."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (0, 0))
    monkeypatch.setattr(plan, "PLANNED_BLOCKS", 10**9)


@pytest.mark.parametrize("name", sorted(VARIED))
def test_stacked_plan_equals_the_general_path(name):
    models = _models(name, 1)
    general, planned = _stacked(models, False), _stacked(models, True)
    kept = planned.system.memo["kinematic plan"]
    assert kept.table is not None and kept.table.shape[1] == len(planned.members)
    assert "kinematic plan" not in general.system.memo
    assert _worst(general, planned) <= 1e-12


def test_the_parameters_alike_in_every_variant_are_numbers_of_the_source():
    """Only the parameters that differ are read from the table: varying BC_ratio moves
    the rod's far point alone (one coordinate per variant)."""
    template = Template.load("mechanisms/slotting_machine.yaml")
    models = [template.model({"BC_ratio": r}) for r in (0.9, 1.0, 1.1)]
    kept = _stacked(models, True).system.memo["kinematic plan"]
    lengths = [next(k for k in m.links if k.name == "rod").points["C"][0] for m in models]
    assert kept.table.shape == (1, 3) and np.array_equal(kept.table[0], lengths)
    assert kept.source.count("PA[") == 1


def test_a_new_population_runs_the_same_source_with_its_own_numbers():
    """Two populations of one pattern: one compiled source, each its own table and
    constraints, each equal to the general path (a stale table or constraint would
    give the first population's numbers)."""
    first, second = _models("slotting_machine", 2), _models("slotting_machine", 3)
    a = _stacked(first, True)
    b = _stacked(second, True)
    pa, pb = a.system.memo["kinematic plan"], b.system.memo["kinematic plan"]
    assert pa.source is pb.source and not np.array_equal(pa.table, pb.table)
    assert _worst(_stacked(second, False), b) <= 1e-12


def test_rates_of_stacked_variants_at_random_states():
    """q̇, q̈ and the inverses against ``derivatives`` off the path (random ψ̇, ψ̈), at
    one row per variant as the refinement of a travel extreme asks."""
    models = _models("slotting_machine", 4)
    system = build_system(stack(models))
    q = _stacked(models, False).q
    rng = np.random.default_rng(5)
    for rows in (q[:, :1], q[:, ::9]):
        psi_d, psi_dd = rng.standard_normal((2,) + rows.shape[:-1] + (1,))
        qd, qdd, lu = derivatives(system, rows, psi_d, psi_dd)
        pqd, pqdd, plu = plan.planned_derivatives(system, rows, psi_d, psi_dd)
        for x, y in ((qd, pqd), (qdd, pqdd), *zip(lu.inv, plu.inv)):
            assert x.shape == y.shape
            assert np.max(np.abs(x - y)) <= 1e-12 * np.max(np.abs(x))


def test_a_model_with_tables_is_one_model():
    """A model's own tables have more than one axis, as stacked values do: its rows
    ``(N, n_q)`` still take the one-model plan, and rows with a leading axis do not."""
    import kinetostatics as ks
    from kinetostatics.model.stacking import is_stacked

    model = ks.load("tests/net/cases/table_corner_turns_effort.yaml")
    assert is_stacked(model)
    system = build_system(model)
    q = np.zeros((4, system.n_q))
    one = build_system(_models("slider_crank", 6)[0])
    assert plan.covers(system, q)
    assert not plan.covers(one, np.zeros((2, 4, one.n_q)))


def _scaled(doc: dict, s: float) -> dict:
    """The mechanism ``doc`` scaled by ``s``: every link's points and centre of mass and
    every sketched position (a similar linkage: the same branch, other lengths)."""
    import copy

    d = copy.deepcopy(doc)
    for link in d["links"].values():
        link["points"] = {k: [s * float(c) for c in p] for k, p in link["points"].items()}
        if isinstance(link.get("com"), list):
            link["com"] = [s * float(c) for c in link["com"]]
    d["sketch"] = {k: [s * float(c) for c in p] for k, p in d.get("sketch", {}).items()}
    return d


def _generated_stacked(seeds) -> int:
    """Stacked plan against the general path on the net's generated mechanisms, each as
    three similar variants (scaled 1, 0.97, 1.03: every length differs between them),
    where the vectorised analysis takes them; the number compared."""
    from tests.net import generate as gen

    used = 0
    for seed in seeds:
        doc = gen.generate(seed)
        try:
            models = [gen.load(_scaled(doc, s)) for s in (1.0, 0.97, 1.03)]
            general = _stacked(models, False)
        except (vectorised.Unsupported, ValueError, KinetostaticsError):
            continue  # outside the vectorised case (a cam, two drivers…): not stacked
        planned = _stacked(models, True)
        assert list(planned.members) == list(general.members), seed
        assert planned.system.memo["kinematic plan"].table is not None, seed
        assert _worst(general, planned) <= 1e-12, seed
        used += 1
    return used


def test_stacked_plan_equals_the_general_path_on_a_few_generated_mechanisms():
    assert _generated_stacked(range(1000, 1004)) >= 1


@pytest.mark.slow
def test_stacked_plan_equals_the_general_path_on_generated_mechanisms():
    """≥ 12 of the net's generated mechanisms, scaled into stacked variants (~1 min; most
    are outside the vectorised case: a driver's length scales too, a cam, no closed form)."""
    assert _generated_stacked(range(1000, 1100)) >= 12
