"""The kinematic plan (kinematics/plan.py) against the general derivative stage.

The plan is the same stage written once per system as straight-line code: every column
of an analysis made with it equals the general path's to 1e-12 of the column's scale
(the largest |value| among the columns of its unit), on every shipped file that a
motion drives, the hard cases and generated mechanisms of the net, and over more than
STACK_UP_TO positions; rows it does not cover (a leading axis on one model's rows;
more than STACK_UP_TO positions of a stack without whole-array kernels) take the general
path.  Stacked variants' plans: tests/kinematics/test_plan_stacked.py."""

import glob
import re
import warnings
from collections import defaultdict

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.kinematics import plan, plan_inverse
from kinetostatics.kinematics.derivatives import derivatives
from kinetostatics.kinematics.plan import (
    covers,
    kinematic_plan,
    planned_derivatives,
    planned_phi,
)
from kinetostatics.kinematics.plan_solve import TRACED_FROM
from kinetostatics.structure.evaluation import STACK_UP_TO
from kinetostatics.structure.system import build_system, phi
from tests.net import generate as gen

SHIPPED_BLOCKS = plan.PLANNED_BLOCKS


@pytest.fixture(autouse=True)
def _plans_at_once(monkeypatch):
    """The plans generated on a system's first analysis (not after PLAN_AFTER rows), and
    for every system, a triad's too (PLANNED_BLOCKS lifted): the plan's lines must equal
    the general path wherever they would run."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (0, 0))
    monkeypatch.setattr(plan, "PLANNED_BLOCKS", 10**9)


def test_a_system_with_a_triad_keeps_the_general_stage(monkeypatch):
    """A group of more than two links (the Stephenson six-bar's triad, 12 columns) has a
    dense inverse: the plan is not made for it (PLANNED_BLOCKS), its rates are the general
    stage's; a system of dyads is planned."""
    monkeypatch.setattr(plan, "PLANNED_BLOCKS", SHIPPED_BLOCKS)
    triad = ks.analyze(ks.load("mechanisms/stephenson_sixbar.yaml"), friction=False)
    assert max(len(p.cols) for p in triad.system.plans) == 12
    assert not covers(triad.system, triad.q) and "kinematic plan" not in triad.system.memo
    dyads = ks.analyze(ks.load("mechanisms/watt_sixbar.yaml"), friction=False)
    assert covers(dyads.system, dyads.q) and "kinematic plan" in dyads.system.memo


FILES = sorted(glob.glob("mechanisms/*.yaml") + glob.glob("tests/hard/*.yaml"))
NET_CASES = sorted(glob.glob("tests/net/cases/*.yaml"))  # the net's kept cases (slow)


def _analyse(model, enabled: bool, **kw):
    old = plan.ENABLED
    plan.ENABLED = enabled
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ks.analyze(model, **kw)
    finally:
        plan.ENABLED = old


def _worst(a, b) -> float:
    """Largest |Δ| of the columns over the largest |value| of their unit's columns."""
    assert list(a.columns) == list(b.columns)
    scale = defaultdict(float)
    for name in a.columns:
        x = np.asarray(a[name], dtype=float)
        if x.size and np.isfinite(x).any():
            scale[a.units[name]] = max(scale[a.units[name]], float(np.nanmax(np.abs(x))))
    worst = 0.0
    for name in a.columns:
        x, y = np.asarray(a[name], dtype=float), np.asarray(b[name], dtype=float)
        assert x.shape == y.shape, name
        assert np.array_equal(np.isfinite(x), np.isfinite(y)), name
        ok = np.isfinite(x)
        if ok.any():
            d = float(np.max(np.abs(x[ok] - y[ok])))
            worst = max(worst, d / max(scale[a.units[name]], 1e-300))
    return worst


def _compare(model, **kw) -> float:
    try:
        general = _analyse(model, False, **kw)
    except ks.KinetostaticsError:  # a hard case that refuses before any rate is made
        return 0.0
    general.system.memo.pop("kinematic plan", None)
    planned = _analyse(model, True, **kw)
    assert "kinematic plan" in planned.system.memo  # the plan made the rows' rates
    return _worst(general, planned)


def _motion_driven(model) -> bool:
    return all(d.effort is None for d in model.drivers)


@pytest.mark.parametrize("path", FILES)
def test_plan_equals_general_path_on_files(path):
    model = ks.load(path)
    if not _motion_driven(model):
        pytest.skip("effort-driven: analyze does not take it")
    assert _compare(model, friction=False) <= 1e-12


@pytest.mark.slow
def test_plan_equals_general_path_on_the_nets_cases():
    """The net's 25 kept cases (tests/net/cases; ~8 s)."""
    for path in NET_CASES:
        model = ks.load(path)
        if _motion_driven(model):
            assert _compare(model, friction=False) <= 1e-12, path


def _generated(seeds) -> int:
    worst, used = 0.0, 0
    for seed in seeds:
        model = gen.load(gen.generate(seed))
        if not _motion_driven(model):
            continue
        worst = max(worst, _compare(model, friction=False))
        used += 1
    assert worst <= 1e-12
    return used


def test_plan_equals_general_path_on_a_few_generated_mechanisms():
    assert _generated(range(1000, 1002)) >= 1


@pytest.mark.slow
def test_plan_equals_general_path_on_generated_mechanisms():
    """≥ 50 of the net's generated mechanisms (tests/net/generate.py; ~30 s: generating
    them is the cost)."""
    assert _generated(range(1000, 1060)) >= 50


def test_rates_equal_general_stage_at_random_states():
    """q̇, q̈ and the factors against ``derivatives`` at poses off the path (random ψ̇, ψ̈)."""
    model = ks.load("mechanisms/slotting_machine.yaml")
    r = _analyse(model, False, kinematics_only=True)
    system, rng = r.system, np.random.default_rng(7)
    q = r.q[::7] + 1e-3 * rng.standard_normal(r.q[::7].shape)
    psi_d, psi_dd = rng.standard_normal((2, len(q), 1))
    qd, qdd, lu = derivatives(system, q, psi_d, psi_dd)
    pqd, pqdd, plu = planned_derivatives(system, q, psi_d, psi_dd)
    for a, b in ((qd, pqd), (qdd, pqdd)):
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(a))
    for a, b in zip(lu.inv, plu.inv):
        assert np.allclose(a, b, rtol=0, atol=1e-12 * np.max(np.abs(a)))


def test_rows_it_does_not_cover_take_the_general_path():
    model = ks.load("mechanisms/slider_crank.yaml")
    system = build_system(model)
    q = ks.analyze(system, kinematics_only=True).q
    assert covers(system, q)
    stacked = q[None]  # variants along a leading axis
    ones = np.ones(q.shape[:-1] + (1,))
    assert planned_derivatives(system, stacked, ones[None], ones[None]) is None


@pytest.mark.parametrize(
    ("name", "n"),
    [
        ("slider_crank", STACK_UP_TO + 10),
        ("slotting_machine", STACK_UP_TO + 10),
        ("cam_roller", STACK_UP_TO + 10),
        ("slotting_machine", 3 * 8192 + 7),  # in chunks (CHUNK_BYTES), each its own blocks
    ],
)
def test_a_long_run_is_planned_and_equals_the_general_path(name, n):
    """Over more than STACK_UP_TO positions the plan still covers the rows (its stacks
    run their kernels joint by joint, as the general path does there), and over more
    than a chunk it runs them chunk by chunk: every column of the general path's analysis
    to 1e-12 of its scale."""
    model = ks.load(f"mechanisms/{name}.yaml")
    angles = model.analysis.start + np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    general = _analyse(model, False, positions=angles, friction=False)
    general.system.memo.pop("kinematic plan", None)
    planned = _analyse(model, True, positions=angles, friction=False)
    assert covers(planned.system, planned.q) and "kinematic plan" in planned.system.memo
    assert _worst(general, planned) <= 1e-12


class _CountingNumpy:
    """NumPy for a plan's text, counting its ``einsum`` calls (the products over blocks)."""

    def __init__(self):
        self.products = 0

    def __getattr__(self, name):
        return getattr(np, name)

    def einsum(self, *a, **k):
        self.products += 1
        return np.einsum(*a, **k)


@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine", "stephenson_sixbar"])
def test_long_chunks_solve_by_lines_over_the_blocks_nonzero_entries(name, monkeypatch):
    """A chunk of TRACED_FROM rows or more solves q̇ and q̈ by lines written over the
    inverses' and coupling blocks' entries that are not zero (no product over whole
    blocks), and a run of that many rows the reactions' Φ_qᵀ y = r so (the friction's
    right-hand sides together, in runs of positions), unless a block was inverted again
    (a fallback's inverse has no known zeros: then the products); every way gives the
    general path's columns, reactions, torque and friction included."""
    model = ks.load(f"mechanisms/{name}.yaml")
    for n in (TRACED_FROM - 1, TRACED_FROM, 3 * TRACED_FROM):
        angles = model.analysis.start + np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        general = _analyse(model, False, positions=angles, friction=False)
        general.system.memo.pop("kinematic plan", None)
        planned = _analyse(model, True, positions=angles, friction=False)
        assert _worst(general, planned) <= 1e-12
    full = _analyse(model, False, positions=angles)  # the friction's n_f solves, in runs
    full.system.memo.pop("kinematic plan", None)
    assert _worst(full, _analyse(model, True, positions=angles)) <= 1e-12
    counting, factors = _CountingNumpy(), []
    monkeypatch.setattr(plan, "np", counting)  # the plans written from here on count
    monkeypatch.setitem(plan_inverse._SCOPE, "np", counting)
    made = plan.BlockFactor
    monkeypatch.setattr(
        plan, "BlockFactor", lambda *a, **k: factors.append(made(*a, **k)) or factors[-1]
    )
    real = plan_inverse.again_where_not_finite
    for forced in (False, True):
        if forced:  # every block "inverted again" (the same numbers)
            stub = lambda *a: real(*a) if real(*a) is not None else np.ones(len(a[0]), bool)  # noqa: E731
            monkeypatch.setitem(plan_inverse._SCOPE, "again_where_not_finite", stub)
        model = ks.load(f"mechanisms/{name}.yaml")  # a new system: a new plan
        for _ in range(2):  # made once 5,000 rows were analysed (PLAN_AFTER)
            counting.products = 0
            got = _analyse(model, True, positions=angles, friction=False)
        assert "kinematic plan" in got.system.memo and _worst(general, got) <= 1e-12
        assert (counting.products > 0) == forced, counting.products
        assert (factors[-1].transposed is None) == forced


class _UnzeroedNumpy:
    """NumPy for the plan's module whose ``empty`` arrays are NaN (or zeros: ``fill``)."""

    def __init__(self, fill: float):
        self.fill, self.made = fill, 0

    def __getattr__(self, name):
        return getattr(np, name)

    def empty(self, shape, *a, **k):
        self.made += 1
        return np.full(shape, self.fill)


@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine", "stephenson_sixbar"])
def test_the_written_product_is_the_blocks_product(name, monkeypatch):
    """Φ_qᵀ y by the plan's lines over Φ_q's entries that are not zero (what the friction
    solutions' residual reads, kinematics/plan_solve.py) equals the products over the
    whole blocks, to 1e-12 of its scale, on a run of TRACED_FROM rows and more — the
    blocks read whole after the run, their unwritten entries (made NaN here) zeroed
    first (kinematics/plan_buffers.py, ``BlockFactor``'s ``ready``)."""
    model = ks.load(f"mechanisms/{name}.yaml")
    n = 3 * TRACED_FROM
    angles = model.analysis.start + np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    r = _analyse(model, True, positions=angles, kinematics_only=True)
    monkeypatch.setattr(plan, "np", _UnzeroedNumpy(np.nan))
    _, _, lu = planned_derivatives(r.system, r.q, np.ones((n, 1)), np.zeros((n, 1)))
    assert lu.product is not None
    y = np.random.default_rng(5).standard_normal((r.system.n_rows, n))
    written = lu.product(y)
    lu.product = None  # the products over the whole blocks
    dense = lu.product_transposed_components(y)
    assert np.max(np.abs(written - dense)) <= 1e-12 * np.max(np.abs(dense))


@pytest.mark.parametrize("path", FILES)
def test_unwritten_entries_are_zeroed_before_they_are_read(path, monkeypatch):
    """Where the plan writes every entry its lines read, Φ_q's buffer and the inverses are
    not zeroed (kinematics/plan_buffers.py): filled with NaN instead of left as memory
    was, an analysis in chunks long and short — the written lines, the products over
    whole blocks, the fallbacks of a hard case, the shaking force's ground block, the
    friction solutions — gives every column of the buffers made of zeros (the blocks read
    whole after the run: ``test_the_written_product_is_the_blocks_product``)."""
    monkeypatch.setattr(plan, "CHUNK_BYTES", 1)  # chunks of 1,024 rows at most
    text = open(path).read()
    for n in (3 * TRACED_FROM, 2 * TRACED_FROM + 3):  # chunks of TRACED_FROM, and shorter
        changed, count = re.subn(r"positions: *\d+", f"positions: {n}", text)
        model = ks.loads(changed, path)
        if not _motion_driven(model) or not count:
            pytest.skip("effort-driven, or no analysis.positions to set")
        # (the self-locked rows of a hard case are solved one by one: ~5 s at 3,072 rows)
        kw = {"friction": False} if "self_locking" in path else {}
        got = []
        for fill in (0.0, np.nan):
            numpy = _UnzeroedNumpy(fill)
            monkeypatch.setattr(plan, "np", numpy)
            try:
                got.append(_analyse(model, True, **kw))
            except ks.KinetostaticsError:  # a hard case that refuses before any rate is made
                return
        unwritten = got[-1].system.memo["kinematic plan"].unwritten
        for name in ("slider_crank", "slotting_machine", "stephenson_sixbar"):
            assert unwritten is not None or name not in path  # the pairs' plans: not zeroed
        assert _worst(got[0], got[1]) <= 1e-12 and numpy.made


def test_a_stack_without_whole_array_kernels_keeps_long_runs_general(monkeypatch):
    """A joint type that stacks but whose kernels do not run over whole arrays would be
    called as one stack by the plan: over STACK_UP_TO positions the general path takes it
    (one joint at a time)."""
    from kinetostatics.joints import Revolute

    monkeypatch.setattr(Revolute, "whole_array_kernels", False)
    system = build_system(ks.load("mechanisms/slider_crank.yaml"))
    q = ks.analyze(system, kinematics_only=True).q
    long = np.repeat(q, STACK_UP_TO // len(q) + 1, axis=0)
    assert covers(system, q) and not covers(system, long)
    assert not kinematic_plan(system).long_runs
    r = ks.analyze(system, positions=np.linspace(0, 2 * np.pi, STACK_UP_TO + 10), friction=False)
    assert np.isfinite(r["motor.torque"]).all()


def test_plan_is_readable_source_kept_with_the_system():
    system = build_system(ks.load("mechanisms/slider_crank.yaml"))
    p = kinematic_plan(system)
    assert p is kinematic_plan(system)  # generated once
    head = "def run(pe, psi_d, psi_dd, buf, qdT, qddT, INV, CND, Z=NOZERO):\n"
    inverses, run = p.source.split(head)
    assert inverses.startswith("def INVERSE0(view, out, buf")  # the blocks' written inverses
    # every set traced, the motor's row too (its joint's direction and bias kernels)
    assert ".jacobian(" not in run and ".acceleration_rhs(" not in run
    assert "psi_dd[:, 0]" in run
    assert len(run.splitlines()) < 20 * (len(system.sets) + len(system.plans)) + 20
    cam = build_system(ks.load("mechanisms/cam_roller.yaml"))  # a cam: through its contract
    assert ".jacobian(" in kinematic_plan(cam).source


@pytest.mark.parametrize(
    "name, numbers_alone", [("slider_crank", False), ("slotting_machine", True)]
)
def test_a_driven_crank_block_is_inverted_without_arithmetic(name, numbers_alone):
    """The crank's block holds its hinge's ±1, the motor's row (0, 0, 1) — numbers when the
    plan is written — and its pin's lever arms: the written inverse copies the arms (−(−x)
    is x) and computes nothing; a crank pinned at its origin (the slotting machine's) has
    an inverse of numbers alone, without a check at each call."""
    body = kinematic_plan(build_system(ks.load(f"mechanisms/{name}.yaml"))).source
    body = body.split("def INVERSE0(")[1].split("\ndef ")[0]
    assert not [line for line in body.splitlines() if re.match(r"\s+v\d+ = .*[-+*/]", line)]
    assert ("redo.append" not in body) == numbers_alone


@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine", "shaper"])
def test_plan_traces_the_pairs_formulas_at_any_number_of_positions(name):
    """The revolute and prismatic pairs' Φ_q and γ, and a motion driver's row on either,
    are their kernels' operations written into the plan (base/trace.py), no call per joint
    or per stack: at 1 to 200 positions the analysis equals the general path's (a slide's
    driver: ``test_plan_equals_general_path_on_files``, the slider-driven hard case)."""
    model = ks.load(f"mechanisms/{name}.yaml")
    start = model.analysis.start
    for n in (1, 2, 10, 63, 64, 200):
        positions = start + np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        assert _compare(model, positions=positions, friction=False) <= 1e-12
    source = kinematic_plan(build_system(model)).source
    assert "PE[" in source and "vr[" in source and "kernel" not in source
    assert ".jacobian(" not in source and ".acceleration_rhs(" not in source  # drivers too


def _random_rows(system, rng, n=40):
    """Coordinates and driver coordinates off the path (Φ ≠ 0: the formulas hold anywhere)."""
    q = rng.uniform(-2.0, 2.0, (n, system.n_q))
    return q, rng.uniform(-3.0, 3.0, (n, len(system.motion_drivers)))


@pytest.mark.parametrize("path", FILES)
def test_planned_residuals_equal_phi(path):
    """Φ by the residual plan (the pairs' residual kernels traced, the other sets by the
    contract) equals ``phi`` at random rows of every shipped file and hard case, and at
    more than STACK_UP_TO rows; stacked variants (3-D rows) go to ``phi`` itself."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = build_system(ks.load(path))
    rng = np.random.default_rng(5)
    for n in (1, 40, STACK_UP_TO + 7):
        q, psi = _random_rows(system, rng, n)
        want = phi(system, q, psi)
        got = planned_phi(system, q, psi)
        assert got.shape == want.shape
        assert np.max(np.abs(got - want), initial=0.0) <= 1e-12 * max(1.0, np.max(np.abs(want)))
    q3, psi3 = q[None, :5], psi[None, :5]
    assert np.array_equal(planned_phi(system, q3, psi3), phi(system, q3, psi3))


def test_planned_residuals_on_generated_mechanisms():
    rng = np.random.default_rng(11)
    for seed in range(1000, 1010):
        system = build_system(gen.load(gen.generate(seed)))
        q, psi = _random_rows(system, rng)
        want = phi(system, q, psi)
        assert np.max(np.abs(planned_phi(system, q, psi) - want)) <= 1e-12 * np.max(np.abs(want))


def test_plans_are_generated_once_worth_it(monkeypatch):
    """A system analysed once over a few hundred rows keeps the general path (generating
    costs more than one analysis saves); after PLAN_AFTER analyses or rows the plans are
    made and used, and the numbers stay the general path's."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (50, 1000))
    system = build_system(ks.load("mechanisms/slotting_machine.yaml"))
    first = ks.analyze(system, friction=False)
    assert "kinematic plan" not in system.memo and "residual plan" not in system.memo
    for _ in range(3):
        again = ks.analyze(system, friction=False)
    assert "kinematic plan" in system.memo and "residual plan" in system.memo
    assert _worst(first, again) <= 1e-12
    long = ks.analyze(build_system(system.model), positions=np.linspace(0, 6.0, 1500))
    assert "kinematic plan" in long.system.memo  # one long run is worth it at once


def test_plans_are_generated_at_a_systems_eighth_short_analysis(monkeypatch):
    monkeypatch.setattr(plan, "PLAN_AFTER", (8, 5000))
    system = build_system(ks.load("mechanisms/slider_crank.yaml"))
    for _ in range(8):
        assert "kinematic plan" not in system.memo
        ks.analyze(system, positions=np.radians([10.0, 20.0, 30.0]), friction=False)
    assert "kinematic plan" in system.memo


def test_short_analyses_and_rows_add_up_to_a_plan(monkeypatch):
    """What earlier analyses would have saved counts with a long one's rows: after five
    short analyses a run of 1,000 rows keeps the general path (6/8 + 1,015/5,000 = 0.95),
    one of 2,000 more makes the plan (7/8 + 3,015/5,000 = 1.48), though neither the calls
    nor the rows reach theirs alone."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (8, 5000))
    system = build_system(ks.load("mechanisms/slider_crank.yaml"))
    for _ in range(5):
        ks.analyze(system, positions=np.radians([10.0, 20.0, 30.0]), friction=False)
    ks.analyze(system, positions=np.linspace(0, 6.0, 1000), friction=False)
    assert "kinematic plan" not in system.memo
    ks.analyze(system, positions=np.linspace(0, 6.0, 2000), friction=False)
    assert "kinematic plan" in system.memo


def test_a_first_run_longer_than_a_stack_waits_for_its_rows(monkeypatch):
    """Over more than STACK_UP_TO rows the plan is asked whether it takes them; that
    question no longer makes it: a first run of 2,000 rows keeps the general path (fewer
    than PLAN_AFTER's 5,000), a run of 6,000 takes the plan at once."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (8, 5000))
    model = ks.load("mechanisms/slider_crank.yaml")
    short = ks.analyze(build_system(model), positions=np.linspace(0, 6.0, 2000), friction=False)
    assert "kinematic plan" not in short.system.memo
    long = ks.analyze(build_system(model), positions=np.linspace(0, 6.0, 6000), friction=False)
    assert "kinematic plan" in long.system.memo
