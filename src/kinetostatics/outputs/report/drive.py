"""The drive-sizing chapter: the motor and reduction data, the torque, speed and power over
the cycle at the driven shaft and at the motor, the checks of the motor's ratings (rigid
drive, and with the flywheel when the file has one), the four-quadrant picture and the
assumptions.  The numbers are the summary's ``drive`` entry
(:mod:`kinetostatics.dynamics.drive`)."""

from __future__ import annotations

from ...dynamics.motor import LIMIT, RPM, WHAT
from ..lang import tr
from ..plotting.drive import torque_speed
from .blocks import _Heading, _List, _Para, _Table


def _g(v, digits: int = 5) -> str:
    return "—" if v is None else f"{v:.{digits}g}"


ASSUMPTIONS = (
    "signs in the sense of motion of the driven shaft: the motor delivers power where torque "
    "and speed have one sign (motoring), takes it back where they differ (braking)",
    "reduction: T_M = T/(i·η) where the driven shaft takes power, T_M = T·η/i where it gives "
    "power back, plus (J_m + J_r)·i·α for the inertia of rotor and reduction",
    "means and RMS values over one cycle, integrated exactly between the load events; peaks: "
    "the largest values over the positions sampled in the cycle",
    "RMS ≤ rated torque: the cycle is short next to the motor's thermal time constant",
    "with flywheel: the ideal flywheel of the energy method (δ): the motor gives the constant "
    "mean torque, the rotor and the reduction are part of the flywheel and its energy swing "
    "passes the reduction without loss; start-up is not checked",
)


def drive_blocks(d: dict, result, image, lang: str = "en", number: int = 10) -> list:
    """Blocks of chapter ``number`` from the summary entry ``d``; ``image(fig, name,
    caption)`` saves a figure as a block."""

    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    red, md = d["reduction"], d["motor_data"]
    head = [T("quantity"), T("symbol"), T("value"), T("unit")]
    data = [
        [T("driver"), "", d["driver"], ""],
        [T("driving torque from"), "T", T(d["torque"]), ""],
        [T("reduction ratio (motor speed / driven shaft speed)"), "i", _g(red["ratio"]), "1"],
        [T("efficiency of the reduction"), "η", _g(red["efficiency"]), "1"],
        [T("inertia of the reduction at the motor shaft"), "J_r", _g(red["inertia"]), "kg·m²"],
        [T("rotor inertia"), "J_m", _g(md["inertia"]), "kg·m²"],
        [T("rated torque"), "T_rated", _g(md["rated_torque"]), "N·m"],
        [T("peak torque rating"), "T_peak", _g(md["peak_torque"]), "N·m"],
        [
            T("rated speed"),
            "n_rated",
            _g(None if md["rated_speed"] is None else md["rated_speed"] * RPM),
            "rpm",
        ],
    ]
    rows = []
    for label, side in (("driven shaft", d["shaft"]), ("motor", d["motor"])):
        t, p, w = side["torque"], side["power"], side["speed"]
        rows.append(
            [
                T(label),
                _g(t["mean"]),
                _g(t["rms"]),
                _g(t["peak"]),
                _g(p["mean"]),
                _g(p["peak"]),
                _g(w["max_rpm"]),
            ]
        )
    cycle_head = [
        "",
        T("mean torque (N·m)"),
        T("RMS torque (N·m)"),
        T("largest |torque| (N·m)"),
        T("mean power (W)"),
        T("largest |power| (W)"),
        T("largest speed (rpm)"),
    ]
    blocks: list = [
        _Heading(2, T("{n}. Drive sizing", n=number)),
        _Para(
            T(
                "The motor turns the driven shaft through a reduction of ratio i and efficiency "
                "η. Its torque T_M = T/(i·η) where the shaft takes power and T_M = T·η/i where "
                "it gives power back, plus the inertia torque (J_m + J_r)·i·α of rotor and "
                "reduction; its speed i·ω. Torques and speeds are positive in the sense of motion."
            )
        ),
        _Table(head, data, T("Drive: data")),
        _Table(cycle_head, rows, T("Drive: torque, power and speed over the cycle")),
    ]
    fw = d.get("flywheel")
    if fw is not None:
        fw_rows = [
            [T("coefficient of speed fluctuation"), "δ", _g(fw["delta"]), "1"],
            [T("motor torque with the flywheel (constant)"), "T_M", _g(fw["torque"]), "N·m"],
            [T("largest motor speed"), "i·ω_m·(1 + δ/2)", _g(fw["speed_max_rpm"]), "rpm"],
            [T("mean motor power"), "P_M", _g(fw["power_mean"]), "W"],
            [
                T("flywheel on the motor shaft, net"),
                "(J_F − J_e)/i²",
                _g(fw["inertia_motor_net"]),
                "kg·m²",
            ],
            [T("of it in rotor and reduction"), "J_m + J_r", _g(fw["inertia_rotor"]), "kg·m²"],
            [
                T("flywheel still to add on the motor shaft"),
                "ΔJ",
                _g(fw["inertia_to_add"]),
                "kg·m²",
            ],
        ]
        blocks.append(_Table(head, fw_rows, T("Drive with the flywheel (ideal, energy method)")))
    check_rows = []
    for name, c in d["checks"].items():
        how = T("rigid drive") if name == "rigid" else T("with flywheel")
        for key, it in c["items"].items():
            scale, unit = (RPM, "rpm") if key == "speed" else (1.0, "N·m")
            ok = {True: T("ok"), False: T("exceeded"), None: T("not checked")}[it["ok"]]
            check_rows.append(
                [
                    how,
                    T(WHAT[key]) + f" ({unit})",
                    _g(it["value"] * scale),
                    T(LIMIT[key]) + " " + _g(None if it["limit"] is None else it["limit"] * scale),
                    ok,
                ]
            )
    blocks.append(
        _Table(
            [T("check"), T("quantity"), T("value"), T("limit"), T("result")],
            check_rows,
            T("Motor check"),
        )
    )
    verdict = d["verdict"]
    blocks.append(
        _Para(
            T(
                "Verdict ({how}): {verdict}.",
                how=T("with flywheel") if d["verdict_from"] == "flywheel" else T("rigid drive"),
                verdict=T(verdict),
            )
        )
    )
    blocks.append(
        image(
            torque_speed(result, lang=lang),
            "drive",
            T(
                "Four-quadrant torque–speed picture of the motor over the cycle, with the rated "
                "and peak torque envelopes."
            ),
        )
    )
    blocks.append(_Para(T("Assumptions:")))
    blocks.append(_List([T(a) for a in ASSUMPTIONS]))
    return blocks
