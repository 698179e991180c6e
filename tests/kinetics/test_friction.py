"""Friction: the consistent solution against the approximate one, self-locking,
and the zero-speed rule."""

import re
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from tests.helpers import assert_close_on_unit_scales, variant


def _scaled(s: float, **extra) -> ks.Model:
    return variant(
        "slider_crank",
        r1=(r"radius: 1.5", f"radius: {1.5 * s}"),
        r2=(r"radius: 1.2", f"radius: {1.2 * s}"),
        r3=(r"radius: 1.0", f"radius: {1.0 * s}"),
        f=(r"coefficient: 0.10", f"coefficient: {0.1 * s}"),
        **extra,
    )


def test_consistent_converges_quadratically_to_approximate():
    """The approximation neglects friction-on-friction terms: error = O(μ²)."""
    errs = []
    for s in (1.0, 0.1, 0.01):
        r = ks.analyze(_scaled(s))
        ok = r["friction.status"] < 2
        errs.append(
            np.max(np.abs(r["motor.torque_friction"] - r["motor.torque_friction_approx"])[ok])
        )
    ratios = [errs[0] / errs[1], errs[1] / errs[2]]
    for ratio in ratios:
        assert 50 < ratio < 200, ratios  # ≈ 100 for a tenfold smaller friction


def test_homotopy_on_the_kinematic_factors():
    """The motor's own effort (A = Φ_qᵀ, handed to the friction solutions as the block
    factors, never assembled dense): at 60 times the friction the fixed point fails at
    some rows, the homotopy takes them, and others self-lock; where a solution is
    reported it is an equilibrium with its own friction (the power balance closes)."""
    r = ks.analyze(_scaled(60.0))
    st = r["friction.status"]
    assert (st == 0).sum() >= 10 and (st == 1).sum() >= 10 and (st == 2).sum() >= 10
    ok = st < 2
    scale = np.max(np.abs(r["power.input"]))
    assert np.max(np.abs(r["power.residual_friction"][ok])) < 1e-9 * scale


LOCKING = "tests/hard/slider_crank_self_locking.yaml"


def _locking(s: float) -> ks.Model:
    """Crank motion prescribed, effort balanced at the slide; short rod, large friction
    (tests/hard/slider_crank_self_locking.yaml, its friction level ``s: 3`` times ``s``)."""
    text, n = re.subn(r"\n  s: 3 ", f"\n  s: {3.0 * s:g} ", open(LOCKING).read())
    assert n == 1
    return ks.loads(text, file="slider_crank_self_locking.yaml")


@pytest.fixture(scope="module")
def locking():
    return ks.analyze(_locking(1.0))


def test_self_locking_ranges_and_homotopy(locking):
    st = locking["friction.status"]
    assert (st == 2).sum() >= 5 and (st == 1).sum() >= 1 and (st == 0).sum() > 200
    # self-locked rows have no friction values; the frictionless force exists
    assert np.isnan(locking["motor.force_friction"][st == 2]).all()
    assert np.isfinite(locking["motor.force"]).all()
    # where a solution is reported (fixed point or homotopy) it is an equilibrium
    # with its own friction: the power balance closes
    ok = st < 2
    scale = np.max(np.abs(locking["power.input"]))
    assert np.max(np.abs(locking["power.residual_friction"][ok])) < 1e-9 * scale


def test_a_cycling_newton_gives_up_early_with_the_same_solutions(locking, monkeypatch):
    """A homotopy step's Newton that is still cycling at its 12th iteration gives up there
    (kinetics/homotopy.py, CYCLING) instead of at its 30th: the self-locking case
    gets every column and status it gets when each Newton runs its 30 (the Newtons that
    converge do so long before), in fewer iterations."""
    from kinetostatics.kinetics import homotopy

    monkeypatch.setattr(homotopy, "CYCLING", (homotopy.NEWTON + 1, np.inf))
    patient = ks.analyze(_locking(1.0))
    status = locking["friction.status"]
    fixed_point = (status == 0) | (status == 3)  # the rows the homotopy did not take
    assert (status == 1).sum() >= 1 and (status == 2).sum() >= 1
    np.testing.assert_array_equal(status, patient["friction.status"])
    assert_close_on_unit_scales(locking, patient, skip=("friction.iterations",))
    fast, slow = locking["friction.iterations"], patient["friction.iterations"]
    assert (fast <= slow).all() and (fast < slow).any()
    np.testing.assert_array_equal(fast[fixed_point], slow[fixed_point])


def _followed_alone(monkeypatch) -> None:
    """The homotopy's positions followed one at a time (kinetics/homotopy.py's ``follow``
    called once per position), as a reference for its positions followed at once."""
    from kinetostatics.kinetics import friction as fr
    from kinetostatics.kinetics import homotopy

    def alone(a, q_load, x0, friction, jacobian):
        def one(p):
            at = np.array([p])
            f = lambda rows, y, s: friction(rows + p, y, s)  # noqa: E731
            j = lambda rows, y, s: jacobian(rows + p, y, s)  # noqa: E731
            return homotopy.follow(a[at], q_load[at], x0[at], f, j)

        return tuple(np.concatenate(z) for z in zip(*(one(p) for p in range(len(x0)))))

    monkeypatch.setattr(fr, "follow", alone)


def _as_alone(at_once, alone, what: str = "") -> None:
    """The same statuses, every column within 1e-12 of its unit's scale, and the same
    Newton iterations at ≥ 95 % of the rows the homotopy took: the positions' paths are
    their own (one step shared by all of them gives the same solutions to ~1e-13 but
    other iterations at every such row)."""
    st = at_once["friction.status"]
    np.testing.assert_array_equal(st, alone["friction.status"], err_msg=what)
    assert_close_on_unit_scales(at_once, alone, skip=("friction.iterations",))
    took = (st == 1) | (st == 2)
    same = at_once["friction.iterations"][took] == alone["friction.iterations"][took]
    assert same.sum() >= 0.95 * same.size, (what, int((~same).sum()), int(took.sum()))


def test_the_homotopy_follows_each_position_as_it_would_alone(locking, monkeypatch):
    """The positions the fixed point leaves are followed all at once (kinetics/homotopy.py),
    each with its own σ, steps and chart: each gets what it gets followed alone
    (:func:`_as_alone`; on this machine every column to the bit)."""
    _followed_alone(monkeypatch)
    one_by_one = ks.analyze(_locking(1.0))
    assert (locking["friction.status"] == 1).sum() >= 1
    _as_alone(locking, one_by_one)


@pytest.mark.slow
def test_the_homotopy_at_once_is_the_homotopy_alone_on_generated_mechanisms(monkeypatch):
    """The same on the net's generated mechanisms with 30 times their friction (~20 s),
    with enough rows taken by the homotopy."""
    from tests.net import generate as gen

    def texts():
        for seed in range(1000, 1040):
            text = gen.to_text(gen.generate(seed))
            more = lambda m: f"coefficient: {30 * float(m.group(1)):g}"  # noqa: E731
            text, n = re.subn(r"coefficient: *([0-9.eE+-]+)", more, text)
            if n:
                yield seed, text

    at_once = {}
    for seed, text in texts():
        try:
            at_once[seed] = ks.analyze(ks.loads(text, f"seed{seed}.yaml"))
        except ks.KinetostaticsError:  # refused as generated (a hard case of the net's)
            continue
    _followed_alone(monkeypatch)
    taken = 0
    for seed, text in texts():
        if seed not in at_once:
            continue
        a, b = at_once[seed], ks.analyze(ks.loads(text, f"seed{seed}.yaml"))
        taken += int((a["friction.status"] == 1).sum())
        _as_alone(a, b, f"seed {seed}")
    assert len(at_once) >= 8 and taken >= 30


def test_the_zones_edges_searched_side_by_side_are_those_found_alone(locking, monkeypatch):
    """The edges of the locked zones are searched side by side (analysis/locking.py: one
    analysis a round for all of them); each is where its search alone puts it (1e-9°:
    a state continued from a row with others beside it may take another Newton step)."""
    from kinetostatics.analysis import locking as lk

    together = lk.locking_zones(locking)
    assert len(together) >= 2 and all(z["from"] is not None for z in together)
    search = lk._locking_edges
    monkeypatch.setattr(
        lk, "_locking_edges", lambda r, s, b, span: [search(r, s, [x], span)[0] for x in b]
    )
    alone = lk.locking_zones(locking)
    for a, b in zip(together, alone):
        assert a["rows"] == b["rows"]
        assert a["from"] == pytest.approx(b["from"], abs=1e-9)
        assert a["to"] == pytest.approx(b["to"], abs=1e-9)


def test_self_locking_range_shrinks_with_friction(locking):
    counts = [int((ks.analyze(_locking(s))["friction.status"] == 2).sum()) for s in (0.5, 0.1)]
    assert (locking["friction.status"] == 2).sum() > counts[0] > counts[1]


def test_self_locking_rows_are_empty_in_csv(locking, tmp_path):
    locking.to_csv(tmp_path / "r.csv")
    lines = (tmp_path / "r.csv").read_text().splitlines()
    header = lines[1].split(",")
    k = header.index("motor.force_friction")
    row = int(np.nonzero(locking["friction.status"] == 2)[0][0])
    assert lines[2 + row].split(",")[k] == ""


def test_zero_relative_speed_gives_status_3_and_no_friction_there():
    model = ks.load("mechanisms/slider_crank.yaml")
    r0 = ks.analyze(model)
    dead = [e.coordinate for e in r0.events]  # slider at rest
    r = ks.analyze(model, positions=dead)
    assert list(r["friction.status"]) == [3, 3]
    np.testing.assert_array_equal(r["slide.friction"], 0.0)
    np.testing.assert_array_equal(r["slide.friction_approx"], 0.0)
    assert np.all(r["O.friction"] != 0)


@pytest.mark.parametrize(
    "path", ["mechanisms/slotting_machine.yaml", "tests/hard/slider_crank_self_locking.yaml"]
)
def test_the_shared_solves_give_each_solution_as_its_own_solve(monkeypatch, path):
    """The approximate solution by the consistent one's n_f solves A⁻¹(−g_k) (x₀ + Σ
    e_k(x₀) A⁻¹(−g_k)) equals the one solve of its definition, A x = −Q − Σ g_k e_k(x₀),
    to 1e-12 of its scale; the consistent solution that starts from it equals the one
    computed alone (no approximate solution before it: a fresh setup), with the same
    status and iterations; the solves are not kept in the result."""
    from kinetostatics.kinetics import friction as fr
    from kinetostatics.kinetics import inverse

    calls = []
    real = inverse.friction_solutions

    def spy(system, motion, q_loads, eq, ref_speed):
        out = real(system, motion, q_loads, eq, ref_speed)
        calls.append((system, motion, q_loads, eq, ref_speed, out))
        return out

    monkeypatch.setattr(inverse, "friction_solutions", spy)
    ks.analyze(ks.load(path))
    system, motion, q_loads, eq, ref_speed, got = calls[0]
    assert not got.setup.shared  # the result keeps the setup, not the solves
    fs = fr.setup(system, motion.q, motion.qd, ref_speed)
    xa, ea = fr.approximate(system, fs, eq.solve, q_loads.total, eq.x0)  # its own solve
    scale = np.nanmax(np.abs(xa))
    assert np.nanmax(np.abs(got.x_approx - xa)) <= 1e-12 * scale
    assert np.array_equal(np.isnan(got.x_approx), np.isnan(xa))
    assert np.array_equal(got.e_approx, ea, equal_nan=True)
    a = eq.lu if eq.a_given is None else eq.a_given  # as friction_solutions hands it
    alone = fr.consistent(system, fs, a, eq.solve, q_loads.total, eq.x0)
    assert "first" not in fs.shared  # computed from x₀, not from an approximate solution
    sol = got.solution
    assert np.array_equal(sol.status, alone.status)
    assert np.array_equal(sol.iterations, alone.iterations)
    assert np.nanmax(np.abs(sol.x - alone.x)) <= 1e-12 * np.nanmax(np.abs(alone.x))


@pytest.mark.parametrize("positions", [[0.7], [0.7, 1.9]])
def test_the_two_solutions_own_their_reactions(positions, monkeypatch):
    """The approximate and the consistent reactions are arrays of their own, also where the
    fixed point stops at its first iterate, which is the approximate solution (friction
    too small to move the reactions), at one position (where a component-major view of
    it is itself contiguous): the consistent solution writes NaN into its rows without a
    friction solution, which must not reach the approximate one."""
    from kinetostatics.kinetics import inverse

    text = Path("mechanisms/slider_crank.yaml").read_text(encoding="utf-8")
    text = re.sub(r"(radius|coefficient): [0-9.]+", r"\1: 1e-20", text)
    calls = []
    real = inverse.friction_solutions
    monkeypatch.setattr(
        inverse, "friction_solutions", lambda *a: calls.append(real(*a)) or calls[-1]
    )
    ks.analyze(ks.loads(text), positions=np.radians(positions))
    got = calls[0]
    assert np.all(got.solution.iterations == 1)  # the first iterate: the approximate one
    assert not np.shares_memory(got.x_approx, got.solution.x)


@pytest.mark.parametrize(
    "path",
    [
        f"mechanisms/{m}.yaml"
        for m in ("slider_crank", "slotting_machine", "rack_rocker", "cam_roller")
    ],
)
def test_the_efforts_are_each_joint_s_own_law(path, monkeypatch):
    """The efforts, e_k = −s_k·σ·μ_k(λ_k), as ``efforts`` gives them (on NumPy from the fixed
    point's −e_k over the reactions stored component-major, each joint's rows gathered
    whole, a type's joints in one stack) and as the fixed point reads them
    (``_minus_efforts``), against each joint's own friction law called alone on its rows
    and its links' poses: over one model's rows, at σ = 1 and σ = 0.3 (the homotopy's),
    at one position (the homotopy's), and over stacked variants' ``(V, N)`` rows."""
    from kinetostatics.kinetics import friction as fr
    from kinetostatics.kinetics import inverse
    from kinetostatics.structure.system import link_pair

    calls = []
    real = inverse.friction_solutions
    monkeypatch.setattr(
        inverse, "friction_solutions", lambda *a: calls.append((a, real(*a))) or calls[-1][1]
    )
    ks.analyze(ks.load(path))
    (system, motion, _, eq, ref_speed), got = calls[0]

    def own(fs, x, sigma):  # each joint alone, by its contract
        cols = []
        for n, k in enumerate(fs.joints):
            joint = system.model.joints[k]
            mu = joint.friction_magnitude(x[..., system.rows_of(k)], *link_pair(system, fs.q, k))
            cols.append(-fs.sign[..., n] * sigma * mu)
        return np.stack(cols, axis=-1)

    def check(fs, x, sigma=1.0):
        want = own(fs, x, sigma)
        tol = 1e-14 * max(np.nanmax(np.abs(want)), 1e-300)
        np.testing.assert_allclose(fr.efforts(system, fs, x, sigma), want, rtol=0, atol=tol)
        if sigma == 1.0:
            out = np.full((len(fs.joints),) + x.shape[:-1], np.nan)
            minus = fr._minus_efforts(system, fs, np.ascontiguousarray(np.moveaxis(x, -1, 0)), out)
            np.testing.assert_allclose(-np.moveaxis(minus, 0, -1), want, rtol=0, atol=tol)

    for x in (got.solution.x, eq.x0):
        got.setup.shared.clear()
        check(got.setup, x)
        check(got.setup, x, 0.3)
    at = len(motion.q) // 3  # one position, as the homotopy follows it
    fs = got.setup
    one = fr.FrictionSetup(
        fs.joints, fs.blocks, fs.grad[at], fs.sign[at], fs.speed[at], fs.zero[at], fs.q[at]
    )
    check(one, eq.x0[at], 0.3)
    # two rows of positions as two variants would lay them out, (V, N, ...)
    half = len(motion.q) // 2
    q, qd = (a[: 2 * half].reshape(2, half, -1) for a in (motion.q, motion.qd))
    check(fr.setup(system, q, qd, ref_speed), eq.x0[: 2 * half].reshape(2, half, -1))


@pytest.mark.parametrize(
    "path, stacked",
    [
        ("mechanisms/slotting_machine.yaml", False),
        ("mechanisms/slotting_machine.yaml", True),
        ("tests/hard/slider_crank_self_locking.yaml", False),
    ],
    ids=["one model", "stacked variants", "self-locking zones"],
)
@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_the_fixed_point_in_runs_of_positions_is_the_fixed_point_over_all(
    path, stacked, backend, monkeypatch, request
):
    """A position's iterates do not depend on the other positions', so the fixed point run
    over runs of a few positions (``FIXED_POINT_RUN``, here 7: the last run shorter, the
    approximate solution's first iterate sliced with them) gives the reactions, efforts,
    statuses and iterations of one run over all of them, on one model, on variants
    stacked along a leading axis, and where positions leave the fixed point for the
    homotopy (self-locked, zero relative speed) — on each backend (the compiled fixed
    point runs by runs too)."""
    from kinetostatics.analysis import vectorised
    from kinetostatics.base import kernels
    from kinetostatics.kinetics import friction as fr

    if backend == "numba":
        pytest.importorskip("numba")
        kernels.set_backend("numba")
        request.addfinalizer(lambda: kernels.set_backend("numpy"))

    if stacked:
        models = [ks.load(path, parameters={"H": 90.0 + 5.0 * k}) for k in range(3)]

        def run():
            return vectorised.as_result(vectorised.analyze_stacked(models))
    else:
        model = ks.load(path)

        def run():
            return ks.analyze(model)

    whole = run()
    monkeypatch.setattr(fr, "FIXED_POINT_RUN", 7)
    runs = run()
    for name in whole.columns:
        a, b = np.asarray(whole[name], dtype=float), np.asarray(runs[name], dtype=float)
        scale = max(np.nanmax(np.abs(a), initial=0.0), 1e-300)
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        assert np.nanmax(np.abs(a - b), initial=0.0) <= 1e-14 * scale, name
    for name in ("friction.status", "friction.iterations"):
        assert np.array_equal(whole[name], runs[name]), name
