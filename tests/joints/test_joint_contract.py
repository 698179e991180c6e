"""Every registered joint type against the interface contract.

Instances come from the shipped mechanisms, so a new type must be shipped in
an example to be covered (asserted).  Each check compares with independent
truth: central differences of the type's own residual and coordinate.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.io import dump
from kinetostatics.joints import JOINT_TYPES
from kinetostatics.outputs.loading import loads
from tests.helpers import MECHANISMS

RNG = np.random.default_rng(7)
SAMPLES = {}
MODEL_OF = {}  # id(joint) -> its model
for path in MECHANISMS:
    model = ks.load(path)
    for joint in model.joints:
        SAMPLES.setdefault(joint.kind, []).append(joint)
        MODEL_OF[id(joint)] = model
JOINTS = [j for js in SAMPLES.values() for j in js]
IDS = [f"{j.kind}:{j.name}" for j in JOINTS]


def _states(batch=(2, 3)):
    q = RNG.normal(size=batch + (2, 3)) * [0.3, 0.3, 2.0]
    v = RNG.normal(size=batch + (2, 3)) * [1.0, 1.0, 5.0]
    return q[..., 0, :], q[..., 1, :], v[..., 0, :], v[..., 1, :]


def _fd(f, qi, qj, h=1e-6):
    """Central-difference derivatives of f over (qi, qj): (..., out, 3) each."""
    cols_i, cols_j = [], []
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        cols_i.append((f(qi + e, qj) - f(qi - e, qj)) / (2 * h))
        cols_j.append((f(qi, qj + e) - f(qi, qj - e)) / (2 * h))
    return np.stack(cols_i, axis=-1), np.stack(cols_j, axis=-1)


def test_every_registered_type_is_shipped():
    assert set(JOINT_TYPES) <= set(SAMPLES), "ship an example using every joint type"


def test_registry_lookup_lists_choices():
    with pytest.raises(KeyError, match="known: .*prismatic.*revolute"):
        ks.joints.joint_type("revolut")
    for kind, cls in JOINT_TYPES.items():
        assert ks.joints.joint_type(kind) is cls and cls.kind == kind


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_shapes_broadcast_over_batch_axes(joint):
    qi, qj, vi, vj = _states()
    n = joint.n_eq
    assert joint.residual(qi, qj).shape == (2, 3, n)
    ji, jj = joint.jacobian(qi, qj)
    assert ji.shape == jj.shape == (2, 3, n, 3)
    assert joint.acceleration_rhs(qi, qj, vi, vj).shape == (2, 3, n)
    reac = joint.reaction(np.ones((2, 3, n)), qi, qj)
    assert set(reac) == set(joint.reaction_labels)
    assert all(v.shape == (2, 3) for v in reac.values())
    # one position (no batch axes) gives the same numbers as the batch
    np.testing.assert_allclose(joint.residual(qi[1, 2], qj[1, 2]), joint.residual(qi, qj)[1, 2])


def _with_frame(q):
    """A pose (..., 3) as the system passes it: with its frame (cos θ, sin θ) after it."""
    return np.concatenate((q, np.cos(q[..., 2:3]), np.sin(q[..., 2:3])), axis=-1)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_poses_with_their_frame_give_the_same_numbers(joint):
    """The system hands a joint its links' poses with (cos θ, sin θ) computed once per
    state, ``(..., 5)``; every method gives what it gives for the bare ``(..., 3)`` pose,
    and gradients over q stay ``(..., 3)``."""
    qi, qj, vi, vj = _states()
    fi, fj = _with_frame(qi), _with_frame(qj)
    lam = RNG.normal(size=(2, 3, joint.n_eq))
    e = RNG.normal(size=(2, 3))  # a friction effort
    pairs = [
        (joint.residual(qi, qj), joint.residual(fi, fj)),
        (joint.acceleration_rhs(qi, qj, vi, vj), joint.acceleration_rhs(fi, fj, vi, vj)),
        (joint.coordinate(qi, qj), joint.coordinate(fi, fj)),
        (joint.coordinate_bias(qi, qj, vi, vj), joint.coordinate_bias(fi, fj, vi, vj)),
        *zip(joint.jacobian(qi, qj), joint.jacobian(fi, fj)),
        *zip(joint.motion_direction(qi, qj), joint.motion_direction(fi, fj)),
        *zip(joint.reaction(lam, qi, qj).values(), joint.reaction(lam, fi, fj).values()),
        *zip(joint.effort_force(e, qi, qj).values(), joint.effort_force(e, fi, fj).values()),
        (joint.friction_kinks(lam, qi, qj), joint.friction_kinks(lam, fi, fj)),
        (joint.motion_breaks(qi, qj), joint.motion_breaks(fi, fj)),
    ]
    for bare, framed in pairs:
        assert bare.shape == framed.shape
        np.testing.assert_array_equal(framed, bare)


def _moved(joint):
    """``joint`` with each real field (a number, an array of them) moved at random."""
    moved = {}
    for f in dataclasses.fields(joint):
        v = getattr(joint, f.name)
        if isinstance(v, float) or (isinstance(v, np.ndarray) and v.dtype.kind == "f"):
            moved[f.name] = v + RNG.uniform(0.1, 0.2, size=np.shape(v))
    return dataclasses.replace(joint, **moved)


@pytest.mark.parametrize("kind", sorted(SAMPLES))
def test_a_stack_gives_each_joints_own_numbers(kind):
    """``Joint.stack``: the joints of a type stacked on an axis before the last give, at
    poses stacked the same way, each joint's own residual, Jacobian and γ to the bit
    (the system evaluates a type's joints in one call; None: one by one)."""
    cls = JOINT_TYPES[kind]
    if cls.stack(SAMPLES[kind] * 2) is None:
        pytest.skip(f"{kind} joints are evaluated one by one")
    # the shipped joints and copies with every real number they hold moved: a field
    # the methods read but the stack does not stack would give the first joint's value
    joints = SAMPLES[kind] + [_moved(j) for j in SAMPLES[kind]]
    stacked = cls.stack(joints)
    q = RNG.normal(size=(2, 4, len(joints), 3)) * [0.3, 0.3, 2.0]
    vi, vj = RNG.normal(size=(2, 4, len(joints), 3)) * [1.0, 1.0, 5.0]
    qi, qj = _with_frame(q[0]), _with_frame(q[1])
    got = (
        stacked.residual(qi, qj),
        *stacked.jacobian(qi, qj),
        stacked.acceleration_rhs(qi, qj, vi, vj),
    )
    for k, joint in enumerate(joints):
        own = (
            joint.residual(qi[:, k], qj[:, k]),
            *joint.jacobian(qi[:, k], qj[:, k]),
            joint.acceleration_rhs(qi[:, k], qj[:, k], vi[:, k], vj[:, k]),
        )
        for a, b in zip(got, own):
            np.testing.assert_array_equal(a[:, k], b)


@pytest.mark.parametrize("kind", sorted(SAMPLES))
def test_a_friction_stack_gives_each_joints_own_magnitude(kind):
    """``Joint.stack_friction``: the joints of a type stacked on a last axis give, for
    reactions stacked on an axis before the last, each joint's own friction magnitude to
    the bit (the friction solutions evaluate a type's efforts in one call; None: one by
    one)."""
    cls = JOINT_TYPES[kind]
    if cls.stack_friction(SAMPLES[kind] * 2) is None:
        pytest.skip(f"{kind} friction efforts are evaluated one by one")
    # with every real number moved: a field friction_magnitude reads but the stack does
    # not stack would give the first joint's value
    joints = SAMPLES[kind] + [_moved(j) for j in SAMPLES[kind]]
    stacked = cls.stack_friction(joints)
    k = len(joints)
    lam = RNG.normal(size=(2, 4, k, joints[0].n_eq)) * 100.0
    q = RNG.normal(size=(2, 2, 4, k, 3)) * [0.3, 0.3, 2.0]
    got = stacked.friction_magnitude(lam, q[0], q[1])
    assert got.shape == (2, 4, k)
    for m, joint in enumerate(joints):
        own = joint.friction_magnitude(lam[..., m, :], q[0][..., m, :], q[1][..., m, :])
        np.testing.assert_array_equal(got[..., m], own)
    assert np.all(np.any(got != 0.0, axis=(0, 1))[len(SAMPLES[kind]) :])  # moved: friction


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_jacobian_matches_central_differences(joint):
    qi, qj, _, _ = _states()
    ji, jj = joint.jacobian(qi, qj)
    fi, fj = _fd(lambda a, b: joint.residual(a, b), qi, qj)
    np.testing.assert_allclose(ji, fi, atol=1e-7)
    np.testing.assert_allclose(jj, fj, atol=1e-7)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_gamma_is_minus_derivative_of_jacobian_times_velocity(joint):
    """γ = −d/dt(Φ_q) q̇ along the motion q(t) = q + t q̇."""
    qi, qj, vi, vj = _states()
    h = 1e-6

    def phiq_qd(s):
        a, b = joint.jacobian(qi + s * vi, qj + s * vj)
        return np.einsum("...ij,...j->...i", a, vi) + np.einsum("...ij,...j->...i", b, vj)

    expected = -(phiq_qd(h) - phiq_qd(-h)) / (2 * h)
    np.testing.assert_allclose(joint.acceleration_rhs(qi, qj, vi, vj), expected, atol=1e-6)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_motion_direction_and_bias_match_the_coordinate(joint):
    qi, qj, vi, vj = _states()
    gi, gj = joint.motion_direction(qi, qj)
    fi, fj = _fd(lambda a, b: joint.coordinate(a, b)[..., None], qi, qj)
    np.testing.assert_allclose(gi, fi[..., 0, :], atol=1e-7)
    np.testing.assert_allclose(gj, fj[..., 0, :], atol=1e-7)

    # the second derivative along q(t) = q + t q̇ is the bias: second differences at h and
    # h/2, extrapolated (Richardson: O(h⁴); the states turn at up to ~15 rad/s, where the
    # plain difference's O(h²) error of a cam reaches 1e-5)
    def second(h):
        c = [joint.coordinate(qi + s * vi, qj + s * vj) for s in (-h, 0.0, h)]
        return (c[0] - 2 * c[1] + c[2]) / h**2

    h = 1e-4
    np.testing.assert_allclose(
        joint.coordinate_bias(qi, qj, vi, vj),
        (4 * second(h / 2) - second(h)) / 3,
        rtol=1e-5,
        atol=1e-5,
    )


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_reaction_is_the_force_of_i_on_j_and_third_law_holds(joint):
    """Φ_qjᵀλ applies (Fx, Fy) to j; Φ_qiᵀλ applies the opposite force to i."""
    qi, qj, _, _ = _states()
    lam = RNG.normal(size=(2, 3, joint.n_eq))
    ji, jj = joint.jacobian(qi, qj)
    on_i = np.einsum("...ij,...i->...j", ji, lam)
    on_j = np.einsum("...ij,...i->...j", jj, lam)
    reac = joint.reaction(lam, qi, qj)
    np.testing.assert_allclose(on_j[..., 0], reac["Fx"], atol=1e-12)
    np.testing.assert_allclose(on_j[..., 1], reac["Fy"], atol=1e-12)
    np.testing.assert_allclose(on_i[..., :2], -on_j[..., :2], atol=1e-12)


@pytest.mark.parametrize(
    "joint",
    [j for j in JOINTS if j.has_friction],
    ids=[i for i, j in zip(IDS, JOINTS) if j.has_friction],
)
def test_friction_dissipates_and_gradient_matches(joint):
    qi, qj, vi, vj = _states()
    lam = RNG.normal(size=(2, 3, joint.n_eq)) * 100
    mag = joint.friction_magnitude(lam, qi, qj)
    assert np.all(mag >= 0)
    speed = joint.relative_speed(qi, qj, vi, vj)
    effort = -np.sign(speed) * mag  # the rule of friction.efforts
    assert np.all(effort * speed <= 0)
    h = 1e-6
    grad = joint.friction_gradient(lam, qi, qj)
    for k in range(joint.n_eq):
        e = np.zeros(joint.n_eq)
        e[k] = h
        fd = (
            joint.friction_magnitude(lam + e, qi, qj) - joint.friction_magnitude(lam - e, qi, qj)
        ) / (2 * h)
        np.testing.assert_allclose(grad[..., k], fd, rtol=1e-6, atol=1e-12 * np.max(mag) / h)


@pytest.mark.parametrize(
    "joint",
    [j for j in JOINTS if j.has_friction],
    ids=[i for i, j in zip(IDS, JOINTS) if j.has_friction],
)
def test_a_friction_law_that_reads_no_poses_is_the_same_without_them(joint):
    """A type that says its ``friction_magnitude`` reads no poses (``friction_reads_poses``
    False: the friction solutions then hand it None) gives the same numbers, to the bit,
    without them as at poses of every kind; a type that reads them is handed them."""
    qi, qj, _, _ = _states()
    lam = RNG.normal(size=(2, 3, joint.n_eq)) * 100
    mag = joint.friction_magnitude(lam, qi, qj)
    if type(joint).friction_reads_poses:
        return
    np.testing.assert_array_equal(joint.friction_magnitude(lam, None, None), mag)
    moved = joint.friction_magnitude(lam, qi + 0.25, -qj)
    np.testing.assert_array_equal(moved, mag)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_a_fixed_direction_is_the_motion_direction_at_every_pose(joint):
    """A type that declares its ``fixed_direction`` (the coordinate's rate then read from
    the links' rates alone) has that ``motion_direction`` at poses of every kind."""
    fixed = type(joint).fixed_direction
    if fixed is None:
        return
    qi, qj, _, _ = _states()
    for g, want in zip(joint.motion_direction(qi, qj), fixed):
        np.testing.assert_array_equal(g, np.broadcast_to(want, g.shape))


@pytest.mark.parametrize("path", MECHANISMS, ids=[p.stem for p in MECHANISMS])
def test_yaml_round_trip(path):
    model = ks.load(path)
    again = loads(dump(model))
    assert [j.name for j in again.joints] == [j.name for j in model.joints]
    for a, b in zip(model.joints, again.joints):
        assert type(a) is type(b) and a.links == b.links
        for name in ("p_i", "p_j", "a", "u", "p", "rho", "f", "angle"):
            if hasattr(a, name):
                np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=1e-15)
    for a, b in zip(model.links, again.links):
        assert a.mass == pytest.approx(b.mass) and a.inertia == pytest.approx(b.inertia)
        for k in a.points:
            np.testing.assert_allclose(a.points[k], b.points[k], atol=1e-15)


@pytest.mark.parametrize("path", MECHANISMS, ids=[p.stem for p in MECHANISMS])
def test_a_joint_equals_itself_loaded_again(path):
    """``==`` by value: a type with array fields sets ``__eq__ = same_fields`` (the
    generated one raised NumPy's ValueError on them)."""
    for a, b in zip(ks.load(path).joints, ks.load(path).joints):
        assert a == b and not a != b, type(a).__name__


# -- the core every type implements and the optional parts it declares (joints/base.py) --
# the members a type that declares a part must give itself (the rest keep their defaults)
REQUIRED = {
    "Presentation": {"letter", "anchors", "glyph"},
    "Friction": {"has_friction", "friction_magnitude", "friction_gradient", "friction_constants"},
    "Compiled": set(),
    "Shaped": set(),
}


def _own_classes(cls):
    """The type's own classes: those of its MRO that the base ``Joint`` does not have."""
    from kinetostatics.joints.base import OPTIONAL_PARTS, Joint

    return [c for c in cls.__mro__ if c not in Joint.__mro__ and c not in OPTIONAL_PARTS]


@pytest.mark.parametrize("kind", sorted(JOINT_TYPES))
def test_a_type_implements_the_core(kind):
    """Every abstract member of the core is the type's own, and its class constants are set."""
    from kinetostatics.joints.base import JointCore

    cls = JOINT_TYPES[kind]
    own = {n for c in _own_classes(cls) for n in vars(c)}
    assert JointCore.__abstractmethods__ <= own, JointCore.__abstractmethods__ - own
    assert cls.n_eq == len(SAMPLES[kind][0].residual(np.zeros(3), np.zeros(3)))
    assert isinstance(cls.angular, bool) and cls.reaction_labels


@pytest.mark.parametrize("kind", sorted(JOINT_TYPES))
def test_a_type_gives_the_members_of_exactly_the_parts_it_declares(kind):
    """A type names each optional part it gives among its bases (directly or through a
    shared part such as the toothed pairs' ``MeshFriction``): it then gives that part's
    required members itself, and it overrides no member of a part it does not name."""
    from kinetostatics.joints.base import OPTIONAL_PARTS

    cls = JOINT_TYPES[kind]
    mine = _own_classes(cls)  # the type itself and a shared part such as MeshFriction
    declared = {b for c in mine for b in c.__bases__ if b in OPTIONAL_PARTS}
    assert set(REQUIRED) == {p.__name__ for p in OPTIONAL_PARTS}
    for part in OPTIONAL_PARTS:
        members = {n for n in vars(part) if not n.startswith("__")}
        given = {n for c in _own_classes(cls) for n in vars(c) if n in members}
        if part in declared:
            assert REQUIRED[part.__name__] <= given, (
                part.__name__,
                REQUIRED[part.__name__] - given,
            )
            assert given, f"{kind} declares {part.__name__} but gives none of its members"
        else:
            assert not given, (
                f"{kind} gives {sorted(given)} of {part.__name__} without declaring it"
            )


# -- the hooks the rest of the code asks (pictures, report, sketch, dump) ---------------
def test_letters_are_one_character_and_distinct():
    letters = [cls.letter for cls in JOINT_TYPES.values()]
    assert all(isinstance(x, str) and len(x) == 1 for x in letters)
    named = [x for x in letters if x != "?"]
    assert len(set(named)) == len(named), "two types share a letter of the Assur labels"
    assert all(isinstance(cls.reports_stroke, bool) for cls in JOINT_TYPES.values())
    assert all(isinstance(cls.reports_swing, bool) for cls in JOINT_TYPES.values())
    assert not any(cls.reports_swing and cls.reports_stroke for cls in JOINT_TYPES.values())
    assert all(cls.angular for cls in JOINT_TYPES.values() if cls.reports_swing)
    assert all(isinstance(cls.pin, bool) for cls in JOINT_TYPES.values())


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_anchors_name_points_of_their_links(joint):
    model = MODEL_OF[id(joint)]
    anchors = joint.anchors()
    assert isinstance(anchors, tuple)
    for a in anchors:
        assert a.link in joint.links
        points = model.link(a.link).points
        assert a.point in points, f"{joint.name}: no point '{a.point}' on '{a.link}'"
        np.testing.assert_array_equal(a.xy, points[a.point])
    if joint.pin:  # a pin ties one point of each link, at the joint
        assert sorted(a.link for a in anchors if a.at_joint) == sorted(joint.links)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_glyph_broadcasts_over_batch_axes(joint):
    qi, qj, _, _ = _states()
    g, one = joint.glyph(qi, qj), joint.glyph(qi[1, 2], qj[1, 2])

    def arrays(glyph):
        out = [glyph.point]
        if glyph.block is not None:
            out += [glyph.block.centre, glyph.block.direction]
        if glyph.guide is not None:
            out += [glyph.guide.point, glyph.guide.direction]
        out += [c.centre for c in glyph.circles]
        out += [x for line in glyph.lines for x in (line.point, line.direction)]
        return out

    assert g.point is not None, "a shipped type draws its reaction point"
    for batch, single in zip(arrays(g), arrays(one)):
        assert batch.shape == (2, 3, 2) and single.shape == (2,)
        np.testing.assert_allclose(single, batch[1, 2], rtol=1e-14, atol=1e-15)
    for batch, single in zip(g.curves, one.curves):  # polylines: (..., n, 2)
        assert batch.points.shape[:2] == (2, 3) and batch.points.shape[2:] == single.points.shape
        np.testing.assert_allclose(single.points, batch.points[1, 2], rtol=1e-14, atol=1e-15)
    links = {p.link for p in (g.block, g.guide, *g.circles, *g.lines, *g.curves) if p is not None}
    assert links <= set(joint.links)
    for u in [p.direction for p in (g.block, g.guide, *g.lines) if p is not None]:
        np.testing.assert_allclose(np.hypot(u[..., 0], u[..., 1]), 1.0, rtol=1e-12)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_glyph_point_is_the_point_at_the_joint_on_link_j(joint):
    """Where a pin's or a slider's reaction acts: its anchor at the joint on link j."""
    qi, qj, _, _ = _states()
    g = joint.glyph(qi, qj)
    c, s = np.cos(qj[..., 2]), np.sin(qj[..., 2])
    for a in joint.anchors():
        if a.at_joint and a.link == joint.links[1]:
            x, y = a.xy
            p = qj[..., :2] + np.stack((c * x - s * y, s * x + c * y), axis=-1)
            np.testing.assert_allclose(g.point, p, atol=1e-15)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_describe_and_label_are_text(joint):
    text = joint.describe()
    assert set(text) == {"where", "friction"}
    assert all(isinstance(v, str) for v in text.values())
    assert isinstance(joint.label(), str) and joint.label()
    assert isinstance(joint.friction_constants(), tuple)


@pytest.mark.parametrize("joint", JOINTS, ids=IDS)
def test_friction_kinks_are_where_the_friction_magnitude_bends(joint):
    """Along a straight path in λ, friction_magnitude is linear except where a value of
    friction_kinks passes zero: its second difference vanishes away from those crossings."""
    qi, qj, _, _ = _states(batch=(1,))
    a, b = RNG.normal(size=joint.n_eq), RNG.normal(size=joint.n_eq)
    s = np.linspace(-3, 3, 601)
    lam = a + s[:, None] * b
    mu = joint.friction_magnitude(lam[:, None, :], qi, qj)[:, 0]
    k = joint.friction_kinks(lam[:, None, :], qi, qj)[:, 0, :]
    bend = np.abs(np.diff(mu, 2)) > 1e-9 * (1 + np.max(np.abs(mu)))
    cross = np.zeros(len(s) - 2, dtype=bool)
    for m in range(k.shape[-1]):
        sign = np.sign(k[:, m])
        change = sign[:-1] * sign[1:] <= 0
        cross |= change[:-1] | change[1:]
    if joint.kind == "revolute":  # ρ|F|: smooth unless the line passes through F = 0
        return
    assert not np.any(bend & ~cross)


def test_a_type_is_imported_when_a_file_names_it():
    """A run of a linkage of revolutes and slides imports no gear or cam module; a file
    with a gear imports it; iterating JOINT_TYPES lists every built-in type."""
    import subprocess
    import sys

    code = (
        "import sys, kinetostatics as ks;"
        "ks.analyze(ks.load('mechanisms/slotting_machine.yaml'));"
        "print(sorted(m.rsplit('.', 1)[1] for m in sys.modules"
        " if m.startswith('kinetostatics.joints.')));"
        "ks.load('mechanisms/geared_fivebar.yaml');"
        "print('kinetostatics.joints.gear' in sys.modules)"
    )
    root = Path(__file__).resolve().parents[2]
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=root
    ).stdout.splitlines()
    assert out == ["['base', 'prismatic', 'relative', 'revolute']", "True"]
    assert list(JOINT_TYPES) == ["cam", "gear", "prismatic", "rack", "revolute"]
