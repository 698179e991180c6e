"""The flywheel chapter: the design as tables (data, result, the energy at the course
positions), its assumptions, the equivalent-moment plot and the energy diagram ΔW–φ."""

from __future__ import annotations

import numpy as np

from ...dynamics.flywheel_texts import assumption_texts
from .. import plotting as pl
from ..lang import tr, tr_unit
from ..plotting.energy import energy_data
from ..summary import ROUND_OFF
from .blocks import _Heading, _List, _Para, _Table


def _g(v, digits: int = 6) -> str:
    return f"{v:.{digits}g}"


def flywheel_blocks(
    fw: dict, design, result, rows, image, lang: str = "en", number: int = 9
) -> list:
    """Blocks of chapter ``number`` from the summary entry ``fw`` (the numbers) and the
    ``design`` (its curve); ``image(fig, name, caption)`` saves a figure as a block."""

    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    je = fw["machine_inertia"]
    deg = tr_unit("deg", lang)
    data = [
        [T("coefficient of speed fluctuation"), "δ", _g(fw["delta"]), "1"],
        [T("driver (crank shaft)"), "", fw["driver"], ""],
        [T("nominal crank speed"), "ω_m", _g(fw["speed"]["omega_m"]), "rad/s"],
        [T("nominal crank speed"), "n", _g(fw["speed"]["rpm"]), "rpm"],
        [
            T("sense of rotation"),
            "",
            T("clockwise" if fw["speed"]["sense"] == "cw" else "counter-clockwise"),
            "",
        ],
        [T("resisting moment from"), "M_r", T(fw["torque"]), ""],
    ]
    if fw.get("ratio") is not None:
        data.append([T("speed ratio motor : crank"), "i", _g(fw["ratio"]), "1"])
    res = [
        [T("work per cycle"), "W", _g(fw["work_per_cycle"]), "J"],
        [T("equivalent driving moment (cycle mean)"), "M_d", _g(fw["mean_torque"]), "N·m"],
        [T("maximum energy swing"), "ΔW_max", _g(fw["energy_swing"]), "J"],
        [T("largest stored energy at"), "φ_max", f"{fw['max_energy_at']:.3f}", deg],
        [T("smallest stored energy at"), "φ_min", f"{fw['min_energy_at']:.3f}", deg],
        [T("machine's equivalent inertia, cycle mean"), "J_e", _g(je["mean"]), "kg·m²"],
        [
            T("machine's equivalent inertia, smallest"),
            "J_e,min",
            _g(je["min"]) if abs(je["min"]) > ROUND_OFF * abs(je["max"]) else "0",
            "kg·m²",
        ],
        [T("machine's equivalent inertia, largest"), "J_e,max", _g(je["max"]), "kg·m²"],
        [
            T("flywheel on the crank shaft, machine inertia neglected"),
            "J_F",
            _g(fw["inertia"]["crank"]),
            "kg·m²",
        ],
        [
            T("flywheel on the crank shaft, less J_e (net)"),
            "J_F − J_e",
            _g(fw["inertia"]["crank_net"]),
            "kg·m²",
        ],
    ]
    if "motor" in fw["inertia"]:
        res += [
            [T("flywheel on the motor shaft"), "J_F / i²", _g(fw["inertia"]["motor"]), "kg·m²"],
            [
                T("flywheel on the motor shaft, net"),
                "(J_F − J_e) / i²",
                _g(fw["inertia"]["motor_net"]),
                "kg·m²",
            ],
        ]
    if fw.get("events_at"):
        res.append([T("load events at"), "φ", ", ".join(f"{a:.3f}" for a in fw["events_at"]), deg])
    head = [T("quantity"), T("symbol"), T("value"), T("unit")]
    blocks: list = [
        _Heading(2, T("{n}. Flywheel", n=number)),
        _Para(
            T(
                "The energy method: J_F = ΔW_max / (ω_m² δ), ΔW(φ) = ∫ (M_d − M_r) dφ from "
                "position 1, with M_r the equivalent resisting moment on the crank (the "
                "balancing moment at the nominal speed, link inertia included) and M_d its "
                "cycle mean. Angles φ are driver angles in [0, 360)°."
            )
        ),
        _Table(head, data, T("Flywheel: data")),
        _Table(head, res, T("Flywheel: result")),
    ]
    e = energy_data(design)
    travel = np.asarray(result["travel"], dtype=float)
    angle = result.columns.get("angle")
    body = []
    scale_m = float(np.max(np.abs(e["resisting"]))) or 1.0
    scale_w = float(np.max(np.abs(e["energy"]))) or 1.0
    for lab, k in rows:
        x = travel[k] % 360.0
        mr = float(np.interp(x, e["phi"], e["resisting"]))
        w = float(np.interp(x, e["phi"], e["energy"]))
        body.append(
            [
                lab,
                f"{float(angle[k]):.5g}" if angle is not None else "",
                f"{x:.5g}",
                "0" if abs(mr) <= ROUND_OFF * scale_m else f"{mr:.5g}",
                f"{fw['mean_torque']:.5g}",
                "0" if abs(w) <= ROUND_OFF * scale_w else f"{w:.5g}",
            ]
        )
    blocks.append(
        _Table(
            [T("pos."), f"φ ({deg})", T("travel (deg)"), "M_r (N·m)", "M_d (N·m)", "ΔW (J)"],
            body,
            T(
                "Equivalent moments and the energy ΔW at the course positions (interpolated on "
                "the design's {n} positions)",
                n=fw["positions"],
            ),
        )
    )
    blocks.append(
        image(
            pl.equivalent_moments(design, result, lang=lang),
            "moments",
            T(
                "Equivalent driving moment M_d (constant) and resisting moment M_r "
                "over the cycle; the shaded areas are the surplus and deficit work."
            ),
        )
    )
    blocks.append(
        image(
            pl.energy_diagram(design, result, lang=lang),
            "energy",
            T("Energy diagram ΔW–φ: its range ΔW_max sizes the flywheel."),
        )
    )
    blocks.append(_Para(T("Assumptions:")))
    texts = assumption_texts(
        design.friction, design.omega_m, design.positions, lambda text: tr(text, lang)
    )
    blocks.append(_List(list(texts)))
    return blocks
