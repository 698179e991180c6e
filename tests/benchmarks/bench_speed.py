"""Speed against closed forms: the targets of issue 40, measured in one run.

Each row times what a user calls — ``ks.analyze(model, ...)`` on a model loaded
once, then reading the result columns that the closed form computes — against
a closed-form numpy evaluation of the same columns (``speed_closed_forms.py``),
checked against ``ks.analyze`` to 1e-9 before it is timed so that both sides do
the same work.  The two are timed in turns (interleaved rounds; each sample
repeats a call until it lasts a few milliseconds), in CPU time of the process
(``time.process_time``), and the ratio is the median over the rounds of the
round's generic time / its closed-form time (issue 40's rule).  The last three rows time whole
processes: ``kinetostatics run mechanisms/slotting_machine.yaml --out DIR``
against ``python -c "import numpy"``, with the package's bytecode written by the
first (warm-up) run and loaded after, as Python does by default and numpy's own
install has it, in CPU time of each process (user + system: issue 40's rule, the
target's row) and in wall time (what a user waits, with no target); and, with no
target, in CPU time on a machine that sets ``PYTHONDONTWRITEBYTECODE=1``, where an
editable install compiles every module on every run.

Ratios, not wall times, are the result: both sides run on the same machine
under the same load.  The targets are printed beside them; nothing here is a
test.  ``--quick`` takes fewer repetitions; ``--write`` rewrites the table of
docs/accuracy.md between ``<!-- speed:begin -->`` and ``<!-- speed:end -->``
with a header naming the machine and its load; ``--note TEXT`` adds TEXT there;
``--no-processes`` leaves out the whole-process rows (for a quick look at the
analyses' rows; ``--write`` then keeps the table's process rows as they were).
The process's allocator is held warm (glibc's ``mallopt``, as the design commands set
it: issue 40's rule, "the allocator held warm for both sides" at 36,000 positions;
at 360 it changes nothing); ``--default-allocator`` keeps glibc's defaults, under which
every array of megabytes costs fresh pages from the kernel on both sides.
Where numba is installed, each ratio row also times the same call with the optional
compiled backend (``KINETOSTATICS_BACKEND=numba``, docs/python.md) in the same turns:
the column "ks, numba backend", each run's ratio beside its own target (issue 40's for
that backend, met when met in every run); the default backend's targets are read on the
default (NumPy) column.

    PYTHONPATH=src python tests/benchmarks/bench_speed.py [--quick] [--write] [--note TEXT]
        [--no-processes] [--default-allocator]
"""

from __future__ import annotations

import argparse
import gc
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import speed_closed_forms as cf
from _common import ROOT, hold_allocator, machine, publish

import kinetostatics as ks
from kinetostatics.base import kernels
from tests.oracles import slider_crank_closed_form as oracle

try:
    import numba  # noqa: F401  (the optional compiled backend: its column, where installed)

    HAVE_NUMBA = True
except ImportError:
    HAVE_NUMBA = False

DOC = ROOT / "docs" / "accuracy.md"
BEGIN, END = "<!-- speed:begin -->", "<!-- speed:end -->"
TOLERANCE = 1e-9  # closed form against ks.analyze, per unit (see check)


# ---------------------------------------------------------------------------------------
# timing
# ---------------------------------------------------------------------------------------
def interleaved(fns, repeat: int, sample: float) -> list[list[float]]:
    """CPU time of one call of each of ``fns`` (s) in each of ``repeat`` rounds, timed in
    turns (one list per function, one entry per round).

    Each sample repeats a call until it lasts about ``sample`` seconds (counts set
    from one warm call); the garbage collector is off inside a sample (as timeit)."""
    clock = time.process_time
    counts = []
    for f in fns:
        f()
        t0 = time.perf_counter()
        f()
        counts.append(max(1, round(sample / max(time.perf_counter() - t0, 1e-9))))
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(repeat):
        for f, number, out in zip(fns, counts, times):
            gc.collect()
            gc.disable()
            t0 = clock()
            for _ in range(number):
                f()
            out.append((clock() - t0) / number)
            gc.enable()
    return times


def median(x) -> float:
    return float(np.median(x))


def round_ratio(ours: list[float], ref: list[float]) -> float:
    """The median over the rounds of ours / ref in the same round."""
    return median([a / b for a, b in zip(ours, ref)])


def processes(commands, repeat: int) -> list[tuple[float, float]]:
    """Median CPU time (user + system, issue 40's rule) and median wall time of each
    ``(command, environment)`` as a whole process (s), run in turns."""
    times: list[list[tuple[float, float]]] = [[] for _ in commands]
    for cmd, env in commands:  # warm the file cache
        subprocess.run(cmd, check=True, capture_output=True, env=env)
    for _ in range(repeat):
        for (cmd, env), out in zip(commands, times):
            r0, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True, env=env)
            wall, r1 = time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_CHILDREN)
            out.append((r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime, wall))
    return [
        (float(np.median([c for c, _ in t])), float(np.median([w for _, w in t]))) for t in times
    ]


# ---------------------------------------------------------------------------------------
# the two sides of a row
# ---------------------------------------------------------------------------------------
@dataclass
class Case:
    """One mechanism at ``n`` positions: its model and its closed form."""

    name: str
    n: int
    model: ks.Model
    closed: object  # closed(phi, level) -> dict of columns
    start: float  # crank angle of row 0 (rad)
    sign: float  # direction of the crank

    def grid(self) -> np.ndarray:
        return self.start + self.sign * np.arange(self.n) * (2 * np.pi / self.n)

    def closed_form(self, level: str):
        return lambda: self.closed(self.grid(), level)

    def generic(self, names, **kw):
        def run():
            r = ks.analyze(self.model, **kw)
            return [r[c] for c in names]

        return run


def case(name: str, n: int) -> Case:
    """``mechanisms/<name>.yaml`` with ``analysis.positions: n``, as a user edits the file."""
    path = ROOT / "mechanisms" / f"{name}.yaml"
    text, k = re.subn(r"positions: 360}", f"positions: {n}}}", path.read_text())
    assert k == 1, name
    model = ks.loads(text, str(path))
    a = model.analysis
    speed = model.drivers[0].motion.speed
    if name == "slider_crank":
        p = oracle.SliderCrank()
        closed = lambda phi, level: cf.slider_crank(p, phi, level)  # noqa: E731
    else:
        p = cf.SlottingMachine()
        closed = lambda phi, level: cf.slotting_machine(p, phi, level)  # noqa: E731
    return Case(name, n, model, closed, a.start, float(np.sign(speed)))  # SI: rad


def check(c: Case, level: str, result) -> float:
    """Largest error of the closed form's columns against ``result`` over each unit's scale
    (m, m/s, deg, N, N*m…: the largest |value| of the unit's columns); SystemExit above 1e-9."""
    cols = c.closed(c.grid(), level)
    scale: dict[str, float] = {}
    for name, ref in cols.items():
        u = result.units[name]
        scale[u] = max(scale.get(u, 0.0), float(np.max(np.abs(ref))))
    worst, where = 0.0, ""
    for name, ref in cols.items():
        d = result[name] - ref
        if result.units[name] == "deg":
            d = (d + 180.0) % 360.0 - 180.0
        err = float(np.max(np.abs(d))) / scale[result.units[name]]
        if err > worst:
            worst, where = err, name
    if not worst <= TOLERANCE:
        raise SystemExit(
            f"{c.name} ({level}, {c.n} positions): closed form off by {worst:.1e} "
            f"in {where}: the rows would not time the same work"
        )
    return worst


def check_against_oracle() -> float:
    """The single-pass slider-crank against tests/oracles (kinematics, reactions, eq. 9)."""
    p, phi = oracle.SliderCrank(), np.radians(np.arange(360.0))
    cols = cf.slider_crank(p, phi, "friction")
    q, qd, qdd = oracle.state(p, phi)
    r, eq9 = oracle.reactions(p, phi), oracle.friction_approx_torque_eq9(p, phi)
    mine = [cols[f"{k}.{x}"] for k in ("crank", "rod", "slider") for x in ("x", "y", "theta")]
    mine[2::3] = [np.radians(t) for t in mine[2::3]]
    pairs = [
        (np.stack(mine, -1), q),
        (
            np.stack(
                [
                    cols[f"{k}.{x}"]
                    for k in ("crank", "rod", "slider")
                    for x in ("vx", "vy", "omega")
                ],
                -1,
            ),
            qd,
        ),
        (
            np.stack(
                [
                    cols[f"{k}.{x}"]
                    for k in ("crank", "rod", "slider")
                    for x in ("ax", "ay", "alpha")
                ],
                -1,
            ),
            qdd,
        ),
        (cols["motor.torque"], r["M1"]),
        (cols["B.Fy"], r["F_By"]),
        (cols["O.Fx"], r["F_Ox"]),
        (cols["motor.torque_friction_approx"], eq9),
    ]
    worst = max(float(np.max(np.abs(a - b)) / np.max(np.abs(b))) for a, b in pairs)
    if not worst <= 1e-12:
        raise SystemExit(f"single-pass slider-crank differs from tests/oracles by {worst:.1e}")
    return worst


# ---------------------------------------------------------------------------------------
# the rows
# ---------------------------------------------------------------------------------------
@dataclass
class Row:
    mechanism: str
    what: str
    positions: str
    ours: float  # s
    ref: float  # s
    target: str  # e.g. "≤ 15×"
    error: str = "—"
    ours_label: str = ""
    ref_label: str = ""
    fixed: float | None = None  # s: the same call at 10 positions (the cost that N leaves)
    compiled: float | None = None  # s: the same call with the numba backend (None: no numba)
    rounds: float | None = None  # the median of the rounds' ratios (None: medians' ratio)
    compiled_rounds: float | None = None  # the same for the numba column
    compiled_target: str = "—"  # the compiled backend's target (issue 40's), e.g. "≤ 4×"

    @property
    def ratio(self) -> float:
        return self.ours / self.ref if self.rounds is None else self.rounds

    @property
    def compiled_ratio(self) -> float | None:
        if self.compiled is None:
            return None
        return self.compiled / self.ref if self.compiled_rounds is None else self.compiled_rounds

    def _bound(self, target: str | None = None):
        m = re.match(r"([≤<]) ?([\d.]+)", self.target if target is None else target)
        return (m.group(1), float(m.group(2))) if m else None

    def met(self, compiled: bool = False) -> str:
        bound = self._bound(self.compiled_target if compiled else None)
        ratio = self.compiled_ratio if compiled else self.ratio
        if bound is None or ratio is None:
            return "—"
        how, limit = bound
        return "yes" if (ratio <= limit if how == "≤" else ratio < limit) else "no"

    def budget(self) -> float | None:
        """The time (s) that meets the target: its ratio × the reference side's time."""
        return None if self._bound() is None else self._bound()[1] * self.ref


LEVEL_KW = {
    "kinematics": {"kinematics_only": True},
    "frictionless": {"friction": False},
    "friction": {},
    "fixed point": {},
}
LEVEL_TEXT = {
    "kinematics": "kinematics",
    "frictionless": "frictionless",
    "friction": "full (both friction solutions)",
    "fixed point": "full (both friction solutions), against the closed form with the fixed point",
}
TARGETS = {  # issue 40's (the full row at 360 positions keeps issue 17's: 40 has none)
    ("slider_crank", 360, "kinematics"): "≤ 8×",
    ("slider_crank", 360, "frictionless"): "≤ 8×",
    ("slider_crank", 360, "friction"): "≤ 25×",
    ("slotting_machine", 360, "kinematics"): "≤ 8×",
    ("slotting_machine", 360, "frictionless"): "≤ 8×",
    ("slider_crank", 36_000, "kinematics"): "≤ 10×",
    ("slider_crank", 36_000, "frictionless"): "≤ 10×",
    ("slotting_machine", 36_000, "kinematics"): "≤ 10×",
    ("slotting_machine", 36_000, "frictionless"): "≤ 10×",
    ("slider_crank", 36_000, "fixed point"): "≤ 4×",
}
COMPILED_TARGETS = {  # issue 40's for the compiled backend (none for the full row at 360)
    **{key: "≤ 4×" for key in TARGETS if key[2] in ("kinematics", "frictionless")},
    ("slider_crank", 36_000, "fixed point"): "≤ 2×",
}


def ratio_row(c: Case, level: str, repeat: int, sample: float) -> Row:
    kw = LEVEL_KW[level]
    names = list(c.closed(c.grid()[:3], level))
    if level == "friction":  # the consistent solution has no closed form: read it as well
        names.append("motor.torque_friction")
    err = check(c, level, ks.analyze(c.model, **kw))
    few = case(c.name, 10).generic(names, **kw)  # what does not scale with the positions
    fns = [c.generic(names, **kw), c.closed_form(level), few]
    if HAVE_NUMBA:  # the optional compiled backend, timed in the same turns
        check(c, level, with_backend("numba", lambda: ks.analyze(c.model, **kw))())
        fns.append(with_backend("numba", c.generic(names, **kw)))
    ours, ref, fixed, *compiled = interleaved(fns, repeat, sample)
    return Row(
        c.name,
        LEVEL_TEXT[level],
        f"{c.n:,}",
        median(ours),
        median(ref),
        TARGETS[c.name, c.n, level],
        f"{err:.0e}",
        fixed=median(fixed),
        compiled=median(compiled[0]) if compiled else None,
        rounds=round_ratio(ours, ref),
        compiled_rounds=round_ratio(compiled[0], ref) if compiled else None,
        compiled_target=COMPILED_TARGETS.get((c.name, c.n, level), "—"),
    )


def with_backend(name: str, fn):
    """``fn`` run with the backend ``name`` (base/kernels.py), the default restored after."""

    def run():
        kernels.set_backend(name)
        try:
            return fn()
        finally:
            kernels.set_backend("numpy")

    return run


def rows(quick: bool, log=print, processes_too: bool = True) -> list[Row]:
    repeat, sample = (5, 0.005) if quick else (15, 0.02)
    out = []
    check_against_oracle()
    for name, levels in (
        ("slider_crank", ("kinematics", "frictionless", "friction")),
        ("slotting_machine", ("kinematics", "frictionless")),
    ):
        c = case(name, 360)
        for level in levels:
            out.append(ratio_row(c, level, repeat, sample))
            log(out[-1])
    # 10 positions against 360: what a user calls, every column read
    small, big = case("slotting_machine", 10), case("slotting_machine", 360)

    def every(c):
        def run():
            r = ks.analyze(c.model)
            return [r[n] for n in r.columns]

        return run

    t10, t360 = interleaved([every(small), every(big)], repeat, sample)
    out.append(
        Row(
            "slotting_machine",
            "`ks.analyze(model)`, every column: 10 positions vs 360",
            "10 / 360",
            median(t10),
            median(t360),
            "< 1×",
            ours_label="10",
            ref_label="360",
            rounds=round_ratio(t10, t360),
        )
    )
    log(out[-1])
    for name, levels in (
        ("slider_crank", ("kinematics", "frictionless", "fixed point")),
        ("slotting_machine", ("kinematics", "frictionless")),
    ):
        c = case(name, 36_000)
        for level in levels:
            out.append(ratio_row(c, level, max(3, repeat // 2), sample))
            log(out[-1])
    if not processes_too:
        return out
    # whole processes as a user's run them: Python writes each module's bytecode on the
    # first import (the warm-up run) and loads it after, as numpy's is loaded from its
    # install.  A machine that sets PYTHONDONTWRITEBYTECODE (this benchmark's own may)
    # compiles every module of an editable install on every run instead: that is timed
    # too, as a second row with no target.
    path = os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])
    written = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    script = Path(sys.executable).with_name("kinetostatics")
    run = [str(script)] if script.exists() else [sys.executable, "-m", "kinetostatics.cli"]
    numpy_cmd = [sys.executable, "-c", "import numpy"]
    for what, env, target in (
        ("bytecode written on the first run, as by default", written, "≤ 2.2×"),
        (
            "every module compiled on every run (PYTHONDONTWRITEBYTECODE=1)",
            dict(os.environ, PYTHONDONTWRITEBYTECODE="1"),
            "—",
        ),
    ):
        env = dict(env, PYTHONPATH=path)
        with tempfile.TemporaryDirectory() as d, tempfile.TemporaryDirectory() as fresh:
            cmd = [*run, "run", str(ROOT / "mechanisms" / "slotting_machine.yaml"), "--out", d]
            run_env = env
            if target == "—":  # no bytecode to read either: a copy of the package without
                shutil.copytree(  # any (the standard library and numpy keep theirs)
                    ROOT / "src" / "kinetostatics",
                    Path(fresh) / "kinetostatics",
                    ignore=shutil.ignore_patterns("__pycache__"),
                )
                run_env = dict(env, PYTHONPATH=os.pathsep.join([fresh, path]))
            t_run, t_np = processes([(cmd, run_env), (numpy_cmd, env)], 5 if quick else 11)
        rows = [(f"{what}, CPU time", t_run[0], t_np[0], target)]
        if target != "—":  # what a user waits on this machine (its other core takes a part)
            rows.append((f"{what}, wall time", t_run[1], t_np[1], "—"))
        for words, ours, ref, aim in rows:
            out.append(
                Row(
                    "slotting_machine",
                    f'`kinetostatics run` vs `python -c "import numpy"`, {words}',
                    "360",
                    ours,
                    ref,
                    aim,
                    ours_label="run",
                    ref_label="import numpy",
                )
            )
            log(out[-1])
    return out


# ---------------------------------------------------------------------------------------
# output
# ---------------------------------------------------------------------------------------
def ms(s: float) -> str:
    return f"{s * 1e3:.3g}"


def table(runs: list[list[Row]]) -> str:
    """The table of one or more runs: times from the first, each run's ratio (``a / b``),
    a target met when it is met in every run."""
    lines = [
        "| mechanism | row | positions | ks [ms] | closed form [ms] | ratio | target | met "
        "| ks at the target [ms] | ks at 10 positions [ms] "
        "| ks, numba backend [ms] (ratio; its target: met) | closed-form error |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for same in zip(*runs):
        r = same[0]
        ours = f"{r.ours_label}: {ms(r.ours)}" if r.ours_label else ms(r.ours)
        ref = f"{r.ref_label}: {ms(r.ref)}" if r.ref_label else ms(r.ref)
        budget, fixed, fast = r.budget(), r.fixed, r.compiled
        if fast is not None:
            ratios = " / ".join(f"{x.compiled_ratio:.3g}×" for x in same)
            fast = f"{ms(fast)} ({ratios}"
            if r.compiled_target != "—":
                fast_mets = {x.met(compiled=True) for x in same}
                fast_met = fast_mets.pop() if len(fast_mets) == 1 else "no"
                fast += f"; {r.compiled_target}: {fast_met}"
            fast += ")"
        else:
            fast = "—"
        ratio = " / ".join(f"{x.ratio:.3g}×" for x in same)
        mets = {x.met() for x in same}
        met = mets.pop() if len(mets) == 1 else "no"
        lines.append(
            f"| {r.mechanism} | {r.what} | {r.positions} | {ours} | {ref} | {ratio} | "
            f"{r.target} | {met} | {'—' if budget is None else ms(budget)} | "
            f"{'—' if fixed is None else ms(fixed)} | {fast} | {r.error} |"
        )
    return "\n".join(lines)


def load() -> str:
    try:
        return "load average " + " / ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "load average unknown"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions")
    ap.add_argument("--write", action="store_true", help="rewrite the table in docs/accuracy.md")
    ap.add_argument("--note", default="", help="text added to the conditions (e.g. other jobs)")
    ap.add_argument(
        "--no-processes", action="store_true", help="leave out the whole-process rows of `run`"
    )
    ap.add_argument("--runs", type=int, default=1, help="runs one after the other (ratio a / b)")
    ap.add_argument(
        "--default-allocator",
        action="store_true",
        help="glibc's defaults (fresh pages for every large array) instead of held warm",
    )
    args = ap.parse_args(argv)
    allocator = "glibc's default allocator" if args.default_allocator else hold_allocator()
    runs, said = [], []
    for k in range(args.runs):
        before, start = load(), time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
        t0 = time.perf_counter()
        runs.append(
            rows(
                args.quick,
                processes_too=not args.no_processes,
                log=lambda r: print(
                    f"  {r.mechanism}, {r.what} [{r.positions}]: {r.ratio:.3g}× "
                    f"(target {r.target})",
                    file=sys.stderr,
                ),
            )
        )
        said.append(
            f"run {k + 1}: {start}, {before} (1/5/15 min) before and {load()} after "
            f"({time.perf_counter() - t0:.0f} s{', --quick' if args.quick else ''})"
        )
    conditions = (
        f"**Conditions:** {machine()}; CPU time of the process, the median of the rounds' "
        f"ratios; {allocator}; {'; '.join(said)}{'; ' + args.note if args.note else ''}."
    )
    body = f"{conditions}\n\n{table(runs)}"
    if args.no_processes:  # keep the whole-process rows the table has
        old = re.search(re.escape(BEGIN) + "(.*?)" + re.escape(END), DOC.read_text(), re.S)
        kept = [
            line
            for line in (old.group(1).splitlines() if old else [])
            if line.startswith("| slotting_machine | `kinetostatics run`")
        ]
        body = "\n".join([body, *kept])
    publish(BEGIN, END, body, args.write)


if __name__ == "__main__":
    main()
