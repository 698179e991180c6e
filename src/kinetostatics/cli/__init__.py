"""The ``kinetostatics`` command: check, run, and the subcommands of ``EXTENSIONS``.

A user error prints one line per problem on stderr (``FILE:LINE:COL:
key.path: message``) and exits with status 2.  ``run`` imports neither
matplotlib nor scipy.
"""

from __future__ import annotations

import argparse
import gc
import sys
import warnings
from pathlib import Path

from ..errors import KinetostaticsError

__all__ = ["main"]

# The cyclic garbage collector's thresholds while the process's own command runs, and
# while a picture command runs in a caller's process (cli/pictures.py); Python's are
# 700, 10, 10.  Importing the package, analysing and drawing make and drop millions of
# small objects (dataclasses, generated functions, matplotlib's artists, paths,
# transforms and font properties), nearly all freed by reference counting as they go; at
# Python's thresholds the collector walked the young ones every 700 allocations and the
# whole heap (NumPy, matplotlib and the analysis included) every 70,000: 10-15 % of the
# CPU time of ``plot`` and ``report``, ~4 % of ``run``'s.  Reference cycles are still
# collected, later: ``report --pdf`` of the slotting machine peaks at ~230 MB instead
# of ~180 MB.
COLLECTOR = (20_000, 20, 20)


def _check(args) -> int:
    from ..outputs.loading import load
    from ..structure.system import build_system

    model = load(args.file)
    system = build_system(model)
    st = system.structure
    from ..analysis import numerical_mobility

    n_num = numerical_mobility(system)
    from ..errors import printable

    print(
        f"{printable(model.name)}: {len(model.moving_links)} moving links, "
        f"{len(model.joints)} joints, "
        f"{len(model.drivers)} drivers"
    )
    _print_units(model)
    print(f"mobility (Grübler–Kutzbach): {st.mobility}")
    print(f"independent loops: {len(st.loops)}")
    for loop in st.loops:
        print(f"  {' - '.join(loop)}")
    print("Assur groups in solve order:")
    for k, plan in enumerate(system.plans, 1):
        g = plan.group
        via = ", ".join(g.joints + g.drivers)
        print(f"  {k}. {g.label} via {via}")
    print(f"mobility (numerical, at the sketched pose): {n_num}")
    if system.motion_drivers and len(system.motion_drivers) == st.mobility:
        from ..analysis.checks import start_checks

        _print_checks(start_checks(system), " (start pose)")
    return 0


def _print_units(model) -> None:
    """The units in force (stdout); a note without units: and the implausible magnitudes
    (stderr), each naming its key."""
    from ..io.plausible import magnitude_warnings, units_line, units_note

    print(units_line(model))
    if note := units_note(model):
        print(f"kinetostatics: {note}", file=sys.stderr)
    for line in magnitude_warnings(model):
        print(f"kinetostatics: warning: {line}", file=sys.stderr)


def _print_checks(checks, label: str = "") -> None:
    """The self-checks in one line; a failed one also as a warning on stderr."""
    print(checks.line().replace("checks:", f"checks{label}:", 1))
    if not checks.ok:
        print(f"kinetostatics: warning: {checks.warning()}", file=sys.stderr)


def _run(args) -> int:
    from ..analysis import analyze
    from ..outputs.loading import load

    model = load(args.file)
    _print_units(model)
    from ..dynamics.stages import cycle_stage

    result = analyze(model, reachable=bool(getattr(args, "reachable", False)))
    # the cycle's stages, then the summary: before anything is written (a failed run
    # writes nothing)
    s = result.summary(cycle_stage(result))
    sized = None  # without bearing, pin or section data (the sizing modules not loaded)
    if model.sizing:
        from ..sizing import sizing_stage

        sized = sizing_stage(result)
    out = Path(args.out)
    from ..base.files import json_text, write_outputs

    writers = [
        (out / "results.csv", result.to_csv),
        (out / "summary.json", lambda path: result.to_json(path, s)),
    ]
    if sized is not None:
        text = json_text(sized.to_json())
        writers.append((out / "sizing.json", lambda path: path.write_text(text, "utf-8")))
    write_outputs(out, f"--out {args.out}", writers)
    from ..errors import printable

    print(
        f"{printable(model.name)}: {len(result)} positions -> {out / 'results.csv'}, "
        f"{out / 'summary.json'}" + (f", {out / 'sizing.json'}" if sized is not None else "")
    )
    _print_motion(s)
    _print_flywheel(s.get("flywheel"))
    if dr := s.get("drive"):
        _print_drive(dr)
    _print_efforts(model, s)
    _print_reactions(result, s)
    if sized is not None:
        _print_sizing(sized)
    _print_checks(result.checks)
    if dr:
        from ..dynamics.drive import drive_warning

        if line := drive_warning(dr):
            print(f"kinetostatics: warning: {line}", file=sys.stderr)
        _drive_picture(result, out)
    return 0


def _print_sizing(sized) -> None:
    """The sizing's line (the least safety factor, the shortest bearing life) and its
    warnings (stderr)."""
    least, parts = sized.least(), []
    if "safety_factor" in least:
        n, link = least["safety_factor"]
        parts.append(f"least safety factor {n:.3g} (Goodman, link {link})")
    if "L10_hours" in least:
        h, joint = least["L10_hours"]
        parts.append(f"shortest bearing life L10 {h:.4g} h (joint {joint})")
    counts = f"{len(sized.bearings)} bearings, {len(sized.pins)} pins, {len(sized.links)} links"
    print(f"sizing: {counts}" + (f"; {'; '.join(parts)}" if parts else ""))
    for line in sized.warnings:
        print(f"kinetostatics: warning: {line}", file=sys.stderr)


def _print_motion(s: dict) -> None:
    """The groups, the outputs, the load events and the singular positions of a summary."""
    print("groups: " + "; ".join(s["structure"]["groups"]))
    for name, o in s["outputs"].items():
        _print_output(name, o, s.get("output") in (name, o["link"]))
    for e in s["events"]:
        print(f"event: {e['load']} {e['switch']} at {e['angle']:.3f}° ({e['condition']})")
    for sp in s["singular_positions"]:
        print(
            f"singular position: {sp['group']} at {sp['angle']:.4f}°, t = {sp['time']:.6g} s "
            f"(condition {sp['condition']:.3g})"
        )


def _print_flywheel(fw: dict | None) -> None:
    """The flywheel's line (summary.json ``flywheel``), if one was designed."""
    if fw and fw.get("undefined"):
        print(f"flywheel for delta = {fw['delta']:g}: {fw['undefined']}")
    elif fw:
        line = (
            f"flywheel for delta = {fw['delta']:g}: J_F = {fw['inertia']['crank']:.4g} "
            f"kg*m^2 on the crank ({fw['inertia']['crank_net']:.4g} less the machine's "
            f"mean {fw['machine_inertia']['mean']:.3g}); energy swing "
            f"{fw['energy_swing']:.4g} J, mean driving torque {fw['mean_torque']:.4g} N*m"
        )
        if fw.get("ratio"):
            line += (
                f"; on the motor shaft (ratio {fw['ratio']:g}): {fw['inertia']['motor']:.4g} kg*m^2"
            )
        print(line)


def _print_efforts(model, s: dict) -> None:
    """The driving efforts' means and peaks (with friction too), the warning of redundant
    constraints and, without singular positions, of implausible torques."""
    import numpy as np

    if s["indeterminate_reactions"]:
        print(
            "warning: redundant constraints: the reactions are the minimum-norm solution "
            "(statically indeterminate)"
        )
    for name, d in s["drivers"].items():
        line = f"{name}: mean {d['mean']:.4g} {d['unit']}, peak {d['peak']:.4g}"
        if "mean_friction" in d and not np.isfinite(d["mean_friction"]):
            line += "; with friction: no consistent solution at any position (self-locking)"
        elif "mean_friction" in d:
            line += (
                f"; with friction mean {d['mean_friction']:.4g}, peak {d['peak_friction']:.4g}"
                f" (approximate mean {d['mean_friction_approx']:.4g})"
            )
        print(line)
    if not s["singular_positions"]:
        from ..io.plausible import torque_warning

        for name, d in s["drivers"].items():
            if line := torque_warning(model, name, d.get("peak", float("nan")), d["unit"]):
                print(f"kinetostatics: warning: {line}", file=sys.stderr)


def _print_reactions(result, s: dict) -> None:
    """The joints' peak reactions, the self-locked rows and zones."""
    import numpy as np

    for name, p in s["reaction_peaks"].items():
        print(f"joint {name}: peak reaction {p['peak']:.4g} N at {p['at']:.4g}")
    if "friction.status" in result.columns:
        st = result["friction.status"]
        locked = int(np.sum(st == 2))
        if locked:
            print(f"self-locking at {locked} positions (friction.status = 2)")
        for z in s.get("self_locking", ()):
            ends = [
                "beyond the run"
                if v is None
                else (f"{v:.9g}°" if z["unit"] == "deg" else f"{v * 1e3:.9g} mm")
                for v in (z["from"], z["to"])
            ]
            print(f"self-locked zone from {ends[0]} to {ends[1]} ({z['rows']} rows)")


def _print_drive(d: dict) -> None:
    """The drive's numbers at the motor and its checks (summary.json ``drive``)."""
    from ..dynamics.drive import check_lines

    red, m = d["reduction"], d["motor"]
    t, p = m["torque"], m["power"]
    print(
        f"drive {d['driver']} (ratio {red['ratio']:g}, efficiency {red['efficiency']:g}; "
        f"{d['torque']}): motor torque mean {t['mean']:.4g}, RMS {t['rms']:.4g}, peak "
        f"{t['peak']:.4g} N*m; speed up to {m['speed']['max_rpm']:.5g} rpm; power mean "
        f"{p['mean']:.4g} W, peak {p['peak']:.4g} W"
    )
    for line in check_lines(d):
        print(line)


def _drive_picture(result, out: Path) -> None:
    """``drive.png``: the four-quadrant torque-speed picture (matplotlib: only with a
    ``drive:`` section)."""
    from ..base.files import write_outputs
    from ..outputs.plotting.drive import torque_speed

    path = out / "drive.png"
    write_outputs(
        out, "drive picture", [(path, lambda p: torque_speed(result).savefig(p, format="png"))]
    )
    print(f"four-quadrant torque-speed picture -> {path}")


def _print_output(name: str, o: dict, named: bool) -> None:
    """One line per output member: stroke or swing, time ratio, limit positions."""
    lo, hi = o["limit_positions"]["min"], o["limit_positions"]["max"]
    what = f"output {name}" if named else name
    if o["kind"] == "slide":
        size = f"stroke {o['stroke'] * 1e3:.4f} mm"
        limits = f"limits at {lo['angle']:.3f}° and {hi['angle']:.3f}°"
    else:
        size = f"swing {o['swing']:.4f}° ({o['link']})"
        limits = (
            f"limits at {lo['angle']:.3f}° ({o['link']} at {lo['theta']:.3f}°) and "
            f"{hi['angle']:.3f}° ({o['link']} at {hi['theta']:.3f}°)"
        )
    print(
        f"{what}: {size}, time ratio K {o['time_ratio']:.4f} (crank angle between the limits "
        f"{o['theta_extreme']:.3f}°), {limits}"
    )


# Modules adding subcommands: each defines ``register(subparsers)`` that adds its
# parsers with ``set_defaults(func=...)``.  They must not import matplotlib or
# scipy at import time (``run`` stays light).
EXTENSIONS: tuple[str, ...] = (
    "kinetostatics.cli.pictures",
    "kinetostatics.cli.dynamics",
    "kinetostatics.cli.batch",
    "kinetostatics.cli.formats",
    "kinetostatics.cli.optimize",
    "kinetostatics.cli.sensitivity",
    "kinetostatics.cli.init",
    "kinetostatics.cli.edit",
)


class _Parser(argparse.ArgumentParser):
    """argparse with a usage error on one line (``kinetostatics run: error: ...``, exit
    2), like every other user error; ``--help`` still prints the usage."""

    def error(self, message: str):
        from ..errors import printable

        self.exit(2, f"{self.prog}: error: {printable(message)} (see {self.prog} --help)\n")


def _escape_unencodable() -> None:
    """A terminal or file whose encoding lacks a character of a name (曲柄 under an ASCII
    locale) shows it escaped (``\\u66f2``) instead of stopping the command."""
    for stream in (sys.stdout, sys.stderr):
        if callable(getattr(stream, "reconfigure", None)):
            stream.reconfigure(errors="backslashreplace")


def _register(sub) -> None:
    """The parsers of this module's commands, ``check`` and ``run``."""
    p = sub.add_parser("check", help="structure: mobility, loops, Assur groups")
    p.add_argument("file", help="mechanism YAML file")
    p.set_defaults(func=_check)
    p = sub.add_parser("run", help="analyse a cycle: results.csv and summary.json")
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument("--out", default="out", help="output folder (default: out)")
    p.add_argument(
        "--reachable",
        action="store_true",
        help="a crank that cannot make a full turn: analyse the reachable range between "
        "its limit positions instead of stopping there",
    )
    p.set_defaults(func=_run)


BLAS_THREADS = ("OPENBLAS_NUM_THREADS",)
"""The variables that set how many threads NumPy's BLAS starts (OpenBLAS, which NumPy's
wheels ship), set to 1 by :func:`main` where the user has not set them."""


def _one_blas_thread() -> None:
    """One BLAS thread for a command, unless the environment says otherwise, set before
    NumPy loads (later it has no effect, and a process that imported NumPy is left as it
    is).  The commands' arrays are stacks of small blocks, which BLAS never splits over
    threads; but OpenBLAS starts one thread per core as NumPy loads, and each spins
    ~0.1 s before it sleeps: ~0.1 s of CPU on every other core for every command (on two
    cores a third of ``run``'s CPU time), and as much again in each process of
    ``--workers`` (which inherit the setting)."""
    if "numpy" in sys.modules:
        return
    import os

    for name in BLAS_THREADS:
        os.environ.setdefault(name, "1")


MALLOC_KEPT = ((-3, 64 << 20), (-1, 256 << 20), (-2, 64 << 20))
"""glibc's ``mallopt`` settings for a design command run as the process's own command
(M_MMAP_THRESHOLD, M_TRIM_THRESHOLD, M_TOP_PAD: the variables ``MALLOC_*_`` set them
alike): arrays up to 64 MB from the heap, and the heap kept after a free.  A population
or a chunk of variants makes and drops arrays of megabytes at every generation; glibc
gives such arrays fresh pages from the kernel and takes them back, so that every
generation paid its page faults again (``optimize`` of the slotting machine at 360
positions: ~12 % less CPU time with them kept)."""


def _memory_kept(args) -> None:
    """:data:`MALLOC_KEPT` for a command that asks for it (``keeps_memory``) when it is the
    process's own (``args.program``) and the user set no ``MALLOC_`` variable; nothing
    where the C library is not glibc.  The worker processes a command forks inherit it."""
    import os

    if not (args.program and getattr(args, "keeps_memory", False)):
        return
    if any(name.startswith("MALLOC_") for name in os.environ):
        return
    import ctypes

    try:
        mallopt = ctypes.CDLL("libc.so.6").mallopt
    except (OSError, AttributeError):  # not glibc: its allocator as it is
        return
    for param, value in MALLOC_KEPT:
        mallopt(param, value)


def main(argv: list[str] | None = None) -> int:
    """The ``kinetostatics`` command: its exit code.  Without ``argv`` it is the process's
    own command (the arguments from ``sys.argv``): the collector runs at
    :data:`COLLECTOR`'s thresholds from the start to the end, and the heap is frozen once
    the command is done, so that neither giving the collector its thresholds back nor
    Python's collection at exit walks the objects of a process about to end (~0.2 s of
    ``plot``).  Called with ``argv`` (tests, a caller's process), none of this happens
    (a picture command's thresholds are given back after it, ``cli/pictures.py``)."""
    import importlib

    program = argv is None
    if program:  # the process's own: at most :data:`COLLECTOR`'s collections to its end
        gc.set_threshold(*COLLECTOR)
    _one_blas_thread()
    _escape_unencodable()
    parser = _Parser(
        prog="kinetostatics",
        description="Kinetostatic analysis of planar linkages described in YAML.",
    )
    from ..base.version import VERSION

    parser.add_argument("--version", action="version", version=f"kinetostatics {VERSION}")
    sub = parser.add_subparsers(dest="command", required=True)
    _register(sub)
    argv = sys.argv[1:] if argv is None else list(argv)
    alone = argv[:1] in (["check"], ["run"])  # their parsers alone: ~6 ms less for each
    for name in () if alone else EXTENSIONS:
        importlib.import_module(name).register(sub)
    args = parser.parse_args(argv)
    args.program = program
    _memory_kept(args)

    def one_line(message, category, filename, lineno, file=None, line=None):
        from ..errors import printable

        print(f"kinetostatics: warning: {printable(str(message))}", file=sys.stderr)

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("default")
            # the interpreter's, not the command's: a file an interrupted import was reading
            warnings.simplefilter("ignore", ResourceWarning)
            warnings.showwarning = one_line
            code = args.func(args)
            sys.stdout.flush()  # a closed pipe shows here, not at exit
            if program:  # the process ends: no collection need walk what it made
                gc.freeze()
            return code
    except KinetostaticsError as exc:
        from ..errors import printable

        file = printable(str(getattr(args, "file", "")))
        for line in str(exc).splitlines():
            line = printable(line)  # no control characters reach the terminal
            prefixed = file and line.startswith(file)
            print(line if prefixed else f"kinetostatics: {line}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C: one line; each file is whole or absent (write_whole)
        sys.stdout.flush()
        print(f"kinetostatics: {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (`kinetostatics check FILE | head`)
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no error at exit
        return 0


if __name__ == "__main__":
    sys.exit(main())
