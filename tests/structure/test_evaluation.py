"""The system's evaluation plan (structure/evaluation.py) against the constraints evaluated
one by one: Φ, γ and the group blocks of Φ_q equal to the bit, on every shipped mechanism,
on stacked design variants, and with the blocks where Φ_q has them.

The truth is each constraint's own method, called alone on its two links' poses, and the
whole Φ_q assembled entry by entry (``jacobian``)."""

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.batch.variants import Template
from kinetostatics.model.stacking import stack
from kinetostatics.structure import evaluation
from kinetostatics.structure import system as S
from tests.helpers import MECHANISMS, ROOT

RNG = np.random.default_rng(5)


def _state(system, lead):
    q = RNG.normal(size=lead + (system.n_q,)) * np.tile([0.3, 0.3, 3.0], len(system.links))
    qd = RNG.normal(size=lead + (system.n_q,))
    psi = RNG.normal(size=lead + (len(system.motion_drivers),))
    return q, qd, psi


def _gamma_one_by_one(system, q, qd, psi_dd):
    """γ with each constraint's own ``acceleration_rhs`` called alone on its two links."""
    pe, n_j, out = S.link_poses(system, q), len(system.model.joints), []
    for k, c in enumerate(system.constraints):
        i, j = system.ends[k]
        args = (pe[..., i, :], pe[..., j, :], *S.link_pair(system, qd, k))
        out.append(
            c.acceleration_rhs(*args, psi_dd[..., k - n_j])
            if k >= n_j
            else c.acceleration_rhs(*args)
        )
    return np.concatenate(out, axis=-1)


def _blocks_one_by_one(system, q):
    """The group blocks gathered from Φ_q built one constraint at a time (``jacobian``
    with a selection), coupling blocks over all the earlier columns."""
    out, done = [], np.zeros(0, dtype=int)
    for p in system.plans:
        blk = S.jacobian(system, q, p.constraints, np.concatenate((done, p.cols)))
        rows = np.arange(len(p.rows))[:, None]
        lower = blk[..., rows, np.arange(done.size)] if done.size else None
        out.append((blk[..., rows, np.arange(done.size, blk.shape[-1])], lower, done))
        done = np.concatenate((done, p.cols))
    return out


def _same_blocks(got, want):
    """The plan's blocks against the reference's: the same diagonal blocks, and coupling
    blocks over the columns the group touches that equal the reference's (taken over all
    the earlier columns) there, with nothing but zeros in the others."""
    for (d, lo, cols), (d0, lo0, done) in zip(got, want, strict=True):
        np.testing.assert_array_equal(d, d0)
        if lo0 is None:
            assert lo is None and cols.size == 0
            continue
        at = np.isin(done, cols)
        np.testing.assert_array_equal(done[at], cols)  # in solve order
        if lo is None:
            assert not at.any()
        else:
            np.testing.assert_array_equal(lo, lo0[..., at])
        assert not np.any(lo0[..., ~at]), "an entry outside the coupling block"


def _check(system, lead):
    q, qd, psi = _state(system, lead)
    every = range(len(system.constraints))
    np.testing.assert_array_equal(S.phi(system, q, psi), S.phi(system, q, psi, every))
    np.testing.assert_array_equal(
        S.gamma(system, q, qd, psi), _gamma_one_by_one(system, q, qd, psi)
    )
    blocks = S.jacobian_blocks(system, q)
    _same_blocks(blocks, _blocks_one_by_one(system, q))
    jac = S.jacobian(system, q, ground=True)  # entry by entry, the ground's columns last
    for p, (d, lo, cols) in zip(system.plans, blocks):
        np.testing.assert_array_equal(d, jac[..., p.rows[:, None], p.cols])
        if lo is not None:
            np.testing.assert_array_equal(lo, jac[..., p.rows[:, None], cols])
    # the ground's block kept from that evaluation: every joint jointed to the ground, its
    # rows × the ground's columns (the shaking force's map)
    ground = len(system.links)
    rows, kept = S.ground_jacobian(system, q)
    touching = [k for k in range(len(system.model.joints)) if ground in system.ends[k]]
    want = [r for k in touching for r in range(system.row_start[k], system.row_start[k + 1])]
    np.testing.assert_array_equal(rows, want)
    if rows.size:
        np.testing.assert_array_equal(kept, np.take(jac, rows, axis=-2)[..., -3:])
        system.memo.clear()  # not kept: evaluated, the same numbers
        np.testing.assert_array_equal(S.ground_jacobian(system, q)[1], kept)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
@pytest.mark.parametrize("lead", [(), (7,), (2, 5)])
def test_the_plan_gives_each_constraints_own_numbers(path, lead):
    system = S.build_system(ks.load(path))
    assert sum(len(s.members) for s in system.sets) == len(system.constraints)
    _check(system, lead)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_stacks_split_over_many_positions_give_the_same_numbers(path, monkeypatch):
    """Over more than STACK_UP_TO positions a stack's joints are evaluated one by one
    (the same blocks and rows, to the bit)."""
    monkeypatch.setattr(evaluation, "STACK_UP_TO", 3)
    system = S.build_system(ks.load(path))
    pe = S.link_poses(system, _state(system, (7,))[0])
    split = [m for _, m, *_ in evaluation._units(system.sets, pe) if m is not None]
    assert len(split) == sum(len(s.members) for s in system.sets if s.stacked)
    _check(system, (7,))
    _check(system, (2, 5))


@pytest.mark.parametrize("name", ["slotting_machine", "watt_sixbar", "shaper"])
def test_the_plan_on_stacked_variants(name):
    """Design variants stacked on a leading axis (joints' points ``(V, 1, 2)``)."""
    tpl = Template.load(ROOT / "mechanisms" / f"{name}.yaml")
    scale = {k: v * 1.02 for k, v in tpl.parameters.items() if isinstance(v, float)}
    model = stack([tpl.model({}), tpl.model(scale)])
    system = S.build_system(model)
    assert any(s.stacked for s in system.sets)
    _check(system, (2, 6))


def test_one_joint_type_in_one_call():
    """The slotting machine's five revolutes and two slides are two calls, its driver one."""
    system = S.build_system(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    kinds = sorted((type(s.constraint).__name__, len(s.members)) for s in system.sets)
    assert kinds == [("DriverConstraint", 1), ("Prismatic", 2), ("Revolute", 5)]


def test_coupling_blocks_grow_with_the_joints_not_with_the_links_before():
    """In a chain of RRR dyads each dyad is jointed to one earlier link: its coupling
    block spans that link's three columns, so the blocks' storage grows linearly with
    the chain (all earlier columns would make it quadratic), and the chain's
    velocities still satisfy Φ_q q̇ = ν entry by entry."""
    from tests.chains import dyad_chain

    sizes = {}
    for n in (10, 40):
        system = S.build_system(ks.loads(dyad_chain(n)))
        widths = [len(c) for c in system.layout.lower_cols]
        assert max(widths) <= 6, widths  # the four-bar's rocker pin: two links at most
        sizes[n] = system.layout.size
    assert sizes[40] / sizes[10] < 4.5  # 4× the dyads (quadratic: ~16×)
    r = ks.analyze(ks.loads(dyad_chain(40, positions=12)))
    system = r.system
    jac = S.jacobian(system, r.q)
    nu = S.nu(system, np.ones((len(r.q), 1)) * system.model.drivers[0].motion.speed)
    np.testing.assert_allclose(
        np.einsum("...ij,...j->...i", jac, r.qd), nu, atol=1e-9 * np.abs(nu).max()
    )


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_condition_numbers_in_chunks_are_those_of_one_pass(path, monkeypatch):
    """Over more than COND_CHUNK positions the groups' condition numbers are computed a
    chunk at a time: the same numbers, to the bit, as in one pass."""
    from kinetostatics.base.linalg import small_inverse
    from kinetostatics.kinematics import newton

    system = S.build_system(ks.load(path))
    q = _state(system, (29,))[0]
    blocks = S.jacobian_blocks(system, q)
    for plan, (d, _, _) in zip(system.plans, blocks):
        if d.shape[-1] != d.shape[-2]:  # an overconstrained group: no inverse, no number
            continue
        inv = small_inverse(d)
        whole = newton.condition_number(system, plan, d, inv)
        monkeypatch.setattr(newton, "COND_CHUNK", 8)  # four passes of 7 or 8
        np.testing.assert_array_equal(newton.condition_number(system, plan, d, inv), whole)
        monkeypatch.setattr(newton, "COND_CHUNK", 10**9)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_condition_numbers_are_the_scaled_blocks_frobenius_norms(path):
    """A group's condition number is ‖S‖_F ‖S⁻¹‖_F of its block S = D_r J D_c (lengths over
    L_ref, each row divided by its largest |entry|), here formed position by position as
    dense matrices and measured by NumPy's Frobenius norm: the same to 1e-13."""
    from kinetostatics.base.linalg import small_inverse
    from kinetostatics.kinematics import newton

    system = S.build_system(ks.load(path))
    q = _state(system, (29,))[0]
    for plan, (d, _, _) in zip(system.plans, S.jacobian_blocks(system, q)):
        if d.shape[-1] != d.shape[-2]:
            continue
        got = newton.condition_number(system, plan, d, small_inverse(d))
        col = np.where(np.arange(len(plan.cols)) % 3 == 2, 1.0, system.l_ref)
        for k in range(len(q)):
            scaled = d[k] * col
            scaled = scaled / np.max(np.abs(scaled), axis=1, keepdims=True)
            want = np.linalg.norm(scaled, "fro") * np.linalg.norm(np.linalg.inv(scaled), "fro")
            assert got[k] == pytest.approx(want, rel=1e-13)


@pytest.mark.parametrize("path", MECHANISMS)
def test_a_joint_coordinate_s_rate_is_its_derivative_along_the_rates(path):
    """``coordinate_rate`` (the power balance's, the efficiency's and the lever method's
    relative speeds) at random states off the path is the central difference of the
    joint's coordinate along the rates, (c(q + h x) − c(q − h x)) / 2h, and its gradient's
    product with them, for every joint of every shipped file (revolute, prismatic, gear
    and cam pairs)."""
    from kinetostatics.kinematics.state import joint_coordinate

    system = S.system_of(ks.load(path))
    q, x, _ = _state(system, (7,))
    h = 1e-6
    for k, joint in enumerate(system.model.joints):
        rate = S.coordinate_rate(system, q, x, k)
        ahead, back = (joint_coordinate(system, q + s * h * x, k) for s in (1.0, -1.0))
        step = ahead - back
        if joint.angular:  # an angle's difference taken to (−π, π]
            step = (step + np.pi) % (2 * np.pi) - np.pi
        scale = max(float(np.max(np.abs(rate))), 1.0)
        assert np.max(np.abs(step / (2 * h) - rate)) <= 1e-6 * scale, joint.name
        product = np.einsum("...n,...n->...", S.coordinate_gradient(system, q, k), x)
        assert np.max(np.abs(product - rate)) <= 1e-12 * scale, joint.name
