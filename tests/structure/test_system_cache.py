"""A model's compiled system is built once and reused — never for a model changed since."""

from __future__ import annotations

import gc
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base.arrays import entry_major_zeros
from kinetostatics.base.geometry import poses
from kinetostatics.structure import system as S

ROOT = Path(__file__).resolve().parents[2]


def test_the_system_is_reused_for_the_same_model():
    m = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    assert S.system_of(m) is S.system_of(m)
    a = ks.analyze(m)
    b = ks.analyze(m)
    assert a.system is b.system


@pytest.mark.parametrize("name", ["cam_roller.yaml", "cam_flat_oscillating.yaml"])
def test_the_values_a_cam_keeps_of_its_last_poses_stay_out_of_the_fingerprint(name):
    """A cam keeps Φ, its coordinate and normal of the last poses (each an inversion of
    its profile): an analysis that leaves them must not make the model a new one."""
    m = ks.load(ROOT / "mechanisms" / name)
    system = S.system_of(m)
    a = ks.analyze(m)
    b = ks.analyze(m, friction=False)
    assert a.system is system and b.system is system and S.system_of(m) is system


def test_a_model_changed_in_place_is_built_again():
    """The crank's pin moved in place in the loaded model: the result equals that of the
    changed file, read afresh (the slider's stroke is twice the crank, a closed form)."""
    path = ROOT / "mechanisms" / "slider_crank.yaml"
    m = ks.load(path)
    first = ks.analyze(m)
    crank = next(link for link in m.links if "A" in link.points and "O" in link.points)
    a, o = crank.points["A"], crank.points["O"]
    before = np.hypot(*(a - o))
    a[:] = o + (a - o) * 1.25  # the same model object, its array changed
    second = ks.analyze(m)
    assert second.system is not first.system
    stroke = lambda r: np.ptp(r[next(c for c in r.names if c.endswith(".s"))])
    if any(c.endswith(".s") for c in first.names):
        # an offset slider-crank's stroke grows with the crank; a centred one's is 2r
        assert stroke(second) > stroke(first)
    assert np.hypot(*(crank.points["A"] - o)) == 1.25 * before


def test_the_cache_lets_go_of_models_and_stays_out_of_pickles():
    import pickle
    import weakref

    m = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    fresh = pickle.dumps(m)
    ks.analyze(m)
    assert pickle.dumps(m) == fresh  # the cache is not part of the model's state
    alive = weakref.ref(m)
    del m
    gc.collect()
    assert alive() is None


def test_a_copy_made_from_the_fields_analyses_like_the_model():
    """``Model(**vars(m))`` and ``replace`` carry the cache along: it is used only where the
    copy describes the same mechanism."""
    import dataclasses

    m = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    ks.analyze(m)
    same = ks.Model(**vars(m))
    assert np.array_equal(ks.analyze(same)["angle"], ks.analyze(m)["angle"])
    moved = dataclasses.replace(m, gravity=np.array([0.0, 0.0]))
    assert S.system_of(moved).model is moved


def test_a_repeated_analysis_gives_the_first_ones_numbers_and_change_points():
    """The change points of the path over a span are kept with the system: the second
    analysis of the same rows and an analysis of a fresh copy of the file agree with the
    first to the bit, change points (singular positions) included, while other rows of the
    same model still find their own."""
    path = ROOT / "tests" / "hard" / "fourbar_change_point.yaml"
    m = ks.load(path)
    with pytest.warns(ks.NearSingularWarning):  # the change point itself, each time
        first, again, fresh = ks.analyze(m), ks.analyze(m), ks.analyze(ks.load(path))
    assert [s.t for s in first.singular] == [s.t for s in again.singular]
    assert [s.t for s in first.singular] == [s.t for s in fresh.singular]
    assert len(first.singular) == 1  # the change point at 180°, a closed form
    np.testing.assert_allclose(np.degrees(first.singular[0].coordinate) % 360, 180.0, atol=1e-6)
    for r in (again, fresh):
        np.testing.assert_array_equal(r.q, first.q)
        np.testing.assert_array_equal(r.qd, first.qd)
    short = ks.analyze(m, positions=np.radians([90.0, 120.0, 150.0]))
    assert short.singular == ()  # this span holds no change point


def test_the_poses_kept_follow_a_state_changed_in_place():
    """The last state's poses are kept with the system under an exact content key: a q
    changed in place gets its own poses (a hinge's residual is that of the new angles,
    computed afresh from cos and sin), and the poses handed out cannot be written."""
    system = S.system_of(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"))
    rng = np.random.default_rng(3)
    q = rng.normal(size=(4, system.n_q))
    first = S.link_poses(system, q)
    assert S.link_poses(system, q.copy()) is first  # the same content: kept
    with pytest.raises(ValueError):
        first[0, 0, 0] = 1.0
    q[:, 2::3] += 0.5  # every angle, in place
    again = S.link_poses(system, q)
    assert again is not first
    np.testing.assert_array_equal(again[..., :-1, 3], np.cos(q[:, 2::3]))
    np.testing.assert_array_equal(again[..., :-1, 4], np.sin(q[:, 2::3]))
    psi = np.zeros((4, 1))
    fresh = S.phi(S.build_system(system.model), q, psi)  # a new system: nothing kept
    np.testing.assert_array_equal(S.phi(system, q, psi), fresh)


@pytest.mark.parametrize("n", [360, 2000])  # frames by np.cos below FRAMES_FROM, by vectors above
def test_an_analysis_reads_the_frames_its_closed_form_pass_placed_the_links_with(n):
    """The rows of a closed-form path carry the frames of their pass (no cosine again): they
    are cos θ and sin θ of the rows' angles to round-off, every stage and every run of the
    rows reads the same ones, and whatever runs in between — another analysis, other rows
    of the same numbers — changes no bit of a column read later."""
    m = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    system, psi = S.system_of(m), np.radians(np.linspace(0.0, 360.0, n, endpoint=False))
    first = ks.analyze(m, positions=psi)
    every = {c: first[c] for c in first.columns}  # read now
    pe = S.link_poses(system, first.q)
    theta = first.q[:, 2::3]
    tol = 4 * np.finfo(float).eps * np.maximum(np.abs(theta), 1.0)  # θ itself to round-off
    assert np.all(np.abs(pe[:, :-1, 3] - np.cos(theta)) <= tol)
    assert np.all(np.abs(pe[:, :-1, 4] - np.sin(theta)) <= tol)
    np.testing.assert_array_equal(pe[:, :-1, :3], first.q.reshape(n, -1, 3))
    assert S.link_poses(system, first.q[5:17]).base is pe.base  # a run of the rows: theirs
    again = ks.analyze(m, positions=psi)
    ks.analyze(m, positions=psi[::7])  # other rows in between
    S.link_poses(system, first.q.copy())  # the same numbers, another array: its own frames
    for c in again.columns:  # read after
        np.testing.assert_array_equal(again[c], every[c], err_msg=c)


def test_poses_run_contiguously_over_the_positions():
    """Each link's x, y, θ, cos θ, sin θ is one contiguous run over the positions (the
    joints' formulas read them so), with the values of the pose-major layout."""
    rng = np.random.default_rng(5)
    q = rng.normal(size=(7, 3, 6))  # positions × variants × two links' coordinates
    pe = poses(q, 2)
    assert pe.shape == (7, 3, 3, 5)
    for link in range(3):
        for c in range(5):
            assert pe[..., link, c].flags.c_contiguous
    np.testing.assert_array_equal(pe[..., :2, :3], q.reshape(7, 3, 2, 3))
    np.testing.assert_array_equal(pe[..., :2, 3], np.cos(q[..., 2::3]))
    np.testing.assert_array_equal(pe[..., :2, 4], np.sin(q[..., 2::3]))
    np.testing.assert_array_equal(pe[..., 2, :], np.broadcast_to([0.0, 0, 0, 1, 0], (7, 3, 5)))


def test_joint_jacobians_and_gamma_run_contiguously_over_the_positions():
    """A hinge's and a slide's Φ_q parts are stored entry-major and γ row-major: each entry
    one contiguous run over the positions (the blocks gather them so), with the values of
    the joints' formulas."""
    system = S.system_of(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    rng = np.random.default_rng(8)
    q, qd = rng.normal(size=(2, 50, system.n_q))
    pe = S.link_poses(system, q)
    for k, joint in enumerate(system.model.joints):
        i, j = system.ends[k]
        for part in joint.jacobian(pe[..., i, :], pe[..., j, :]):
            assert part.shape == (50, joint.n_eq, 3)
            assert all(
                part[..., r, c].flags.c_contiguous for r in range(joint.n_eq) for c in range(3)
            )
    g = S.gamma(system, q, qd, np.zeros((50, 1)))
    assert all(g[..., r].flags.c_contiguous for r in range(g.shape[-1]))


def test_entry_major_zeros():
    z = entry_major_zeros((4, 3, 2, 3))
    assert z.shape == (4, 3, 2, 3) and not z.any()
    assert z[..., 1, 2].flags.c_contiguous and z[..., 1, 2].shape == (4, 3)


def _long_pass(source: str) -> str:
    """The closed forms' pass as it runs over FRAMES_FROM points or more (the branches
    for fewer left out)."""
    kept, skipping = [], False
    for line in source.splitlines():
        if line == "    else:":
            skipping = True
            continue
        if skipping and line.startswith("        "):
            continue
        skipping = False
        kept.append(line)
    return "\n".join(kept)


def test_the_closed_forms_turn_each_link_once_and_satisfy_the_constraints():
    """The closed forms' pass evaluates each link's cos θ and sin θ once (the later groups
    read them) — over many points by ``np.cos`` and ``np.sin`` only for a driven link's
    angle, a dyad's links turning by the directions of the vectors their angles are the
    headings of — and
    on every shipped file whose groups all have one (the angles of the links not listed
    as headings, ``ClosedForms.wrapping``, without a jump of 2π) its sweep satisfies
    Φ = 0 and its discriminants are those of the assembly: D ≥ 0 along it, and a link
    turned by its own angle's cos and sin (the frames are those of the angles placed)."""
    from kinetostatics.kinematics.closed_path import _closed_forms
    from kinetostatics.kinematics.dyads import FRAMES_FROM
    from kinetostatics.kinematics.schedule import schedule
    from kinetostatics.kinematics.start import closed_form_solvers, start_pose

    checked = 0
    for path in sorted((ROOT / "mechanisms").glob("*.yaml")):
        m = ks.load(path)
        system = S.system_of(m)
        if len(system.motion_drivers) != system.structure.mobility or not system.motion_drivers:
            continue  # effort-driven: no closed-form sweep
        sched = schedule(system)
        forms = closed_form_solvers(system, sched)
        if forms is None:
            continue
        driven = sum(p.group.kind == "driven" for p in system.plans)  # a driver's angle
        long = _long_pass(forms.source)  # a dyad's links: their own vectors' directions
        assert long.count("np.cos(") == long.count("np.sin(") == driven, path.name
        for n in (97, FRAMES_FROM):  # the frames by np.cos and np.sin, and not
            t = np.linspace(0.0, 0.9 * sched.period if sched.period else 1.0, n)
            psi = sched(t)[0]
            q0 = np.broadcast_to(start_pose(system, sched)[0], (len(t), system.n_q))
            q, d = _closed_forms(forms, q0.shape, psi, np.ones((len(t), len(forms))))
            assert d.shape == (len(t), len(system.plans)) and np.all(d >= -1e-12), path.name
            res = np.max(np.abs(S.phi(system, q, psi)))
            assert res <= 1e-13 * system.l_ref, (path.name, res)
            steady = [k for k in range(len(system.links)) if k not in forms.wrapping]
            turns = np.abs(np.diff(q[:, 3 * np.array(steady, dtype=int) + 2], axis=0))
            assert np.all(turns < np.pi), path.name  # no 2π jump: the path need not unwrap
        checked += 1
    assert checked >= 5  # the slider-crank and the slotting machine among them


def test_every_change_in_place_is_noticed_without_a_pickle(monkeypatch):
    """The fingerprint (structure/fingerprint.py) sees an array written, a mapping's item
    replaced or added, and a field replaced by ``dataclasses.replace`` — and no analysis
    pickles the model to know it."""
    import dataclasses
    import pickle

    def forbidden(*a, **k):
        raise AssertionError("the model was pickled")

    m = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    monkeypatch.setattr(pickle, "dumps", forbidden)
    first = S.system_of(m)
    assert S.system_of(m) is first
    crank = next(link for link in m.links if "A" in link.points and "O" in link.points)
    changes = [
        lambda: m.gravity.__setitem__(1, -9.80),  # an array written
        lambda: crank.points.__setitem__("A", crank.points["A"].copy()),  # same values, new
        lambda: crank.points.__setitem__("Z", np.zeros(2)),  # an item added
        lambda: crank.points.pop("Z"),  # and taken away
    ]
    for change in changes:
        before = S.system_of(m)
        change()
        after = S.system_of(m)
        assert after is not before
        assert S.system_of(m) is after  # and kept again
    moved = dataclasses.replace(m, name="other")
    assert S.system_of(moved) is not S.system_of(m)


def test_every_shipped_model_keeps_its_system():
    """Every file of mechanisms/ is followed by a fingerprint (none falls back to no cache),
    and an analysis leaves it unchanged."""
    import warnings

    for path in sorted((ROOT / "mechanisms").glob("*.yaml")):
        m = ks.load(path)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                ks.analyze(m, friction=False)
            except ks.StructureError:  # effort-driven: simulate's, not analyze's
                S.system_of(m)
        assert m._compiled is not None, path.name
        assert S.system_of(m) is m._compiled[1], path.name


def test_the_path_unwraps_its_angles_as_numpy_does():
    """The closed-form path's unwrapping (whole turns counted as integers) gives
    ``np.unwrap``'s angles along the rows, to round-off of the angles' size, on random
    paths with steps up to ±3 rad and with jumps of whole turns."""
    from kinetostatics.kinematics.closed_path import _unwrapped

    rng = np.random.default_rng(2)
    true = np.cumsum(rng.uniform(-3.0, 3.0, (2, 4000, 3)), axis=1)
    wrapped = (true + np.pi) % (2 * np.pi) - np.pi
    wrapped[:, ::7] += 2 * np.pi * rng.integers(-3, 4, (2, len(wrapped[0, ::7]), 3))
    got = _unwrapped(wrapped)
    assert np.max(np.abs(got - np.unwrap(wrapped, axis=1))) <= 1e-13 * np.max(np.abs(got))
    assert np.max(np.abs(got - got[:, :1] - (true - true[:, :1]))) <= 1e-12 * np.max(np.abs(true))
