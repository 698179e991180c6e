"""Every number of docs/drive.md: the slotting machine's drive (tests/drive/
slotting_machine_drive.yaml) at the motor, rigid and with its flywheel, and the same file
with a smaller motor.

    python docs/scripts/drive_values.py            # print the block
    python docs/scripts/drive_values.py --write    # and replace the block in docs/drive.md
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import kinetostatics as ks  # noqa: E402
from kinetostatics.dynamics.drive import check_lines, size  # noqa: E402

FILE = ROOT / "tests" / "drive" / "slotting_machine_drive.yaml"
BEGIN, END = "<!-- drive_values: begin -->", "<!-- drive_values: end -->"
SMALL = "motor: {rated_torque: 0.9, peak_torque: 3, rated_speed: 1500}"


def _table(d) -> list[str]:
    out = [
        "| | mean torque (N·m) | RMS torque (N·m) | peak \\|torque\\| (N·m) "
        "| mean power (W) | peak \\|power\\| (W) | largest speed (rpm) |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, s in (("driven shaft (crank)", d["shaft"]), ("motor", d["motor"])):
        t, p, w = s["torque"], s["power"], s["speed"]
        out.append(
            f"| {label} | {t['mean']:.5g} | {t['rms']:.5g} | {t['peak']:.5g} | "
            f"{p['mean']:.5g} | {p['peak']:.5g} | {w['max_rpm']:.5g} |"
        )
    return out


def block() -> str:
    text = FILE.read_text(encoding="utf-8")
    lines = []
    for friction in (False, True):
        model = ks.load(FILE)
        spec = type(model.drive)(**{**vars(model.drive), "friction": friction})
        d = size(ks.analyze(model), spec).to_dict()
        lines += [f"*{d['torque']}:*", "", *_table(d), ""]
    d = size(ks.analyze(ks.load(FILE))).to_dict()
    fw = d["flywheel"]
    lines += [
        f"With the flywheel (δ = {fw['delta']:g}, torque {d['torque']}): the motor gives "
        f"{fw['torque']:.5g} N·m, reaches {fw['speed_max_rpm']:.5g} rpm and "
        f"{fw['power_mean']:.5g} W on average; the flywheel on the motor shaft, net of the "
        "machine's inertia, is "
        f"{fw['inertia_motor_net']:.5g} kg·m², of which rotor and reduction give "
        f"{fw['inertia_rotor']:.5g}: {fw['inertia_to_add']:.5g} kg·m² to add.",
        "",
        "The file's motor (`run` prints):",
        "",
        "```text",
        *check_lines(d),
        "```",
        "",
        f"With `{SMALL}` instead, and without the `flywheel:` line:",
        "",
        "```text",
    ]
    small = text.replace(
        "motor: {rated_torque: 1.6, peak_torque: 4.8, rated_speed: 1500, inertia: 0.0008}", SMALL
    )
    rigid = "\n".join(s for s in small.splitlines() if not s.startswith("flywheel:"))
    d = size(ks.analyze(ks.loads(rigid))).to_dict()
    lines += [*check_lines(d), "```", "", "and with the flywheel:", "", "```text"]
    d = size(ks.analyze(ks.loads(small))).to_dict()
    lines += [*check_lines(d), "```"]
    return "\n".join(lines)


if __name__ == "__main__":
    text = block()
    print(text)
    if "--write" in sys.argv:
        doc = ROOT / "docs" / "drive.md"
        old = doc.read_text(encoding="utf-8")
        i, j = old.index(BEGIN) + len(BEGIN), old.index(END)
        doc.write_text(old[:i] + "\n" + text + "\n" + old[j:], encoding="utf-8")
