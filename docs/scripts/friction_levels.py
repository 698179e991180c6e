"""How wrong is the approximate friction solution?  Tables for docs/friction.md.

For each shipped mechanism with friction, all friction data (friction-circle
radii and Coulomb coefficients) are scaled by s; the table gives the largest
difference between the approximate and the consistent driving torque over the
cycle, relative to the largest consistent torque, the crank angle where it
occurs, and the positions by friction status.

    python docs/scripts/friction_levels.py
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import kinetostatics as ks  # noqa: E402

SCALES = (0.01, 0.1, 0.5, 1.0, 2.0, 4.0)


def scaled(name: str, s: float) -> ks.Model:
    text = (ROOT / "mechanisms" / f"{name}.yaml").read_text()

    def mul(m: re.Match) -> str:
        return f"{m.group(1)}{float(m.group(2)) * s:g}"

    text = re.sub(r"(radius: )([\d.]+)", mul, text)
    text = re.sub(r"(coefficient: )([\d.]+)", mul, text)
    return ks.loads(text, file=f"{name}.yaml")


def table(name: str) -> str:
    driver = ks.load(ROOT / "mechanisms" / f"{name}.yaml").drivers[0].name
    rows = [
        "| friction × s | max \\|τ − τ_approx\\| (N·m) | relative to max \\|τ\\| "
        "| at crank angle (°) | status 0 / 1 / 2 / 3 |",
        "|---|---|---|---|---|",
    ]
    for s in SCALES:
        r = ks.analyze(scaled(name, s))
        tau, tau_a = r[f"{driver}.torque_friction"], r[f"{driver}.torque_friction_approx"]
        ok = np.isfinite(tau)
        diff = np.abs(tau - tau_a)
        k = int(np.nanargmax(np.where(ok, diff, -1)))
        counts = np.bincount(r["friction.status"].astype(int), minlength=4)
        rows.append(
            f"| {s:g} | {diff[k]:.3e} | {diff[k] / np.max(np.abs(tau[ok])):.3e} | "
            f"{r['angle'][k]:.0f} | {' / '.join(str(c) for c in counts)} |"
        )
    return "\n".join(rows)


def main() -> None:
    for name in ("slider_crank", "slotting_machine"):
        print(f"### {name}\n")
        print(table(name))
        print()


if __name__ == "__main__":
    main()
