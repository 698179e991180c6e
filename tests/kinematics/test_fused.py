"""The fused derivative stage (kinematics/fused.py) and the programs it runs
(base/program.py).

A program is checked against its own lines run over whole arrays (no numba needed: the
executor is plain Python until compiled); the fused stage against the NumPy plan, every
column of an analysis within 1e-12 of its unit's scale on the shipped files, the hard
cases and generated mechanisms (the compiled backend's contract), and its fallback: a
position whose pivot fails its test sends the call to the NumPy plan."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base import kernels, program
from kinetostatics.base.trace import Lines
from kinetostatics.kinematics import fused, plan
from kinetostatics.structure.system import link_poses
from tests.helpers import ROOT, assert_close_on_unit_scales, motion_driven
from tests.net import generate

SHIPPED = [ROOT / "mechanisms" / f"{name}.yaml" for name in motion_driven()]
HARD = sorted((ROOT / "tests" / "hard").glob("*.yaml"))
SEEDS = range(8)
MANY = range(1_000_000, 1_000_200)  # the slow run's: 200 generated mechanisms
KEY_PLAN = "kinematic plan"

try:
    import numba  # noqa: F401

    HAVE_NUMBA = True
except ImportError:
    HAVE_NUMBA = False
compiling = pytest.mark.skipif(not HAVE_NUMBA, reason="numba is not installed")


def _over_arrays(lines: list[str], inputs, rows: int) -> np.ndarray:
    """The lines run as Python over whole arrays (the oracle of a program)."""
    text = "\n".join(
        line.replace("abs(", "np.abs(").replace("max(", "np.maximum(")
        if not line.startswith("    check")
        else "    pass"
        for line in lines
    )
    env = {
        "np": np,
        "sqrt": np.sqrt,
        "positive_or_one": lambda x: np.where(x > 0, x, 1.0),
        "finite_or_inf": lambda x: np.where(np.isfinite(x), x, np.inf),
    }
    exec(f"def f(PE, psi_d, psi_dd, out):\n{text}\n", env)  # noqa: S102  the test's own lines
    out = np.zeros((rows, inputs[0].shape[-1]))
    with np.errstate(all="ignore"):
        env["f"](*inputs, out)
    return out


def _close(out: np.ndarray, ref: np.ndarray) -> None:
    """Each row of ``out`` as ``ref``'s to 1e-14 of that row's largest finite |value|
    (each operation is correctly rounded on both sides: the margin is for a compiler's
    choices only), NaN and ±∞ where ``ref`` has them."""
    for row, (a, b) in enumerate(zip(out, ref)):
        scale = np.max(np.abs(b[np.isfinite(b)]), initial=0.0)
        np.testing.assert_allclose(
            a, b, rtol=0, atol=1e-14 * scale, equal_nan=True, err_msg=f"row {row}"
        )


def _inputs(n: int, rng) -> tuple:
    return rng.normal(size=(3, 5, n)), rng.normal(size=(2, 1, n)), rng.normal(size=(2, 1, n))


def test_a_program_gives_its_lines_numbers():
    """Every operation, constants (negative, repeated), an operand read twice in one
    operation (its register freed once), NaN through max, and blocks of positions with a
    short last one."""
    lines = [
        "    e0 = PE[0, 3]",
        "    e1 = e0 * e0",  # e0 read twice, last time: freed once, not twice
        "    e2 = PE[1, 4]",
        "    e3 = psi_d[1, 0]",
        "    e4 = e2 + e3",
        "    e5 = e4 * (-0.03)",
        "    e6 = e5 / e1",
        "    e7 = -e6",
        "    e8 = abs(e7)",
        "    e9 = psi_dd[0, 0]",
        "    e10 = max(e8, e9)",
        "    e11 = e10 - 2.5",
        "    e12 = 0.0 / e11",
        "    e13 = sqrt(e11)",  # NaN where e11 < 0
        "    e14 = positive_or_one(e13)",  # 1 where NaN or ≤ 0
        "    e15 = e4 / e12",  # ±inf or NaN where e12 is 0
        "    e16 = finite_or_inf(e15)",
        "    e17 = e0 * 0.0",
        "    e18 = e0 * (-0.0)",  # a constant −0 is not the constant 0
        "    e19 = e17 - e18",
        "    e20 = 1.0 / e19",  # +inf where e0 ≥ 0: 0 − (−0) = +0; −inf where e0 < 0
        "    out[9] = e20",
        "    out[0] = e1",
        "    out[7] = e14",
        "    out[8] = e16",
        "    out[2] = e4",
        "    out[3] = e7",
        "    out[4] = e10",
        "    out[5] = (-0.03)",
        "    out[6] = e12",
        "    check e8 <= 1.5",
    ]
    rng = np.random.default_rng(3)
    n = 2 * program.block(12) + 5
    inputs = _inputs(n, rng)
    inputs[2][0, 0, 7] = np.nan  # max(x, NaN) is NaN, as np.maximum
    prog = program.assembled(lines, 10)
    out = np.zeros((10, n))
    with np.errstate(all="ignore"):
        failed = program.execute(
            prog.ops, prog.values, np.empty((prog.registers, program.block(12))), *inputs, out
        )
    ref = _over_arrays(lines, inputs, 10)
    _close(out, ref)
    assert np.isnan(out[4, 7]) and (out[7] == 1.0).any() and np.isinf(out[8]).any()
    assert (out[9] == np.inf).any() and (out[9] == -np.inf).any()
    assert failed == int(np.sum(~(np.abs(ref[3]) <= 1.5)))
    assert prog.registers < 21  # registers are reused


def _random_program(rng, n_ops: int, rows: int) -> list[str]:
    """A straight-line program of ``n_ops`` random operations on recent values, numbers
    (negative, zero, −0 among them) and inputs (some reading one value twice), every
    value read or stored, the stores at random rows."""
    lines, values = [], []
    numbers = ["0.0", "(-0.0)", "1.0", "(-2.5)", "0.125", "3e-07"]

    def pick() -> str:
        if values and rng.random() < 0.8:
            return values[int(rng.integers(max(0, len(values) - 12), len(values)))]
        return str(rng.choice(numbers))

    for k in range(n_ops):
        kind = rng.integers(6)
        if kind == 0 or not values:
            array = rng.choice(["PE", "psi_d", "psi_dd"])
            i, c = (int(rng.integers(3)), int(rng.integers(5))) if array == "PE" else (1, 0)
            expr = f"{array}[{i}, {c}]"
        elif kind == 1:
            a = pick()
            expr = f"{a} {rng.choice(['+', '-', '*', '/'])} {a}"  # one value read twice
        elif kind == 2:
            expr = f"{rng.choice(['abs', 'sqrt', 'positive_or_one', 'finite_or_inf'])}({pick()})"
        elif kind == 3:
            expr = f"max({pick()}, {pick()})"
        elif kind == 4 and values:
            expr = f"-{values[-1]}"
        else:
            expr = f"{pick()} {rng.choice(['+', '-', '*', '/'])} {pick()}"
        if not re.search(r"\be\d+\b|\[", expr):  # numbers alone (the trace folds those)
            expr = f"PE[0, {k % 5}]"
        lines.append(f"    e{k} = {expr}")
        values.append(f"e{k}")
    read = set(re.findall(r"\be\d+\b", " ".join(line.split(" = ", 1)[1] for line in lines)))
    stores = [v for v in values if v not in read or rng.random() < 0.2]
    lines += [f"    out[{int(rng.integers(rows))}] = {v}" for v in stores]
    return lines


@pytest.mark.parametrize("seed", range(12))
def test_random_programs_give_their_lines_numbers(seed):
    """Register reuse against the lines run over whole arrays, on random programs (every
    value stored or read; the same value stored twice keeps its last store, as the lines
    do)."""
    rng = np.random.default_rng(seed)
    lines = _random_program(rng, 120, 16)
    inputs = _inputs(70, rng)
    prog = program.assembled(lines, 16)
    out = np.zeros((16, 70))
    with np.errstate(all="ignore"):
        program.execute(prog.ops, prog.values, np.empty((prog.registers, 32)), *inputs, out)
    _close(out, _over_arrays(lines, inputs, 16))
    assert prog.registers < 120


def test_a_program_refuses_a_line_it_does_not_know():
    with pytest.raises(ValueError, match="not an operation"):
        program.assembled(["    e0 = PE[0, 3]", "    e1 = e0 ** 2", "    out[0] = e1"], 1)
    with pytest.raises(ValueError, match="never read"):
        program.assembled(["    e0 = PE[0, 3]"], 1)


def test_traced_lines_assemble(monkeypatch):
    """Lines as the trace writes them (base/trace.py), numbers simplified away."""
    lines = Lines()
    x, y = lines.value("PE[0, 3]"), lines.value("PE[2, 4]")
    z = (x * 1.0 + 0.0) * y - x / 3.0
    body = [*lines.take(), f"    out[0] = {z.name}"]
    inputs = _inputs(10, np.random.default_rng(1))
    out = np.zeros((1, 10))
    prog = program.assembled(body, 1)
    program.execute(prog.ops, prog.values, np.empty((prog.registers, 4)), *inputs, out)
    _close(out, _over_arrays(body, inputs, 1))


# -- the fused stage against the NumPy plan ------------------------------------------------
@pytest.fixture
def at_once(monkeypatch):
    """The plans made on a system's first analysis, for every system (a triad's too:
    PLANNED_BLOCKS lifted); the default backend back after."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (0, 0))
    monkeypatch.setattr(plan, "PLANNED_BLOCKS", 10**9)
    yield
    kernels.set_backend("numpy")


def _analysis(model, backend: str, **kw):
    kernels.set_backend(backend)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return ks.analyze(model, **kw)
        except ks.KinetostaticsError as e:
            return type(e)


def _both(model, **kw):
    """The analysis on both backends, every column within 1e-12 of its unit's scale;
    the fused plan the compiled one kept (the rates-only program's for the kinematics)."""
    a, b = _analysis(model, "numpy", **kw), _analysis(model, "numba", **kw)
    if isinstance(a, type):
        assert a is b
        return None
    assert_close_on_unit_scales(b, a, 1e-12)
    return b.system.memo.get(fused.RATES_KEY if kw.get("kinematics_only") else fused.KEY)


def _model(source):
    if isinstance(source, int):
        return ks.loads(generate.to_text(generate.generate(source)), f"seed{source}.yaml")
    return ks.load(source)


@compiling
@pytest.mark.parametrize(
    "source", SHIPPED + HARD + list(SEEDS), ids=lambda s: getattr(s, "stem", f"seed{s}")
)
def test_fused_stage_gives_every_column(source, at_once):
    """A whole analysis with the fused stage, and the kinematics alone with its rates-only
    program: every column within 1e-12 of its unit's scale of the NumPy plan's."""
    model = _model(source)
    _both(model)
    _both(model, kinematics_only=True)


@compiling
@pytest.mark.parametrize(
    "source", SHIPPED + HARD + list(SEEDS), ids=lambda s: getattr(s, "stem", f"seed{s}")
)
def test_the_fused_factors_take_the_written_out_transposed_solves(source, at_once, monkeypatch):
    """From TRACED_FROM positions (here all) the stages after the fused stage solve with
    its factors by the plan's written-out transposed solves, as after the NumPy plan:
    every column within 1e-12 of its unit's scale of the NumPy backend's."""
    monkeypatch.setattr(plan, "TRACED_FROM", 0)
    _both(_model(source))


@compiling
@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine"])
def test_the_pairs_mechanisms_take_the_fused_stage(name, at_once, monkeypatch):
    """Over 36,000 positions too (the program's blocks, no chunks): the rates alone by
    their program; with the factors the NumPy plan above FACTORS_UP_TO positions, the
    fused stage at or below it."""
    model = ks.load(ROOT / "mechanisms" / f"{name}.yaml")
    assert _both(model) is not None
    assert _both(model, kinematics_only=True) is not None
    angles = model.analysis.start + np.linspace(0.0, 2 * np.pi, 36_000, endpoint=False)
    assert _both(model, positions=angles, kinematics_only=True) is not None
    runs = []
    real = fused.program.run
    monkeypatch.setattr(fused.program, "run", lambda *a: runs.append(a[-1].shape) or real(*a))
    _both(model, positions=angles, friction=False)
    assert not runs  # the NumPy plan's factors, its transposed solves with them
    monkeypatch.setattr(fused, "FACTORS_UP_TO", len(angles))
    made = _both(model, positions=angles, friction=False)
    assert runs == [(made.program.rows, len(angles))]


@compiling
def test_a_cam_keeps_the_numpy_plan(at_once):
    model = ks.load(ROOT / "mechanisms" / "cam_roller.yaml")
    assert _both(model) is None
    memo = _analysis(model, "numba").system.memo
    assert KEY_PLAN in memo and fused.KEY in memo  # the fused plan tried, not made


@compiling
def test_a_failed_pivot_sends_the_call_to_the_numpy_plan(at_once, monkeypatch, request):
    """With pivot tests no position passes, the program runs, counts its failures and the
    call is the NumPy plan's: the same columns."""
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    made = _both(model)
    checks = made.program.ops[:, 0] == program.CHECK_LE
    assert checks.any()  # the slotting machine's 6×6 blocks are eliminated
    kept = made.program.values.copy()
    made.program.values[checks] = -1.0  # |x| <= -1 fails everywhere
    request.addfinalizer(lambda: made.program.values.__setitem__(slice(None), kept))
    calls = []
    real = fused.program.run

    def counted(*args):
        calls.append(real(*args))
        return calls[-1]

    monkeypatch.setattr(fused.program, "run", counted)
    assert _both(model) is made
    assert calls and all(c > 0 for c in calls)


@compiling
@pytest.mark.slow
def test_fused_stage_on_200_generated_mechanisms(at_once):
    for seed in MANY:
        model = _model(seed)
        _both(model)
        _both(model, kinematics_only=True)


@compiling
def test_a_first_position_off_the_path_does_not_pick_the_row_orders(at_once):
    """The row orders come from the first finite position of the call that makes the plan:
    a first row of NaN (a position the links do not reach) would pick an order whose
    pivot tests fail everywhere, and every later call would take the NumPy plan."""
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    result = _analysis(model, "numpy", kinematics_only=True)
    system, q = result.system, np.array(result.q)
    system.memo.pop(fused.KEY, None)
    off = q.copy()
    off[0] = np.nan
    kernels.set_backend("numba")
    assert fused.fused_plan(system, link_poses(system, off)) is not None
    ones = np.ones((len(q), 1))
    assert fused.fused_derivatives(system, link_poses(system, q), ones, ones) is not None
