"""The optional compiled backend (base/kernels.py): the joints' kernels give the numbers of
their NumPy formulas, and so does a whole analysis on the numba backend, every column
within 1e-12 of its unit's scale (the backend's contract, docs/python.md: not the same
bits — NumPy's SIMD sin and cos, and the order of a sum, move the last bits from one CPU
to another, and a compiler may fuse a multiply and an add).

The kernels are plain Python: the first tests run them uncompiled (no numba needed), on
random poses and rates, against the NumPy path of the same system — so a kernel whose
formula is wrong fails here whether numba is installed or not.  The rest compile them;
the slow run takes 200 generated mechanisms through both backends.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base import kernels
from kinetostatics.base.geometry import poses
from kinetostatics.errors import MissingPackageError, ModelError
from kinetostatics.kinetics import friction
from kinetostatics.structure import evaluation
from kinetostatics.structure.system import _rates, build_system
from tests.helpers import ROOT, assert_close_on_unit_scales, motion_driven
from tests.net import generate

SHIPPED = [ROOT / "mechanisms" / f"{name}.yaml" for name in motion_driven()]
HARD = sorted((ROOT / "tests" / "hard").glob("*.yaml"))
SEEDS = range(8)  # generated mechanisms (tests/net): dyads, triads, sliders on moving links
MANY = range(1_000_000, 1_000_200)  # the slow run's: the long run's first 200 seeds
REL = 1e-12  # of the scale: the compiled backend's contract

try:
    import numba  # noqa: F401

    HAVE_NUMBA = True
except ImportError:  # the extra is optional: the tests that compile are skipped
    HAVE_NUMBA = False
compiling = pytest.mark.skipif(not HAVE_NUMBA, reason="numba is not installed")


def _name(source) -> str:
    return source.stem if isinstance(source, Path) else f"seed{source}"


def _model(source) -> ks.Model:
    if isinstance(source, Path):
        return ks.load(source)
    return ks.loads(generate.to_text(generate.generate(source)), f"seed{source}.yaml")


@pytest.fixture
def backend():
    """Set the backend inside a test; the default (NumPy) back after it."""
    yield kernels.set_backend
    kernels.set_backend("numpy")


@pytest.fixture
def uncompiled(monkeypatch, backend):
    """The kernel path with the kernels run as plain Python (not compiled)."""
    identity = lambda f: f  # noqa: E731
    monkeypatch.setattr(kernels, "compiled", identity)
    monkeypatch.setattr("kinetostatics.joints.base.compiled", identity)
    monkeypatch.setattr("kinetostatics.structure.drivers.compiled", identity)
    monkeypatch.setattr(kernels, "active", lambda: True)


def _state(system, rng, n=7):
    """Random coordinates, rates and ψ̈ at ``n`` positions (not assembled: the formulas
    hold anywhere)."""
    q = rng.uniform(-2.0, 2.0, (n, system.n_q))
    qd = rng.uniform(-3.0, 3.0, (n, system.n_q))
    psi_dd = rng.uniform(-5.0, 5.0, (n, len(system.motion_drivers)))
    return poses(q, len(system.links)), _rates(qd), psi_dd


def _evaluate(system, pe, ve, psi_dd):
    blocks, ground = evaluation.jacobian_blocks_all(system.sets, system.layout, pe)
    gamma = evaluation.gamma_all(system.sets, system.n_rows, pe, ve, psi_dd)
    parts = [p for d, lo, _ in blocks for p in (d, lo) if p is not None]
    return [np.array(p) for p in parts] + ([] if ground is None else [ground]) + [gamma]


@pytest.mark.parametrize("source", SHIPPED + HARD + list(SEEDS), ids=_name)
def test_kernels_give_the_numpy_formulas(source, uncompiled, monkeypatch):
    """Φ_q's group blocks, the ground's block and γ at random states: every set with
    kernels evaluated by them (uncompiled), against every set by NumPy."""
    model = _model(source)
    rng = np.random.default_rng(7)
    system = build_system(model)
    if not any(s.kernels() is not None for s in system.sets):
        pytest.skip("no joint type with kernels")
    state = _state(system, rng)
    with_kernels = _evaluate(system, *state)
    monkeypatch.setattr(kernels, "active", lambda: False)
    by_numpy = _evaluate(system, *state)
    for a, b in zip(with_kernels, by_numpy):
        assert a.shape == b.shape
        _close(a, b)


def _close(a, b) -> None:
    """``a`` within :data:`REL` of the largest finite |value| of ``b``; NaN, ±inf where
    ``b`` has them."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    finite = np.isfinite(b)
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    np.testing.assert_array_equal(a[np.isinf(b)], b[np.isinf(b)])
    scale = float(np.max(np.abs(b[finite]), initial=0.0))
    np.testing.assert_allclose(a[finite], b[finite], rtol=0, atol=REL * scale)


@pytest.mark.parametrize("source", SHIPPED + HARD + list(SEEDS), ids=_name)
def test_friction_kernels_give_the_efforts(source, uncompiled):
    """Each joint's friction magnitude by its kernel (uncompiled), at random reactions and
    speed signs, against the efforts of the NumPy path."""
    system = build_system(_model(source))
    joints = [k for k, j in enumerate(system.model.joints) if j.has_friction]
    if not joints:
        pytest.skip("no friction")
    rng = np.random.default_rng(11)
    n = 9
    fs = friction.FrictionSetup(
        joints,
        [system.rows_of(k) for k in joints],
        None,
        rng.choice([-1.0, 0.0, 1.0], (n, len(joints))),
        None,
        None,
        rng.uniform(-2.0, 2.0, (n, system.n_q)),
    )
    x = rng.uniform(-1e3, 1e3, (n, system.n_rows))
    by_numpy = friction.efforts(system, fs, x)
    sets = friction._effort_kernels(system, fs)
    if sets is None:
        pytest.skip("a joint with friction has no kernel")
    mu = np.empty((len(joints), n))
    for kernel, par, rows, cols in sets:
        part = np.empty((len(cols), n))
        kernel(par, x, rows, part)
        mu[cols] = part
    _close(-fs.sign * mu.T, by_numpy)


@pytest.mark.parametrize("source", SHIPPED + HARD + list(SEEDS[:3]), ids=_name)
def test_an_uncompiled_analysis_gives_every_column(source, uncompiled):
    """A whole analysis with every kernel run as plain Python — the fixed point of the
    consistent friction solution included — against the NumPy path."""
    model = _model(source)
    results = []
    for active in (True, False):
        kernels.active = lambda active=active: active  # the fixture restores it
        results.append(_analysis(model))
    _same(*results)


def test_a_type_without_kernels_and_stacked_variants_stay_on_numpy():
    """A cam (no kernels) has none; stacked variants (a field per variant) have none."""
    kinds = {j.kind: j for j in ks.load(ROOT / "mechanisms" / "cam_roller.yaml").joints}
    assert kinds["cam"].kernels(1) is None
    kinds = {j.kind: j for j in ks.load(ROOT / "mechanisms" / "geared_fivebar.yaml").joints}
    pin = kinds["revolute"]
    assert pin.kernel_params(1).shape == (1, 4)
    varied = type(pin)(pin.name, pin.links, pin.where, np.ones((3, 2)), pin.p_j)
    assert varied.kernel_params(1) is None


def test_backend_choice_and_errors(backend, monkeypatch):
    with pytest.raises(ModelError, match="unknown backend 'fortran'; known: numpy, numba"):
        backend("fortran")
    monkeypatch.setattr(kernels, "_chosen", [])
    monkeypatch.setenv("KINETOSTATICS_BACKEND", "cuda")
    with pytest.raises(ModelError, match="environment variable KINETOSTATICS_BACKEND"):
        kernels.backend()
    monkeypatch.setenv("KINETOSTATICS_BACKEND", "")
    assert kernels.backend() == "numpy"

    def missing(module, extra, feature):
        raise MissingPackageError(f"{feature} needs {module}: pip install 'kinetostatics[{extra}]'")

    monkeypatch.setattr(kernels, "require", missing)
    with pytest.raises(MissingPackageError, match=r"kinetostatics\[numba\]"):
        backend("numba")
    assert kernels.backend() == "numpy"  # unchanged by the refusal


# -- compiled --------------------------------------------------------------------------------
@compiling
@pytest.mark.parametrize("source", SHIPPED + HARD + list(SEEDS), ids=_name)
def test_numba_backend_gives_every_column(source, backend):
    """A whole analysis (kinematics, reactions, both friction solutions, checks) on the
    numba backend: every column within 1e-12 of its unit's scale of the default
    backend's, NaN where it is NaN."""
    _both_backends(_model(source), backend)


@compiling
@pytest.mark.slow
def test_numba_backend_on_200_generated_mechanisms(backend):
    """The same on the long run's first 200 generated mechanisms (tests/net)."""
    for seed in MANY:
        _both_backends(_model(seed), backend)


def _both_backends(model, backend) -> None:
    results = []
    for name in ("numpy", "numba"):
        backend(name)
        results.append(_analysis(model))
    _same(*results)


def _analysis(model):
    """``ks.analyze(model)`` (warnings silenced), or the type of the error it refuses with."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return ks.analyze(model)
        except ks.KinetostaticsError as e:
            return type(e)


def _same(a, b) -> None:
    """Two results with the same columns, each within :data:`REL` of its unit's scale (NaN
    where NaN), or the same refusal."""
    if isinstance(a, type):
        assert a is b
        return
    assert_close_on_unit_scales(a, b, REL)


@compiling
def test_numba_backend_compiles_the_kernels_of_a_run(backend):
    """The kernel path is the one taken: every set of the slotting machine has kernels."""
    backend("numba")
    system = build_system(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    assert all(s.kernels() is not None for s in system.sets)
    assert kernels.active()


@compiling
def test_batch_workers_take_the_backend_of_their_parent(backend, monkeypatch):
    """A batch's worker processes run on the backend chosen in the process that starts
    them, whatever their environment says."""
    from kinetostatics.batch import executors

    monkeypatch.setenv("KINETOSTATICS_BACKEND", "numpy")
    backend("numba")
    ex, _, close = executors._open_executor("processes", 1)
    try:
        assert ex.submit(kernels.backend).result(timeout=60) == "numba"
    finally:
        close()


VARIANTS = {  # of the slotting machine
    "same geometry": [{"G5": 300.0 + 20.0 * k, "Q": 900.0 + 50.0 * k} for k in range(4)],
    "other geometry": [{"H": 90.0 + 5.0 * k} for k in range(4)],  # its kernels: NumPy
}


@compiling
@pytest.mark.parametrize("variants", VARIANTS.values(), ids=VARIANTS.keys())
def test_a_batch_gives_the_same_table_on_both_backends(variants, backend, tmp_path):
    """The batch runner on both backends: the same summary table, each number within 1e-12
    of its column's largest."""
    from kinetostatics import batch

    tasks = [batch.Task(str(k), 0, v) for k, v in enumerate(variants)]
    path = str(ROOT / "mechanisms" / "slotting_machine.yaml")
    tables = []
    for name in ("numpy", "numba"):
        backend(name)
        out = tmp_path / name
        batch.run_batch(path, tasks, out, executor="serial", chunk=4, positions=36)
        tables.append((out / "summary.csv").read_text())
    _same_table(*tables)


def _same_table(a: str, b: str) -> None:
    """Two CSV tables with the same header and texts, each numeric column within :data:`REL`
    of its largest |value| in ``b``."""
    import csv
    import io

    ra, rb = list(csv.reader(io.StringIO(a))), list(csv.reader(io.StringIO(b)))
    head = 2 if rb[0][0].startswith("# units") else 1  # the units' line, then the names
    assert ra[:head] == rb[:head] and len(ra) == len(rb)
    for j, name in enumerate(rb[head - 1]):
        xa, xb = [r[j] for r in ra[head:]], [r[j] for r in rb[head:]]
        try:
            fa, fb = [float(v or "nan") for v in xa], [float(v or "nan") for v in xb]
        except ValueError:
            assert xa == xb, name
            continue
        _close(fa, fb)


@compiling
@pytest.mark.parametrize("variants", VARIANTS.values(), ids=VARIANTS.keys())
def test_stacked_variants_give_the_same_columns_on_both_backends(variants, backend):
    """The variants of one topology in one pass (``(V, N)`` poses on the kernels' one axis
    of positions, ψ̈ broadcast over the variants): every column within 1e-12 of its
    unit's scale."""
    from kinetostatics.analysis import vectorised

    path = ROOT / "mechanisms" / "slotting_machine.yaml"
    results = []
    for name in ("numpy", "numba"):
        backend(name)
        models = [ks.load(path, parameters=v) for v in variants]
        results.append(vectorised.as_result(vectorised.analyze_stacked(models)))
    assert results[0]["ram.x"].shape == (4, 360)
    _same(*results)


def test_an_extra_that_is_installed_but_broken_is_not_called_missing(tmp_path, monkeypatch):
    """numba built for another NumPy fails at import: the message says so, with the
    reason, instead of "not installed"."""
    from kinetostatics.base.optional import require

    (tmp_path / "brokenextra.py").write_text('raise ImportError("built for NumPy 1.x")\n')
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(MissingPackageError, match=r"cannot be imported \(built for NumPy 1\.x\)"):
        require("brokenextra", "numba", "the compiled backend")
    with pytest.raises(MissingPackageError, match="which is not installed"):
        require("absentextra", "numba", "the compiled backend")


def _hard_stacks(rng):
    """Stacks of 1×1 to 3×3 blocks with the cases the adjugate treats apart: an exactly
    singular one (its pseudo-inverse), a zero, a NaN and an infinity."""
    out = []
    for n in (1, 2, 3):
        a = rng.uniform(-2.0, 2.0, (300, n, n))
        a[5] = 0.0
        a[5, 0, 0] = 2.0
        a[6] = 0.0
        a[7, -1, 0] = np.nan
        a[8, 0, -1] = np.inf
        out.append(a)
    return out


@pytest.mark.parametrize("compile_them", [False, True], ids=["uncompiled", "compiled"])
def test_the_block_inverses_are_the_same(compile_them, monkeypatch, request):
    """small_inverse's adjugate (blocks up to 3×3) by its kernel against NumPy's, on
    positions-fastest storage as the blocks have it."""
    if compile_them and not HAVE_NUMBA:
        pytest.skip("numba is not installed")
    if not compile_them:
        request.getfixturevalue("uncompiled")
    from kinetostatics.base.arrays import entries_first, entries_last
    from kinetostatics.base.linalg import small_inverse

    for a in _hard_stacks(np.random.default_rng(5)):
        stored = entries_last(np.ascontiguousarray(entries_first(a)))
        monkeypatch.setattr(kernels, "active", lambda: True)
        with np.errstate(all="ignore"):
            mine = small_inverse(stored)
        monkeypatch.setattr(kernels, "active", lambda: False)
        with np.errstate(all="ignore"):
            ref = small_inverse(stored)
        _close(mine, ref)
