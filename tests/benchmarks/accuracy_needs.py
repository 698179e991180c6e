"""Model only what a scene needs: what each request computes, imports and costs.

Four measurements, each beside the behaviour that tests/analysis/test_only_what_is_needed.py
pins (that file asserts the counts; this script adds the wall times):

* *kinematics only*: ``ks.analyze(..., kinematics_only=True)`` against the full
  analysis: result columns, whether loads (``analysis.kinetics``) and load
  events ran, wall time;
* *no friction in the file*: the shipped slider-crank with its friction data
  removed: friction solves run by the default ``ks.analyze`` (counted by
  wrapping ``friction.approximate`` and ``friction.consistent``), wall time
  against the file with friction;
* *one joint's reaction*: columns computed and wall time to read ``O3.Fx``
  from a fresh result, against reading every column;
* *`kinetostatics run`*: the modules a ``run`` of the slotting machine imports
  (in a fresh interpreter) and its wall time with start-up, against ``plot``.

    PYTHONPATH=src python tests/benchmarks/accuracy_needs.py [--quick] [--update]
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
import time

import accuracy_common as ac
from accuracy_common import Table, ms

import kinetostatics as ks
from kinetostatics.analysis import pipeline as analysis
from kinetostatics.kinetics import inverse

SLOTTING = ac.ROOT / "mechanisms" / "slotting_machine.yaml"
HEAVY = ("matplotlib", "scipy.optimize", "scipy.integrate", "scipy.interpolate", "pandas")


class Calls:
    """Counts the calls of module attributes while active: ``Calls(module, "name", ...)``."""

    def __init__(self, module, *names):
        self.module, self.names, self.count = module, names, 0

    def __enter__(self):
        self.saved = {n: getattr(self.module, n) for n in self.names}
        for n, f in self.saved.items():

            def counted(*a, _f=f, **k):
                self.count += 1
                return _f(*a, **k)

            setattr(self.module, n, counted)
        return self

    def __exit__(self, *exc):
        for n, f in self.saved.items():
            setattr(self.module, n, f)


def kinematics_only(timing: bool) -> Table:
    tab = Table(
        [
            "request",
            "result columns",
            "loads assembled (kinetics calls)",
            "event searches",
            "360 positions [ms]",
        ],
        timing={"360 positions [ms]"},
    )
    system = ks.build_system(ks.load(SLOTTING))
    for label, kw in (
        ("ks.analyze(model, kinematics_only=True)", dict(kinematics_only=True)),
        ("ks.analyze(model)", {}),
    ):
        with Calls(analysis, "inverse_dynamics") as kin, Calls(analysis, "load_events") as ev:
            r = ks.analyze(system, **kw)
        tab.add(
            label,
            len(r.columns),
            kin.count,
            ev.count,
            ms(ac.best_of(lambda kw=kw: ks.analyze(system, **kw)) if timing else None),
        )
    return tab


def without_friction(timing: bool) -> Table:
    text = (ac.ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    bare = re.sub(r"(, |\n +)friction: \{[^}]*\}", "", text)
    tab = Table(
        ["file", "has friction", "friction solves run", "result columns", "360 positions [ms]"],
        timing={"360 positions [ms]"},
    )
    for label, src in (("slider_crank.yaml", text), ("slider_crank.yaml, friction removed", bare)):
        system = ks.build_system(ks.loads(src, file="slider_crank.yaml"))
        with Calls(inverse.fr, "approximate", "consistent") as calls:
            r = ks.analyze(system)
        tab.add(
            label,
            "yes" if system.model.has_friction else "no",
            calls.count,
            len(r.columns),
            ms(ac.best_of(lambda system=system: ks.analyze(system)) if timing else None),
        )
    return tab


def one_reaction(timing: bool) -> Table:
    system = ks.build_system(ks.load(SLOTTING))
    tab = Table(
        ["read from a fresh result", "columns computed", "of", "time [ms]"], timing={"time [ms]"}
    )
    for label, names in (
        ("r['O3.Fx']", lambda r: ["O3.Fx"]),
        ("every column", lambda r: list(r.columns)),
    ):
        r = ks.analyze(system)
        for n in names(r):
            r[n]
        computed, total = r.columns.computed, len(r.columns)

        def read(names=names):
            fresh = ks.analyze(system)
            t0 = time.perf_counter()
            for n in names(fresh):
                fresh[n]
            return time.perf_counter() - t0

        t = min(read() for _ in range(ac.REPEAT)) if timing else None
        tab.add(label, computed, total, ms(t))
    return tab


PROBE = """
import sys, time
t0 = time.perf_counter()
from kinetostatics.cli import main
code = main(sys.argv[1:])
wall = time.perf_counter() - t0
mods = sorted(sys.modules)
import json
print(json.dumps({"code": code, "wall": wall, "modules": mods}))
"""


def cli_imports(timing: bool) -> Table:
    tab = Table(
        ["command", "modules imported", *HEAVY, "wall time in the process [ms]"],
        timing={"modules imported", "wall time in the process [ms]"},
    )  # counts vary by install
    with tempfile.TemporaryDirectory() as out:
        for label, argv in (
            ("run", ["run", str(SLOTTING), "--out", out]),
            ("plot", ["plot", str(SLOTTING), "--out", f"{out}/p"]),
        ):
            walls, mods = [], []
            for _ in range(3 if timing else 1):
                p = subprocess.run(
                    [sys.executable, "-c", PROBE, *argv], capture_output=True, text=True, check=True
                )
                info = json.loads(p.stdout.strip().splitlines()[-1])
                walls.append(info["wall"])
                mods = info["modules"]
            heavy = [
                "yes" if any(m == h or m.startswith(h + ".") for m in mods) else "no" for h in HEAVY
            ]
            tab.add(
                f"kinetostatics {label} slotting_machine.yaml",
                len(mods) if timing else ac.PLACEHOLDER,
                *heavy,
                ms(min(walls) if timing else None),
            )
    return tab


def build(timing: bool = True):
    return {
        "needs-kinematics": kinematics_only(timing).markdown(),
        "needs-friction": without_friction(timing).markdown(),
        "needs-reaction": one_reaction(timing).markdown(),
        "needs-imports": cli_imports(timing).markdown(),
    }, None


if __name__ == "__main__":
    ac.main(build)
