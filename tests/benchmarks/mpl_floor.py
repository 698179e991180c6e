"""The floor of a picture command: matplotlib alone, drawing N bare figures of the
pictures' size and resolution, each one axes with four curves of 361 points, a
mathtext label on each axis, a title, a legend and a grid, saved as PNG (Agg).  No
analysis, no layout, no mechanism: what any command that draws N such pictures with
matplotlib pays at least.  ``bench_commands.py`` times it as a whole process against
``import numpy``, as it times ``plot`` (N = 9) and ``report --pdf`` (N = 28).

    python tests/benchmarks/mpl_floor.py N OUT_FOLDER
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

MM = 1 / 25.4
DPI = 110  # the commands' default


def figure(path: Path) -> None:
    fig = Figure(figsize=(150 * MM, 95 * MM), dpi=DPI)
    ax = fig.add_subplot()
    x = np.linspace(0.0, 360.0, 361)
    for k in range(4):
        ax.plot(x, np.sin(np.radians(x) * (k + 1)) * 40.0, label=f"$M_{{{k + 1}}}$")
    ax.set_xlabel(r"crank angle $\varphi_1$ (°)")
    ax.set_ylabel(r"$M_b$ (N·m)")
    ax.set_title("driving torque")
    ax.legend()
    ax.grid(True)
    fig.subplots_adjust(bottom=0.14)  # the axis label inside the picture
    fig.savefig(path, dpi=DPI)


def main(argv: list[str]) -> None:
    n, out = int(argv[0]), Path(argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for k in range(n):
        figure(out / f"floor_{k}.png")


if __name__ == "__main__":
    main(sys.argv[1:])
