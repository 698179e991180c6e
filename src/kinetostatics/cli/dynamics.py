"""``kinetostatics simulate``: forward dynamics over time (CSV and a plot), and the
flywheel line of ``run`` when the file asks for a flywheel.

Imports neither scipy nor matplotlib at import time (``run`` stays light).
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import KinetostaticsError

__all__ = ["register", "plot_simulation"]


class _UserError(KinetostaticsError):
    pass


METHODS = ("RK45", "DOP853", "RK23", "Radau", "BDF", "LSODA")


def _option(name: str, value, **bounds) -> None:
    """``--name value`` checked by :func:`~kinetostatics.base.arguments.real_number`
    (finite, within ``bounds``): one line naming the option."""
    from ..base.arguments import real_number

    try:
        real_number(name, value, **bounds)
    except ValueError as exc:
        raise _UserError(f"--{name} {value:g}: {str(exc).split(': ', 1)[1]}") from None


def _check_options(args) -> None:
    """The numbers of the command line, before any work: a time up to the file
    limit's, tolerances in (0, 1], rows within MAX_POSITIONS and the memory
    available, an initial speed within SPEED_RANGE."""
    from ..base.limits import MAGNITUDE, MAX_POSITIONS, SPEED_RANGE
    from ..base.memory import memory_shortfall

    _option("until", args.until, low=0.0, strict_low=True, high=MAGNITUDE["time"][1], why="s")
    _option("rtol", args.rtol, low=0.0, strict_low=True, high=1.0)
    if args.atol is not None:
        _option("atol", args.atol, low=0.0, strict_low=True)
    if not 2 <= args.points <= MAX_POSITIONS:
        raise _UserError(f"--points {args.points}: must be from 2 to {MAX_POSITIONS}")
    if why := memory_shortfall(args.points, "the table"):
        raise _UserError(f"--points {args.points}: {why}")
    if args.speed is not None:
        hi = SPEED_RANGE[1]
        _option("speed", args.speed, low=-hi, high=hi, why="rad/s or m/s")
    if args.angle is not None:
        _option("angle", args.angle)  # its range once the driver is known
    _option("slip", args.slip, low=MAGNITUDE[None][0], high=MAGNITUDE[None][1])


def register(sub) -> None:
    p = sub.add_parser(
        "simulate",
        help="forward dynamics: the motion under the effort drivers (or a flywheel)",
        description="Integrate the motion of the effort: drivers' coordinates (motion: drivers "
        "stay prescribed). Writes DIR/simulation.csv (time, driver angle/speed/"
        "acceleration/torque, equivalent inertia, energies, drivers' work) and "
        "DIR/simulation.png (angle, speed, torque over time).",
    )
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument("--until", type=float, required=True, help="end time, s")
    p.add_argument("--out", default="out", help="output folder (default: out)")
    p.add_argument(
        "--progress",
        action="store_true",
        default=None,
        help="show the simulated time on stderr even when it is not a terminal",
    )
    p.add_argument(
        "--method",
        default="RK45",
        choices=METHODS,
        metavar="METHOD",
        help="scipy solve_ivp method: RK45, DOP853, RK23, Radau, BDF, LSODA (default RK45)",
    )
    p.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance (default 1e-8)")
    p.add_argument(
        "--atol",
        type=float,
        default=None,
        help="absolute tolerance in rad (speeds: × the reference speed); default rtol",
    )
    p.add_argument("--points", type=int, default=501, help="CSV rows (default 501)")
    p.add_argument(
        "--angle",
        type=float,
        default=None,
        help="initial coordinate of the first free driver, deg (m if prismatic); "
        "default analysis.start",
    )
    p.add_argument(
        "--speed",
        type=float,
        default=None,
        help="initial speed of the first free driver, rad/s (m/s); default 0, or "
        "the flywheel design start",
    )
    fr = p.add_mutually_exclusive_group()
    fr.add_argument(
        "--friction",
        dest="friction",
        action="store_true",
        default=None,
        help="friction in the equations of motion (default: when the file has it)",
    )
    fr.add_argument("--no-friction", dest="friction", action="store_false")
    p.add_argument(
        "--flywheel",
        choices=("constant", "motor"),
        default=None,
        help="use the file's flywheel: design: the motion driver is set free with "
        "the designed flywheel (net inertia) under the constant mean moment or "
        "the motor curve M_d[1 + (w_m - w)/(s w_m)], from the position of "
        "maximum stored energy at w_m (friction as in the design unless "
        "--friction/--no-friction)",
    )
    p.add_argument("--slip", type=float, default=0.05, help="motor-curve slip s (default 0.05)")
    p.add_argument("--no-plot", action="store_true", help="write the CSV only")
    p.set_defaults(func=_simulate)


def _simulate(args) -> int:
    import numpy as np

    from ..base.files import make_folder, write_outputs
    from ..dynamics import simulate, speed_fluctuation, write_csv
    from ..outputs.loading import load

    _check_options(args)
    make_folder(Path(args.out), f"--out {args.out}")  # a file there: before the work
    model = load(args.file)
    initial = {}
    mark = None
    inertia = None
    free = [d for d in model.drivers if d.motion is None]
    if args.flywheel:
        from ..dynamics import with_effort
        from ..dynamics.flywheel import design
        from ..model import EffortLaw

        if model.flywheel is None:
            raise _UserError(f"{args.file}: --flywheel needs a flywheel: section in the file")
        fw = design(model)
        m_d = fw.sense * fw.mean_torque
        law = (
            EffortLaw("constant", value=m_d)
            if args.flywheel == "constant"
            else EffortLaw("motor", value=m_d, speed=fw.sense * fw.omega_m, slip=args.slip)
        )
        model = with_effort(model, fw.driver, law)
        inertia = {fw.driver: fw.inertia_net}
        initial[fw.driver] = (fw.at_max, fw.sense * fw.omega_m)
        mark = fw.at_max
        if args.friction is None:  # as the design: frictionless unless it used friction
            args.friction = fw.friction
        free = [d for d in model.drivers if d.motion is None]
        print(
            f"flywheel: {fw.inertia_net:.4g} kg*m^2 on '{fw.driver}', "
            f"{'constant moment' if args.flywheel == 'constant' else 'motor curve'} "
            f"M_d = {fw.mean_torque:.4g} N*m"
        )
    if not free:
        raise _UserError(
            f"{args.file}: drivers: nothing to simulate: every driver prescribes a "
            "motion; give the driver to be set free an effort: (or use --flywheel "
            "with a flywheel: section)"
        )
    if args.angle is not None or args.speed is not None:
        first = free[0].name
        joint = model.joint(free[0].joint)
        psi, w = initial.get(first, (model.analysis.start, 0.0))
        if args.angle is not None:
            _angle_in_range(args.angle, joint.angular)
            psi = np.radians(args.angle) if joint.angular else args.angle
        if args.speed is not None:
            w = args.speed
        initial[first] = (psi, w)
    sim = simulate(
        model,
        args.until,
        initial=initial,
        inertia=inertia,
        friction=args.friction,
        method=args.method,
        rtol=args.rtol,
        atol=args.atol,
        mark=mark,
        progress=sys.stderr.isatty() if args.progress is None else args.progress,
    )
    out = Path(args.out)
    cols, units = sim.table(points=args.points)
    sim_csv = out / "simulation.csv"
    write_outputs(out, f"--out {args.out}", [(sim_csv, lambda p: write_csv(p, cols, units))])
    print(
        f"{model.name}: simulated {sim.t_end:.6g} s ({sim.nfev} evaluations, "
        f"{len(sim.events)} events, {sim.status}) -> {sim_csv}"
    )
    for e in sim.events:
        if e["kind"] == "rest":
            what = (
                "stays at rest (stuck)"
                if e["sense"] == 0
                else f"breaks away {'+' if e['sense'] > 0 else '-'}"
            )
            print(
                f"at rest at t = {e['t']:.6g} s: applied {e['applied']:.4g}, needed "
                f"{e['to_start_positive']:.4g} (+) / {e['to_start_negative']:.4g} (-): {what}"
            )
    for name in sim.dynamics.free_names:
        for key in (f"{name}.angle", f"{name}.position"):
            if key in cols:
                print(
                    f"{name}: final {key.split('.')[-1]} {cols[key][-1]:.6g} {units[key]}, "
                    f"speed {cols[name + '.speed'][-1]:.6g} {units[name + '.speed']}"
                )
    if mark is not None and len(sim.marks) >= 2:
        d = speed_fluctuation(sim, sim.marks[-2], sim.marks[-1])
        print(
            f"last full cycle: omega {d['omega_min']:.5g}..{d['omega_max']:.5g} rad/s, "
            f"mean {d['omega_mean']:.5g}, delta = {d['delta']:.4f}"
        )
    if not args.no_plot:
        png = out / "simulation.png"
        names = sim.dynamics.free_names + [
            n for n in sim.dynamics.names if n not in sim.dynamics.free_names
        ]
        write_outputs(
            out, f"--out {args.out}", [(png, lambda p: plot_simulation(cols, units, names, p))]
        )
        print(f"plot -> {png}")
    return 0


def _angle_in_range(angle: float, angular: bool) -> None:
    """``--angle``: within MAX_TURNS turns of 0 (deg), or a length within MAGNITUDE (m)."""
    from ..base.limits import MAGNITUDE, MAX_TURNS

    hi = 360.0 * MAX_TURNS if angular else MAGNITUDE["length"][1]
    _option("angle", angle, low=-hi, high=hi, why="deg" if angular else "m")


def plot_simulation(cols, units, drivers, path) -> None:
    """Angle, speed and torque of each driver over time (matplotlib imported here)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    t = cols["time"]
    for name in drivers:
        for ax, keys in zip(
            axes,
            (
                (f"{name}.angle", f"{name}.position"),
                (f"{name}.speed",),
                (f"{name}.torque", f"{name}.force"),
            ),
        ):
            key = next((k for k in keys if k in cols), None)
            if key is not None:
                ax.plot(t, cols[key], label=f"{key} [{units[key]}]")
    for ax, label in zip(axes, ("coordinate", "speed", "effort")):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    try:
        fig.savefig(path, dpi=110, format="png")
    finally:
        plt.close(fig)
