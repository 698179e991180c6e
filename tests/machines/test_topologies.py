"""Topologies beyond the shipped examples, checked against independent truths.

For each mechanism file: the structure (mobility, Assur groups) asserted
exactly; closed loops from the named-point columns; velocities and
accelerations against finite differences of the positions; Φ_q q̇ = ν; the
power balance recomputed here from the link columns with the masses, loads
and friction data written out below (not read back from the loader); the
friction laws themselves; and the ``check`` command.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.structure.system import jacobian, nu

ROOT = Path(__file__).resolve().parents[2]
MECH = ROOT / "mechanisms"
GRID = np.radians(np.arange(0.0, 360.0, 0.25))  # driver coordinates, rad
G = np.array([0.0, -9.81])
L_REF = 0.5  # m, the size of every mechanism here


@dataclass(frozen=True)
class Case:
    file: str
    labels: list[str]
    speed: float  # crank speed, rad/s (signed)
    crank: str
    mass: dict[str, tuple[float, float]]  # link -> (kg, kg·m²)
    torques: dict[str, float] = field(default_factory=dict)  # link -> N·m
    forces: dict[str, tuple[str, tuple[float, float]]] = field(default_factory=dict)
    revolutes: dict[str, tuple[str, str, float]] = field(
        default_factory=dict
    )  # joint -> (i, j, ρ m)
    # prismatic joint -> (axis link i, axis points, slider link j, its point, f, bearing length m)
    prismatics: dict[str, tuple] = field(default_factory=dict)


RPM = 2 * np.pi / 60
CASES = {
    "watt": Case(
        "watt_sixbar.yaml",
        ["driven link {crank}", "RRR dyad {coupler, rocker}", "RRR dyad {rod, output}"],
        120 * RPM,
        "crank",
        {
            "crank": (1.2, 0.0016),
            "coupler": (2.0, 0.0105),
            "rocker": (3.0, 0.0120),
            "rod": (1.8, 0.0095),
            "output": (1.0, 0.0022),
        },
        torques={"output": -12.0},
        revolutes={
            "O2": ("ground", "crank", 1.5e-3),
            "A": ("crank", "coupler", 10e-3 * 0.12),
            "B": ("coupler", "rocker", 1.2e-3),
            "O4": ("ground", "rocker", 1.5e-3),
            "C": ("rocker", "rod", 1.2e-3),
            "D": ("rod", "output", 1.0e-3),
            "O6": ("ground", "output", 1.5e-3),
        },
    ),
    "inverted": Case(
        "inverted_slider_crank.yaml",
        ["driven link {crank}", "RPR dyad {block, rocker}"],
        -90 * RPM,
        "crank",
        {"crank": (1.5, 0.0020), "block": (0.6, 0.0002), "rocker": (4.0, 0.068)},
        torques={"rocker": -25.0},
        revolutes={
            "O2": ("ground", "crank", 1.5e-3),
            "A": ("crank", "block", 1.0e-3),
            "O4": ("ground", "rocker", 12e-3 * 0.1),
        },
        prismatics={"slot": ("rocker", ("slot0", "slot1"), "block", "A", 0.12, 0.040)},
    ),
    "stephenson": Case(
        "stephenson_sixbar.yaml",
        ["driven link {crank}", "triad {rod, beam, upper, lower}"],
        200 * RPM,
        "crank",
        {
            "crank": (1.0, 0.0008),
            "rod": (1.5, 0.0066),
            "beam": (2.0, 0.0043),
            "upper": (1.2, 0.0040),
            "lower": (1.2, 0.0040),
        },
        forces={"beam": ("D1", (0.0, -300.0))},
        revolutes={
            "O1": ("ground", "crank", 1.5e-3),
            "A": ("crank", "rod", 1.2e-3),
            "D1": ("rod", "beam", 1.0e-3),
            "D2": ("upper", "beam", 1.0e-3),
            "D3": ("lower", "beam", 1.0e-3),
            "O2": ("ground", "upper", 1.2e-3),
            "O3": ("ground", "lower", 1.2e-3),
        },
    ),
}
IDS = list(CASES)


@pytest.fixture(scope="module", params=IDS)
def case(request):
    c = CASES[request.param]
    model = ks.load(MECH / c.file)
    result = ks.analyze(model, positions=GRID)
    order = np.argsort(result.t, kind="stable")
    return c, model, result, order


def col(result, name, order):
    return np.asarray(result[name], dtype=float)[order]


def rel(x, ref):
    """Accuracy (docs/conventions.md): max|x − ref| / max|ref|."""
    return np.max(np.abs(x - ref)) / np.max(np.abs(ref))


def omega(result, link, order):
    return np.zeros(len(order)) if link == "ground" else col(result, f"{link}.omega", order)


def point(result, link, name, order, what=""):
    return np.stack(
        [
            col(result, f"{link}.{name}.{what}x", order),
            col(result, f"{link}.{name}.{what}y", order),
        ],
        axis=-1,
    )


# -- structure -------------------------------------------------------------------
@pytest.mark.parametrize("key", IDS)
def test_structure_and_groups(key):
    c = CASES[key]
    system = ks.build_system(ks.load(MECH / c.file))
    assert system.structure.mobility == 1
    assert [p.group.label for p in system.plans] == c.labels
    # every moving link is solved exactly once
    solved = [name for p in system.plans for name in p.group.links]
    assert sorted(solved) == sorted(c.mass)


@pytest.mark.parametrize("key", IDS)
def test_check_command_prints_groups(key, capsys):
    c = CASES[key]
    assert main(["check", str(MECH / c.file)]) == 0
    out = capsys.readouterr().out
    at = [out.find(label) for label in c.labels]
    assert -1 not in at and at == sorted(at), out  # every group, in solve order


@pytest.mark.parametrize("key", IDS)
def test_default_analysis_runs_the_full_cycle(key):
    c = CASES[key]
    result = ks.analyze(ks.load(MECH / c.file))
    assert len(result) == 360 and result.full_cycle
    assert result.singular == ()
    travel = result["travel"]
    assert travel[0] == 0.0 and travel[-1] == pytest.approx(359.0, abs=1e-9)
    assert np.all(np.isfinite(result["motor.torque"]))


# -- kinematics --------------------------------------------------------------------
def test_numerical_mobility_and_closed_loops(case):
    c, model, result, order = case
    system = result.system
    assert result.singular == ()
    q = result.q[order]
    # n_q − rank Φ_q (joint rows only) = 1 at every position
    jac = jacobian(system, q, range(len(model.joints)))
    s = np.linalg.svd(jac, compute_uv=False)
    rank = np.sum(s > 1e-9 * s[:, :1], axis=-1)
    assert np.all(system.n_q - rank == 1)
    # every revolute: the two links' copies of the pin coincide (ground pins fixed)
    for name, (i, j, _) in c.revolutes.items():
        pj = point(result, j, name, order)
        pi = (
            np.broadcast_to(model.link(i).points[name] + model.link(i).com, pj.shape)
            if i == model.ground.name
            else point(result, i, name, order)
        )
        assert np.max(np.abs(pi - pj)) <= 1e-10 * L_REF, name
    # every prismatic: the slider point on the axis line, no relative rotation
    for name, (i, (a0, a1), j, p, _, _) in c.prismatics.items():
        a, b, pj = (
            point(result, i, a0, order),
            point(result, i, a1, order),
            point(result, j, p, order),
        )
        u = (b - a) / np.linalg.norm(b - a, axis=-1, keepdims=True)
        assert (
            np.max(np.abs(u[:, 0] * (pj - a)[:, 1] - u[:, 1] * (pj - a)[:, 0])) <= 1e-10 * L_REF
        ), name
        dth = col(result, f"{j}.theta", order) - col(result, f"{i}.theta", order)
        assert np.ptp(dth) <= 1e-9, name


def _central(y, h):
    """Central differences at interior points, Richardson-extrapolated (O(h⁴))."""
    d1 = (y[2:] - y[:-2]) / (2 * h)
    d2 = (y[4:] - y[:-4]) / (4 * h)
    return (4 * d1[1:-1] - d2) / 3


def _time_step(result, order):
    t = result.t[order]
    h = np.diff(t)
    assert np.allclose(h, h[0], rtol=1e-9, atol=0)
    return t, h[0]


def test_velocities_are_derivatives_of_positions(case):
    c, model, result, order = case
    _, h = _time_step(result, order)
    q, qd, qdd = result.q[order], result.qd[order], result.qdd[order]
    q = q.copy()
    q[:, 2::3] = np.unwrap(q[:, 2::3], axis=0)
    # the path is continuous: no branch jump between neighbouring positions
    step = np.abs(np.diff(q, axis=0))
    assert np.all(step <= 2 * h * np.max(np.abs(qd), axis=0) + 1e-15)
    fd_v, fd_a = _central(q, h), _central(qd, h)
    for fd, ref in ((fd_v, qd[2:-2]), (fd_a, qdd[2:-2])):
        # (plain central differences on this grid are only good to ~4e-5, hence Richardson)
        # per coordinate, relative to its own extreme; a coordinate that hardly moves
        # (the crank's constant ω has α = 0) is measured against the largest of its kind
        kind = np.arange(ref.shape[1]) % 3 == 2
        peak = np.max(np.abs(ref), axis=0)
        floor = np.where(kind, peak[kind].max(), peak[~kind].max())
        err = np.max(np.abs(fd - ref), axis=0) / np.maximum(peak, 1e-3 * floor)
        assert np.max(err) <= 1e-6, err
    # the named columns are the same arrays, in their units (theta in deg)
    for n, link in enumerate(result.system.links):
        assert np.allclose(col(result, f"{link}.omega", order), qd[:, 3 * n + 2], rtol=0, atol=0)
        d = np.radians(col(result, f"{link}.theta", order)) - q[:, 3 * n + 2]
        assert np.max(np.abs(d - 2 * np.pi * np.round(d / (2 * np.pi)))) <= 1e-12


def test_phi_q_qdot_equals_nu(case):
    c, model, result, order = case
    system = result.system
    q, qd = result.q[order], result.qd[order]
    jac = jacobian(system, q)
    psi_d = np.full((len(q), 1), c.speed)
    rhs = nu(system, psi_d)
    lhs = np.einsum("nij,nj->ni", jac, qd)
    scale = np.einsum("nij,nj->ni", np.abs(jac), np.abs(qd)).max()
    assert np.max(np.abs(lhs - rhs)) <= 1e-12 * scale
    assert np.max(np.abs(rhs)) == pytest.approx(abs(c.speed))  # the driver row is live
    # the crank turns at the prescribed speed
    assert np.allclose(col(result, f"{c.crank}.omega", order), c.speed, rtol=1e-13, atol=0)


# -- power ----------------------------------------------------------------------------
def _powers(c, model, result, order):
    """(P_kin, P_pot, P_ext) from the link columns and the case's own data."""
    kin = pot = ext = 0.0
    energy = 0.0
    for link, (m, j) in c.mass.items():
        v = np.stack([col(result, f"{link}.vx", order), col(result, f"{link}.vy", order)], -1)
        a = np.stack([col(result, f"{link}.ax", order), col(result, f"{link}.ay", order)], -1)
        w, al = col(result, f"{link}.omega", order), col(result, f"{link}.alpha", order)
        kin = kin + m * np.sum(v * a, -1) + j * w * al
        pot = pot - m * v @ G
        energy = energy + 0.5 * (m * np.sum(v * v, -1) + j * w * w)
    for link, tq in c.torques.items():
        ext = ext - tq * col(result, f"{link}.omega", order)
    for link, (p, f) in c.forces.items():
        ext = ext - point(result, link, p, order, "v") @ np.array(f)
    return kin, pot, ext, energy


def test_frictionless_power_balance(case):
    c, model, result, order = case
    t, h = _time_step(result, order)
    p_in = col(result, "power.input", order)
    p_kin = col(result, "power.kinetic", order)
    scale = max(np.max(np.abs(p_in)), np.max(np.abs(p_kin)))
    assert np.max(np.abs(col(result, "power.residual", order))) <= 1e-9 * scale
    # recomputed here: input = torque × crank speed; the other terms from the link columns
    kin, pot, ext, energy = _powers(c, model, result, order)
    assert np.allclose(
        p_in, col(result, "motor.torque", order) * c.speed, rtol=0, atol=1e-12 * scale
    )
    assert np.max(np.abs(p_in - kin - pot - ext)) <= 1e-9 * scale
    assert rel(col(result, "power.kinetic", order), kin) <= 1e-12
    assert rel(col(result, "power.potential", order), pot) <= 1e-12
    assert rel(col(result, "power.external", order), ext) <= 1e-12
    # dT/dt from the kinetic energy by finite differences
    assert rel(_central(energy, h), kin[2:-2]) <= 1e-5
    # all loads are conservative over a cycle: the mean input power is zero
    assert abs(np.mean(p_in)) <= 1e-9 * scale
    assert np.max(np.abs(p_in)) > 1.0  # not trivially zero


def _relative_speeds(c, result, order):
    """Joint → relative speed of j with respect to i (ω_j − ω_i, or ṡ)."""
    out = {}
    for name, (i, j, _) in c.revolutes.items():
        out[name] = omega(result, j, order) - omega(result, i, order)
    for name, (i, (a0, a1), j, p, _, _) in c.prismatics.items():
        a, b = point(result, i, a0, order), point(result, i, a1, order)
        u = (b - a) / np.linalg.norm(b - a, axis=-1, keepdims=True)
        va, vp = point(result, i, a0, order, "v"), point(result, j, p, order, "v")
        perp = np.stack([-u[:, 1], u[:, 0]], -1)
        rate = np.sum((vp - va) * u, -1) + np.sum(
            (point(result, j, p, order) - a) * perp, -1
        ) * omega(result, i, order)
        out[name] = rate
    return out


def test_friction_laws_and_power_balance(case):
    c, model, result, order = case
    status = col(result, "friction.status", order)
    ok = (status == 0) | (status == 1)
    assert ok.mean() > 0.99  # zero relative speed only at isolated positions
    assert not np.any(status == 2)
    speeds = _relative_speeds(c, result, order)
    # the ṡ computed here is the derivative of s = (P − A)·u
    t, h = _time_step(result, order)
    for name, (i, (a0, a1), j, p, _, _) in c.prismatics.items():
        a, b = point(result, i, a0, order), point(result, i, a1, order)
        u = (b - a) / np.linalg.norm(b - a, axis=-1, keepdims=True)
        s = np.sum((point(result, j, p, order) - a) * u, -1)
        assert rel(_central(s, h), speeds[name][2:-2]) <= 1e-5
    # status 3 exactly where a relative speed is zero (SPEC: ≤ 1e-9·x_ref); no friction there
    ref = {k: abs(c.speed) * (L_REF if k in c.prismatics else 1.0) for k in speeds}
    still = {k: np.abs(v) <= 1e-9 * ref[k] for k, v in speeds.items()}
    assert np.array_equal(status == 3, np.any(list(still.values()), axis=0))
    for k, z in still.items():
        assert np.all(col(result, f"{k}.friction", order)[z] == 0), k
        assert np.all(col(result, f"{k}.friction_approx", order)[z] == 0), k
    loss = np.zeros(len(order))
    for name, (_, _, rho) in c.revolutes.items():
        mf = col(result, f"{name}.friction", order)
        fr = np.hypot(
            col(result, f"{name}.Fx_friction", order), col(result, f"{name}.Fy_friction", order)
        )
        f0 = np.hypot(col(result, f"{name}.Fx", order), col(result, f"{name}.Fy", order))
        moving = ok & (np.abs(speeds[name]) > 1e-6 * abs(c.speed))
        assert np.allclose(np.abs(mf[ok]), rho * fr[ok], rtol=1e-10, atol=1e-14), name
        assert np.all(np.sign(mf[moving]) == -np.sign(speeds[name][moving])), name
        ma = col(result, f"{name}.friction_approx", order)
        assert np.allclose(
            ma[moving], -np.sign(speeds[name][moving]) * rho * f0[moving], rtol=1e-10, atol=1e-14
        ), name
        loss += np.abs(mf * speeds[name])
    for name, (*_, f, length) in c.prismatics.items():
        ff = col(result, f"{name}.friction", order)
        n, m = col(result, f"{name}.N_friction", order), col(result, f"{name}.M_friction", order)
        moving = ok & (np.abs(speeds[name]) > 1e-6 * abs(c.speed) * L_REF)
        bearing = np.abs(n / 2 + m / length) + np.abs(n / 2 - m / length)
        assert np.allclose(np.abs(ff[ok]), f * bearing[ok], rtol=1e-10, atol=1e-12), name
        assert np.all(np.sign(ff[moving]) == -np.sign(speeds[name][moving])), name
        # the block's couple is small (its own inertia only): both edges bear the same
        # way, N₁ N₂ > 0, so f(|N₁| + |N₂|) = f|N| here; a couple in wrong units would show
        assert np.all(np.abs(m[ok]) < np.abs(n[ok]) * length / 2), name
        n0, m0 = col(result, f"{name}.N", order), col(result, f"{name}.M", order)
        approx = f * (np.abs(n0 / 2 + m0 / length) + np.abs(n0 / 2 - m0 / length))
        assert np.allclose(
            col(result, f"{name}.friction_approx", order)[moving],
            -np.sign(speeds[name][moving]) * approx[moving],
            rtol=1e-10,
            atol=1e-12,
        )
        loss += np.abs(ff * speeds[name])
    p_fric = col(result, "power.friction", order)
    assert np.all(p_fric[ok] >= 0)
    kin, pot, ext, _ = _powers(c, model, result, order)
    p_in = col(result, "motor.torque_friction", order) * c.speed
    scale = max(np.max(np.abs(p_in[ok])), np.max(np.abs(kin)))
    assert np.max(np.abs(col(result, "power.residual_friction", order)[ok])) <= 1e-9 * scale
    assert np.max(np.abs(p_fric[ok] - loss[ok])) <= 1e-9 * scale
    assert np.max(np.abs(p_in - kin - pot - ext - loss)[ok]) <= 1e-9 * scale
    # friction costs energy over the cycle
    assert np.mean(p_in[ok]) > 0 and np.mean(loss) > 0


# -- Newton–Euler of every link from the reported reactions ------------------------------
def _cross(r, f):
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def _axis(c, result, name, order):
    i, (a0, a1) = c.prismatics[name][:2]
    a, b = point(result, i, a0, order), point(result, i, a1, order)
    u = (b - a) / np.linalg.norm(b - a, axis=-1, keepdims=True)
    return u, np.stack([-u[:, 1], u[:, 0]], -1)


def _link_balance(c, model, result, order, friction, prismatic_force):
    """Max residual of ΣF − m a and ΣM_S − J α over links and positions, and a force scale.

    ``prismatic_force(name, u, n, order)`` gives the force of i on j of each prismatic pair.
    """
    n_pos = len(order)
    force = {k: np.zeros((n_pos, 2)) for k in c.mass}
    moment = {k: np.zeros(n_pos) for k in c.mass}
    com = {
        k: np.stack([col(result, f"{k}.x", order), col(result, f"{k}.y", order)], -1)
        for k in c.mass
    }
    sfx = "_friction" if friction else ""
    peak = 0.0

    def apply(link, f, p, m=0.0):
        if link in force:
            force[link] += f
            moment[link] += _cross(p - com[link], f) + m

    for name, (i, j, _) in c.revolutes.items():
        f = np.stack(
            [col(result, f"{name}.Fx{sfx}", order), col(result, f"{name}.Fy{sfx}", order)], -1
        )
        p = point(result, j, name, order)
        mf = col(result, f"{name}.friction", order) if friction else 0.0
        apply(j, f, p, mf)
        apply(i, -f, p, -mf)
        peak = max(peak, np.max(np.abs(f)))
    for name, (i, _, j, pj, _, _) in c.prismatics.items():
        u, n = _axis(c, result, name, order)
        f = prismatic_force(name, u, n, order)
        m = col(result, f"{name}.M{sfx}", order)
        p = point(result, j, pj, order)
        apply(j, f, p, m)
        apply(i, -f, p, -m)
        peak = max(peak, np.max(np.abs(f)))
    tq = col(result, "motor.torque_friction" if friction else "motor.torque", order)
    moment[c.crank] += tq
    for link, value in c.torques.items():
        moment[link] += value
    for link, (p, f) in c.forces.items():
        apply(link, np.broadcast_to(np.array(f), (n_pos, 2)), point(result, link, p, order))
    worst = 0.0
    for link, (m, j) in c.mass.items():
        a = np.stack([col(result, f"{link}.ax", order), col(result, f"{link}.ay", order)], -1)
        rf = force[link] + m * G - m * a
        rm = moment[link] - j * col(result, f"{link}.alpha", order)
        worst = max(worst, np.max(np.abs(rf)), np.max(np.abs(rm)) / L_REF)
    return worst, peak


def test_newton_euler_frictionless(case):
    c, model, result, order = case

    def prismatic(name, u, n, order=order):
        return col(result, f"{name}.N", order)[:, None] * n

    worst, peak = _link_balance(c, model, result, order, False, prismatic)
    assert peak > 10.0
    assert worst <= 1e-9 * peak
    for name in c.prismatics:  # Fx, Fy are N along the axis normal
        _, n = _axis(c, result, name, order)
        f = np.stack([col(result, f"{name}.Fx", order), col(result, f"{name}.Fy", order)], -1)
        assert np.max(np.abs(f - prismatic(name, None, n))) <= 1e-12 * peak


def test_newton_euler_with_friction(case):
    """Consistent friction solution; prismatic force rebuilt as N·n + friction·u."""
    c, model, result, order = case
    ok = np.isin(col(result, "friction.status", order), (0, 1))

    def prismatic(name, u, n, order):
        return (
            col(result, f"{name}.N_friction", order)[:, None] * n
            + col(result, f"{name}.friction", order)[:, None] * u
        )

    sub = order[ok]
    worst, peak = _link_balance(c, model, result, sub, True, prismatic)
    assert peak > 10.0
    assert worst <= 1e-9 * peak


def test_prismatic_reaction_with_friction_includes_the_friction_force():
    c = CASES["inverted"]
    result = ks.analyze(ks.load(MECH / c.file))
    order = np.argsort(result.t, kind="stable")
    ok = np.isin(col(result, "friction.status", order), (0, 1))
    u, n = _axis(c, result, "slot", order)
    expect = (
        col(result, "slot.N_friction", order)[:, None] * n
        + col(result, "slot.friction", order)[:, None] * u
    )
    got = np.stack(
        [col(result, "slot.Fx_friction", order), col(result, "slot.Fy_friction", order)], -1
    )
    assert np.max(np.abs(col(result, "slot.friction", order)[ok])) > 1.0
    assert np.allclose(got[ok], expect[ok], rtol=1e-10, atol=1e-9)
