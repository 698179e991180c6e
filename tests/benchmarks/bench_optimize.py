"""Design throughput (issue 40): ``optimize`` in designs per CPU-second and the vectorised
batch path in variants per CPU-second, each against a closed form of the same quantity
timed in the same run.

Four rows, on ``mechanisms/slotting_machine.yaml``:

* **optimize, friction** — ``ks.optimize`` varying ``BC_ratio`` (0.8–1.2) and ``L_O2O3``
  (130–170 mm) to minimise ``motor.torque_friction_rms`` at 360 positions (populations of
  12 × 2 = 24 designs, ``--generations`` generations, no local refinement, no progress
  bar): its distinct designs (``len(Optimum.designs)``) over the CPU time of the call;
* **optimize, frictionless** — the same with ``friction=False`` and ``motor.torque_rms``;
* **optimize, a frictionless objective, friction as the file** — ``motor.torque_rms`` with
  ``friction`` left to the file (which has friction): what a search computes when the
  expressions name no quantity with friction;
* **batch, vectorised, friction** — ``analyze_variants`` of ``--variants`` variants of
  ``bench_batch.py``'s sweep (K, H, L_O2O3, BC_ratio, G3, G5, Q) at 72 positions with both
  friction solutions and no flywheel, in this process (one core): the chunk's variants
  over its CPU time.

The closed form is the slotting machine of ``speed_closed_forms.py`` (its kinematics
and frictionless reactions, derived by hand), evaluated for every design at once
(parameters ``(S, 1)``, crank angles ``(S, N)``) and reduced to the RMS of
``motor.torque`` over the rows.  For the optimize rows it computes the torque alone (the
formulas it needs), and ``scipy.optimize.differential_evolution`` runs over it with the
same bounds, population, generations, tolerance and seed (``vectorized=True``,
``updating="deferred"``; designs = the columns it was given).  For the batch row it
computes every column of ``speed_closed_forms.slotting_machine`` (the links' motion, the
reactions, the torque: a batch row reads most of them) for the sweep's variants.  It
solves no friction: the friction rows compare a search that solves both friction
solutions with one that does not, as the issue's measurement did.
Before timing, the closed form is checked against ``ks.analyze`` of the file's design
and against ``speed_closed_forms.slotting_machine`` (the frictionless torque over the rows,
to 1e-9 of its largest value).

Where numba is installed, each of ours is also timed with the optional compiled backend
(``kinetostatics.set_backend("numba")``, docs/python.md) in the same rounds: the columns
"numba backend", read against the issue's compiled targets.

Each round times every candidate once, in turns, by ``time.process_time`` (CPU time, so
that another process's load delays but does not count); a ratio is the median over the
rounds of (closed form's rate / ours) in the same round.  One untimed round warms both.
Nothing here is a test: the targets are issue 40's.

    PYTHONPATH=src python tests/benchmarks/bench_optimize.py [--rounds 5] [--runs 2]
        [--generations 5] [--variants 125] [--write] [--note TEXT]

``--write`` rewrites the table of docs/accuracy.md between ``<!-- throughput:begin -->``
and ``<!-- throughput:end -->`` with the conditions (machine, load before and after).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import warnings
from dataclasses import dataclass
from datetime import datetime, timezone

import numpy as np
import speed_closed_forms as cf
from _common import ROOT, machine, publish

import kinetostatics as ks
from kinetostatics.base import kernels
from kinetostatics.batch import sweeps
from kinetostatics.batch.variants import Template, analyze_variants

BEGIN, END = "<!-- throughput:begin -->", "<!-- throughput:end -->"
PATH = ROOT / "mechanisms" / "slotting_machine.yaml"
VARY = {"BC_ratio": (0.8, 1.2), "L_O2O3": (130.0, 170.0)}
POPSIZE, SEED, TOL = 12, 0, 1e-6  # optimize's defaults
START = np.radians(300.0)  # analysis.start; the crank turns clockwise
from bench_batch import SWEEP  # noqa: E402  the batch benchmark's 7-parameter sweep

try:
    import numba  # noqa: F401  (the optional compiled backend: its column, where installed)

    HAVE_NUMBA = True
except ImportError:
    HAVE_NUMBA = False
# the compiled backend's targets (the closed form's rate over ours at most this)
COMPILED_TARGETS = {"optimize, friction": 6.0, "batch, friction": 10.0}
# name: (target: the closed form's rate over ours at most this, the row's words)
TARGETS = {
    "optimize, friction": (15.0, "`optimize`, 360 positions, friction"),
    "optimize, frictionless": (None, "`optimize`, 360 positions, frictionless"),
    "optimize, file's friction": (
        None,
        "`optimize`, 360 positions, a frictionless objective, friction as the file",
    ),
    "batch, friction": (25.0, "batch, vectorised, 72 positions, friction"),
}


# -- the closed form ----------------------------------------------------------------------
def machines(**file_params) -> cf.SlottingMachine:
    """The closed form's machine(s) from the file's parameters (mm, N), each an array
    ``(S, 1)`` or a number; the others as the file has them."""
    conv = {"K": ("K", 1.0), "H": ("H", 1e-3), "L_O2O3": ("L", 1e-3), "BC_ratio": ("bc_ratio", 1)}
    conv |= {"G3": ("G3", 1.0), "G5": ("G5", 1.0), "Q": ("Q", 1.0)}
    kw = {conv[k][0]: np.asarray(v, dtype=float) * conv[k][1] for k, v in file_params.items()}
    return cf.SlottingMachine(**kw)


def torque(p: cf.SlottingMachine, phi1: np.ndarray) -> np.ndarray:
    """``motor.torque`` of ``speed_closed_forms.slotting_machine`` (its "frictionless"
    level) alone: the same formulas, only those the torque needs, without the other
    columns (``check_closed_form`` compares the two)."""
    r, l3, l4, X, w1 = p.r, p.l3, p.l4, p.X, p.omega1
    c1, s1 = np.cos(phi1), np.sin(phi1)
    Ax, Ay = r * c1 - p.L, r * s1
    Avx, Avy = -r * w1 * s1, r * w1 * c1
    Aax, Aay = -r * w1**2 * c1, -r * w1**2 * s1
    rho2 = Ax * Ax + Ay * Ay
    rho = np.sqrt(rho2)
    u3x, u3y = -Ax / rho, -Ay / rho
    w3 = (Ax * Avy - Ay * Avx) / rho2
    al3 = (Ax * Aay - Ay * Aax) / rho2 - 2 * w3 * (Ax * Avx + Ay * Avy) / rho2
    S3x, S3y = -p.c * u3x, -p.c * u3y
    S3ax = p.c * (al3 * u3y + w3**2 * u3x)
    S3ay = p.c * (-al3 * u3x + w3**2 * u3y)
    Bx, By = l3 * u3x, l3 * u3y
    Bvx, Bvy = -l3 * w3 * u3y, l3 * w3 * u3x
    Bax = -l3 * (al3 * u3y + w3**2 * u3x)
    Bay = l3 * (al3 * u3x - w3**2 * u3y)
    c4 = (X - Bx) / l4
    s4 = np.sqrt(1.0 - c4 * c4)
    w4 = Bvx / (l4 * s4)
    al4 = (Bax - l4 * w4**2 * c4) / (l4 * s4)
    yC = By + l4 * s4
    vC = Bvy + l4 * w4 * c4
    aC = Bay + l4 * (al4 * c4 - w4**2 * s4)
    h = p.half_theta
    bx_top, by_top = l3 * np.cos(h), l3 * np.sin(h)
    down = by_top + np.sqrt(l4 * l4 - (X - bx_top) ** 2) - yC
    v_zero = 1e-9 * abs(w1) * (l3 + p.c)
    Fq = np.where((vC < -v_zero) & (down >= p.band[0] * p.H) & (down <= p.band[1] * p.H), p.Q, 0.0)
    FCy = p.G5 / p.g * (aC + p.g) - Fq
    FCx = FCy * c4 / s4
    m3 = p.G3 / p.g
    N2 = (p.J3 * al3 + m3 * (S3x * (S3ay + p.g) - S3y * S3ax) + (Bx * FCy - By * FCx)) / rho
    return -N2 * ((Ax + p.L) * u3x + Ay * u3y)  # (A − O2) × (−N2 n3), n3 = (−u3y, u3x)


def closed_torque_rms(p: cf.SlottingMachine, n: int, s: int) -> np.ndarray:
    """RMS of ``motor.torque`` over ``n`` rows of a full turn, for ``s`` machines ``p``."""
    phi = START - np.arange(n) * (2 * np.pi / n)
    with np.errstate(invalid="ignore", divide="ignore"):
        m1 = torque(p, np.broadcast_to(phi, (s, n)))
        return np.sqrt(np.mean(m1 * m1, axis=-1))


def closed_objective(n: int):
    """The DE objective over the closed form: x ``(2, S)`` → ``(S,)`` (NaN → a large score)."""

    def f(x: np.ndarray) -> np.ndarray:
        x = np.atleast_2d(x)
        p = machines(BC_ratio=x[0][:, None], L_O2O3=x[1][:, None])
        out = closed_torque_rms(p, n, x.shape[1])
        return np.where(np.isfinite(out), out, 1e18)

    return f


def check_closed_form() -> float:
    """Relative difference of the closed form's torque RMS and ``ks.analyze``'s at the
    file's design (360 positions); refuses to time above 1e-9."""
    r = ks.analyze(ks.load(PATH), friction=False)
    m = r["motor.torque"]
    ours = float(np.sqrt(np.mean(m * m)))
    closed = float(closed_torque_rms(machines(), len(m), 1)[0])
    phi = START - np.arange(len(m)) * (2 * np.pi / len(m))
    full = cf.slotting_machine(machines(), phi, "frictionless")["motor.torque"]
    err = max(abs(closed - ours) / abs(ours), float(np.max(np.abs(full - m))) / np.max(np.abs(m)))
    err = max(err, float(np.max(np.abs(torque(machines(), phi) - full))) / np.max(np.abs(m)))
    if not err <= 1e-9:
        raise SystemExit(f"closed form disagrees with ks.analyze: {closed} vs {ours}")
    return err


# -- the candidates -----------------------------------------------------------------------
def search_ks(friction: bool | None, generations: int, objective: str):
    def run() -> int:
        best = ks.optimize(
            str(PATH),
            VARY,
            objective,
            maxiter=generations,
            popsize=POPSIZE,
            seed=SEED,
            tol=TOL,
            polish=False,
            positions=360,
            friction=friction,
            progress=False,
        )
        return len(best.designs)

    return run


def search_closed(generations: int):
    from scipy.optimize import differential_evolution

    f = closed_objective(360)

    def run() -> int:
        count = [0]

        def counted(x: np.ndarray) -> np.ndarray:
            count[0] += np.atleast_2d(x).shape[1]
            return f(x)

        differential_evolution(
            counted,
            list(VARY.values()),
            maxiter=generations,
            popsize=POPSIZE,
            rng=np.random.default_rng(SEED),
            tol=TOL,
            polish=False,
            updating="deferred",
            vectorized=True,
        )
        return count[0]

    return run


def sweep(n: int) -> list[dict[str, float]]:
    return [ov for _, ov in sweeps.expand(sweeps.load_sweep(SWEEP.format(n=n), "bench"))]


def batch_ks(variants: list[dict[str, float]]):
    tpl = Template.load(PATH)

    def run() -> int:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = analyze_variants(tpl, variants, positions=72, friction=True, flywheel=False)
        return len(rows)

    return run


def batch_closed(variants: list[dict[str, float]]):
    names = list(variants[0])
    cols = {k: np.array([v[k] for v in variants])[:, None] for k in names}

    phi = np.broadcast_to(START - np.arange(72) * (2 * np.pi / 72), (len(variants), 72))

    def run() -> int:  # every column of the closed form: a row reads most of them
        with np.errstate(invalid="ignore", divide="ignore"):
            m1 = cf.slotting_machine(machines(**cols), phi, "frictionless")["motor.torque"]
            return len(np.sqrt(np.mean(m1 * m1, axis=-1)))

    return run


@dataclass
class Row:
    name: str
    ours: list[float]  # per round: designs (variants) per CPU-second
    closed: list[float]
    compiled: list[float]  # ours with the numba backend (empty without numba)

    @property
    def ratios(self) -> list[float]:
        return [c / o for c, o in zip(self.closed, self.ours)]

    @property
    def compiled_ratios(self) -> list[float]:
        return [c / o for c, o in zip(self.closed, self.compiled)]

    @property
    def ratio(self) -> float:
        return statistics.median(self.ratios)

    def met(self) -> str:
        target = TARGETS[self.name][0]
        if target is None:
            return "—"
        return "yes" if self.ratio <= target else "no"

    def compiled_met(self) -> str:
        target = COMPILED_TARGETS.get(self.name)
        if target is None or not self.compiled:
            return "—"
        return "yes" if statistics.median(self.compiled_ratios) <= target else "no"


def with_backend(name: str, fn):
    """``fn`` run with the backend ``name`` (base/kernels.py), NumPy's restored after."""

    def run():
        kernels.set_backend(name)
        try:
            return fn()
        finally:
            kernels.set_backend("numpy")

    return run


def cpu_rate(fn) -> float:
    t0 = time.process_time()
    count = fn()
    return count / (time.process_time() - t0)


def measure(rounds: int, generations: int, n_variants: int, log=print) -> list[Row]:
    variants = sweep(n_variants)
    pairs = {
        "optimize, friction": (
            search_ks(True, generations, "motor.torque_friction_rms"),
            search_closed(generations),
        ),
        "optimize, frictionless": (
            search_ks(False, generations, "motor.torque_rms"),
            search_closed(generations),
        ),
        "optimize, file's friction": (
            search_ks(None, generations, "motor.torque_rms"),
            search_closed(generations),
        ),
        "batch, friction": (batch_ks(variants), batch_closed(variants)),
    }
    for ours, closed in pairs.values():  # warm: imports, the template, scipy, the kernels
        ours(), closed()
        if HAVE_NUMBA:
            with_backend("numba", ours)()
    rows = {name: Row(name, [], [], []) for name in pairs}
    for k in range(rounds):
        for name, (ours, closed) in pairs.items():
            rows[name].ours.append(cpu_rate(ours))
            if HAVE_NUMBA:
                rows[name].compiled.append(cpu_rate(with_backend("numba", ours)))
            # the closed form is fast: repeat it for a measurable CPU time
            reps, t0, count = 0, time.process_time(), 0
            while reps < 3 or time.process_time() - t0 < 0.05:
                count += closed()
                reps += 1
            rows[name].closed.append(count / (time.process_time() - t0))
        log(
            f"round {k + 1}/{rounds}: "
            + ", ".join(f"{n} {r.ours[-1]:.0f}/s vs {r.closed[-1]:.0f}/s" for n, r in rows.items())
        )
    return list(rows.values())


# -- the table ----------------------------------------------------------------------------
def load() -> str:
    try:
        return " / ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def table(runs: list[tuple[str, list[Row]]], args) -> str:
    head = "| measure | target: closed form / ours ≤ |"
    rule = "|---|---|"
    compiled = bool(runs and runs[0][1][0].compiled)
    if compiled:
        head += " target, numba backend |"
        rule += "---|"
    for k in range(len(runs)):
        head += f" run {k + 1}: ours [/CPU-s] | run {k + 1}: closed form [/CPU-s] |"
        head += f" run {k + 1}: ratio (rounds' range) |"
        rule += "---|---|---|"
        if compiled:
            head += f" run {k + 1}: numba backend [/CPU-s], ratio |"
            rule += "---|"
    head += " met |" + (" met, numba |" if compiled else "")
    rule += "---|" + ("---|" if compiled else "")
    lines = [head, rule]
    for i, name in enumerate(TARGETS):
        target, words = TARGETS[name]
        line = f"| {words} | {'—' if target is None else f'{target:g}'} |"
        if compiled:
            ct = COMPILED_TARGETS.get(name)
            line += f" {'—' if ct is None else f'{ct:g}'} |"
        for _, rs in runs:
            r = rs[i]
            lo, hi = min(r.ratios), max(r.ratios)
            line += f" {statistics.median(r.ours):.0f} | {statistics.median(r.closed):.0f} |"
            line += f" {r.ratio:.0f}× ({lo:.0f}–{hi:.0f}) |"
            if compiled:
                line += (
                    f" {statistics.median(r.compiled):.0f}, "
                    f"{statistics.median(r.compiled_ratios):.0f}× |"
                )
        line += f" {', '.join(rs[i].met() for _, rs in runs)} |"
        if compiled:
            line += f" {', '.join(rs[i].compiled_met() for _, rs in runs)} |"
        lines.append(line)
    cond = (
        f"**Conditions:** {machine()}; CPU time of this process (`time.process_time`); "
        f"{args.rounds} rounds per run, {args.generations} generations of "
        f"{POPSIZE} × {len(VARY)} designs per search, {args.variants} variants per batch; "
        + "; ".join(f"run {k + 1}: {what}" for k, (what, _) in enumerate(runs))
        + "."
        + (f" {args.note}" if args.note else "")
    )
    return cond + "\n\n" + "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--runs", type=int, default=1, help="whole measurements (the doc has 2)")
    ap.add_argument("--generations", type=int, default=5, help="of each search")
    ap.add_argument("--variants", type=int, default=125, help="of the batch (one chunk)")
    ap.add_argument("--write", action="store_true", help="rewrite the table in docs/accuracy.md")
    ap.add_argument("--note", default="", help="a sentence for the conditions")
    args = ap.parse_args(argv)
    err = check_closed_form()
    print(f"closed form vs ks.analyze, torque RMS at the file's design: {err:.1e} relative")
    runs = []
    for k in range(args.runs):
        before, t0 = load(), time.perf_counter()
        when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        rs = measure(args.rounds, args.generations, args.variants)
        what = (
            f"{when}, {time.perf_counter() - t0:.0f} s, load average {before} (1/5/15 min) "
            f"before and {load()} after"
        )
        runs.append((what, rs))
        print(f"run {k + 1}: {what}")
    body = table(runs, args)
    publish(BEGIN, END, body, args.write)


if __name__ == "__main__":
    main()
