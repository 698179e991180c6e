"""``kinetostatics init``: the course-design templates (docs/templates.md).

Every row of every template is written, passes ``check`` and keeps its data; the
refusals are one line with exit 2.  Each template's kinematics and frictionless
reactions are compared, at several crank angles, with closed forms written
independently (tests/oracles/course_templates.py, tests/oracles/slider_crank_closed_form.py):
the dimensions are synthesised here from the row's data by the textbook's formulas, the
positions solved by hand, the rates by differentiating the loop equations, the reactions
from the Newton–Euler equations of each Assur group, solved group by group.  Each
quantity agrees to 1e-12 of the largest value of its unit; the stroke, K and the limit
positions of summary.json to the synthesis.  Row I of each template runs in the default
run, the other rows in the slow one.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.io.templates import NAMES, TemplateError, load_template, render, templates
from tests.oracles import slider_crank_closed_form as sc
from tests.oracles.course_templates import (
    Body,
    Motion,
    Unknown,
    crank,
    guide_bar,
    on_link,
    rrp,
    rrr,
    solve_group,
)

ROOT = Path(__file__).resolve().parents[2]
ALL = [(t.name, key) for t in templates() for key in t.rows]
CASES = [
    pytest.param(name, key, marks=[] if key == "I" else [pytest.mark.slow], id=f"{name}-{key}")
    for name, key in ALL
]
TRAVEL = (7, 52, 101, 149, 203, 257, 311)  # grid rows (degrees of crank travel) compared


def write(tmp_path, name, row=None) -> Path:
    out = tmp_path / f"{name}-{row or 'I'}.yaml"
    argv = ["init", name, "--out", str(out)] + (["--data", row] if row else [])
    assert main(argv) == 0
    return out


# -- the command ----------------------------------------------------------------------------
def test_the_template_files_are_the_listed_ones():
    on_disk = {p.stem for p in (ROOT / "src" / "kinetostatics" / "templates").glob("*.yaml")}
    assert on_disk == set(NAMES)
    assert "templates/*.yaml" in (ROOT / "pyproject.toml").read_text()  # the wheel has them
    for t in templates():  # every row gives every data line (none left at row I's value)
        assert len({tuple(row) for row in t.rows.values()}) == 1, t.name
        assert list(t.rows)[:3] == ["I", "II", "III"], t.name


def test_list_names_every_template_its_chinese_name_and_rows(capsys):
    assert main(["init", "--list"]) == 0
    out = capsys.readouterr().out
    for zh, name in [("插床", "slotting"), ("牛头刨床", "shaper"), ("压床", "press"),
                     ("颚式破碎机", "jaw_crusher"), ("锯床", "saw")]:  # fmt: skip
        line = next(line for line in out.splitlines() if line.startswith(name + " "))
        assert f"({zh}); rows I, II, III" in line


@pytest.mark.parametrize("name, row", ALL, ids=[f"{n}-{r}" for n, r in ALL])
def test_every_row_is_written_with_its_data_and_passes_check(tmp_path, capsys, name, row):
    path = write(tmp_path, name, row)
    assert f"row {row} -> {path}" in capsys.readouterr().out
    text = path.read_text(encoding="utf-8")
    assert "template:" not in text and f"(row {row})" in text
    assert main(["check", str(path)]) == 0
    assert "mobility (Grübler–Kutzbach): 1" in capsys.readouterr().out
    data = load_template(name).rows[row]
    params = ks.load(path).parameters
    for key, value in data.items():
        assert params[key] == value, key
    # the comments stay, the table of rows follows with this row marked
    assert text.count("# ") > 30 and f"kinetostatics init {name} --data ROW" in text
    marked = [line for line in text.splitlines() if line.endswith("<-")]
    assert len(marked) == 1 and marked[0].split()[1] == row


def test_chinese_name_and_other_spellings_of_a_row(tmp_path):
    texts = []
    for k, (name, row) in enumerate([("牛头刨床", "Ⅱ"), ("shaper", "2"), ("shaper", "ii")]):
        (tmp_path / str(k)).mkdir()
        texts.append(write(tmp_path / str(k), name, row).read_text(encoding="utf-8"))
    assert texts[0] == texts[1] == texts[2] == render(load_template("shaper"), "II")
    assert "(row I)" in render(load_template("插床"))  # row I by default


@pytest.mark.parametrize(
    "argv, words",
    [
        (["init", "shapr", "--out", "x.yaml"], "no template 'shapr' (did you mean 'shaper'?)"),
        (["init", "shaper", "--data", "IV", "--out", "x.yaml"], "--data IV: template shaper"),
        (["init", "--out", "x.yaml"], "name a template and --out FILE"),
        (["init", "press"], "name a template and --out FILE"),
    ],
)
def test_an_unknown_template_or_row_is_one_line_with_the_choices(tmp_path, capsys, argv, words):
    argv = [a if a != "x.yaml" else str(tmp_path / a) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1
    assert "slotting (插床)" in err or "rows are I, II, III" in err or "init --list" in err
    assert not (tmp_path / "x.yaml").exists()


def test_an_existing_file_is_not_overwritten(tmp_path, capsys):
    out = tmp_path / "mine.yaml"
    out.write_text("my work\n")
    assert main(["init", "slotting", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"kinetostatics: --out {out}: the file exists; init does not overwrite it"
    assert out.read_text() == "my work\n"
    assert main(["init", "slotting", "--out", str(tmp_path)]) == 2  # a folder
    assert "is a folder, not a file" in capsys.readouterr().err


def test_template_error_is_a_user_error():
    with pytest.raises(TemplateError, match="its rows are I, II, III"):
        load_template("saw").row("V")


# -- the closed forms -----------------------------------------------------------------------
def run(tmp_path, path):
    """``kinetostatics run``: results.csv as {column: array}, its units, and summary.json."""
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 0
    with open(out / "results.csv", encoding="utf-8") as f:
        units = f.readline().removeprefix("# units: ").strip().split(",")
        reader = csv.reader(f)
        head = next(reader)
        rows = [[float(x) if x else math.nan for x in r] for r in reader]
    table = dict(zip(head, np.array(rows).T))
    return table, dict(zip(head, units)), json.loads((out / "summary.json").read_text())


def point(name, m: Motion) -> dict:
    z, v, a = m.z, m.v, m.a
    keys = ("x", "y", "vx", "vy", "ax", "ay")
    return {
        f"{name}.{k}": x for k, x in zip(keys, (z.real, z.imag, v.real, v.imag, a.real, a.imag))
    }


def link(name, theta, omega, alpha) -> dict:
    return {f"{name}.theta": math.degrees(theta), f"{name}.omega": omega, f"{name}.alpha": alpha}


def force(name, F) -> dict:
    return {f"{name}.Fx": F.real, f"{name}.Fy": F.imag}


def pin(name, body, at, sign=1.0, other=None):
    on = ((body, sign),) if other is None else ((body, sign), (other, -sign))
    return Unknown(name, "pin", on, at)


def compare(table, units, rows, expected: list[dict]):
    """Each column at the rows against its closed form, to 1e-12 of the largest value of
    its unit among the compared columns; angles (deg) modulo 360."""
    names = list(expected[0])
    got = {c: table[c][rows] for c in names}
    want = {c: np.array([e[c] for e in expected]) for c in names}
    scale: dict[str, float] = {}
    for c in names:
        scale[units[c]] = max(scale.get(units[c], 0.0), float(np.max(np.abs(want[c]))))
    worst = {}
    for c in names:
        d = got[c] - want[c]
        if units[c] == "deg":
            d = (d + 180.0) % 360.0 - 180.0
        worst[c] = float(np.max(np.abs(d))) / scale[units[c]]
    bad = {c: w for c, w in worst.items() if not w <= 1e-12}
    assert not bad, bad


def at_travel(table, degrees):
    rows = [int(np.argmin(np.abs(table["travel"] - k))) for k in degrees]
    assert np.allclose(table["travel"][rows], degrees, atol=1e-9)
    return rows


def limits(summary, key):
    lim = summary["outputs"][key]["limit_positions"]
    return sorted(lim[k]["angle"] % 360.0 for k in ("min", "max"))


def closed_form(name, row, table, summary):
    """The template's closed form: the compared rows and the expected columns there; each
    also checks the summary's stroke or swing, K and limit positions."""
    return {
        "slotting": slotting,
        "shaper": shaper,
        "press": press,
        "jaw_crusher": jaw_crusher,
        "saw": saw,
    }[name](row, table, summary)


@pytest.mark.parametrize("name, row", CASES)
def test_kinematics_and_reactions_match_the_closed_form(tmp_path, name, row):
    path = write(tmp_path, name, row)
    table, units, summary = run(tmp_path, path)
    data = load_template(name).rows[row]
    rows, expected = closed_form(name, data, table, summary)
    compare(table, units, rows, expected)
    # the course positions 1 ... 12 are rows: every 30° of travel from the first
    at_travel(table, range(0, 360, 30))


def _rows_and_angles(table, extra_angle=None):
    rows = at_travel(table, TRAVEL)
    if extra_angle is not None:  # the other limit position, added by analysis.at
        d = np.abs((table["angle"] - extra_angle + 180.0) % 360.0 - 180.0)
        k = int(np.argmin(d))
        assert d[k] < 1e-9
        rows.append(k)
    return rows, [math.radians(a) for a in table["angle"][rows]]


def _band(d, lo, hi, size):
    """Whether the travel d is in the band [lo, hi]; the compared rows keep away from
    its edges (where the program and this file could round differently)."""
    assert min(abs(d - lo), abs(d - hi)) > 1e-6 * size
    return lo <= d <= hi


def slotting(p, table, summary):
    """Crank O2A (O2 at (−L, 0)), guide bar O3B through the block A, rod BC, ram C on
    the vertical line x = X; θ = 180(K − 1)/(K + 1), O2A = L·sin(θ/2),
    O3B = (H/2)/sin(θ/2), X = O3B·(1 + cos(θ/2))/2; the ram at its top with the bar at
    +θ/2 (crank at 270° + θ/2), at its bottom with the bar at −θ/2 (crank 90° − θ/2)."""
    g = 10.0
    K, H, L = p["K"], p["H"] * 1e-3, p["L_O2O3"] * 1e-3
    th = math.pi * (K - 1) / (K + 1)
    r, l3 = L * math.sin(th / 2), H / 2 / math.sin(th / 2)
    l4, X = p["BC_ratio"] * l3, l3 * (1 + math.cos(th / 2)) / 2
    c, d = p["c"] * 1e-3, p["d"] * 1e-3
    m3, m5, J3, Q = p["G3"] / g, p["G5"] / g, p["J_S3"], p["Q"]
    w1 = -p["n1"] * math.pi / 30
    top, bottom = 270 + math.degrees(th) / 2, 90 - math.degrees(th) / 2
    out = summary["outputs"]["guide"]
    assert out["stroke"] == pytest.approx(H, rel=1e-12)
    assert out["time_ratio"] == pytest.approx(K, rel=1e-9)
    np.testing.assert_allclose(limits(summary, "guide"), sorted([top, bottom]), atol=1e-7)
    B_top = l3 * np.exp(1j * th / 2)
    y_top = B_top.imag + math.sqrt(l4**2 - (X - B_top.real) ** 2)
    rows, angles = _rows_and_angles(table, bottom)
    expected, on = [], []
    for phi in angles:
        A = crank(-L, r, phi, w1)
        bar = guide_bar(0j, A)
        th3 = bar.theta + math.pi  # the bar's x axis points from O3 away from A, to B
        B = on_link(Motion(0j), bar.omega, bar.alpha, l3 * np.exp(1j * th3))
        S3 = on_link(Motion(0j), bar.omega, bar.alpha, -c * np.exp(1j * th3))
        rod = rrp(B, l4, X + 0j, 1j, +1)  # C above B
        C = rod.C
        cutting = C.v.imag < -1e-9 * abs(w1) * L and _band(y_top - C.z.imag, 0.05 * H, 0.95 * H, H)
        ram = Body(m5, 0.0, C.z, C.a, forces=[(-1j * g * m5, C.z), (1j * Q * cutting, C.z + d)])
        g3 = solve_group(
            {"rod": Body(), "ram": ram},
            [pin("B", "rod", B.z), pin("C", "ram", C.z, other="rod"),
             Unknown("guide.N", "normal", (("ram", 1),), C.z, 1j * 1j),
             Unknown("guide.M", "couple", (("ram", 1),))],
        )  # fmt: skip
        bar_body = Body(m3, J3, S3.z, S3.a, bar.alpha, [(-1j * g * m3, S3.z), (-g3["B"], B.z)])
        n = 1j * np.exp(1j * th3)  # the slot's axis (the bar's x) turned +90°
        g2 = solve_group(
            {"block": Body(S=A.z), "bar": bar_body},
            [pin("A", "block", A.z),
             Unknown("slot.N", "normal", (("block", 1), ("bar", -1)), A.z, n),
             Unknown("slot.M", "couple", (("block", 1), ("bar", -1))),
             pin("O3", "bar", 0j)],
        )  # fmt: skip
        g1 = solve_group(
            {"crank": Body(S=-L, forces=[(-g2["A"], A.z)])},
            [pin("O2", "crank", -L + 0j), Unknown("motor.torque", "couple", (("crank", 1),))],
        )
        e = {**point("crank.A", A), **link("bar", th3, bar.omega, bar.alpha)}
        e |= point("bar.B", B) | point("bar.S3", S3) | link("rod", rod.phi1, rod.omega1, rod.alpha1)
        e |= point("ram.C", C) | point("ram.tool", Motion(C.z + d, C.v, C.a))
        for k in ("B", "C", "A", "O3", "O2"):
            e |= force(k, (g1 | g2 | g3)[k])
        e |= {k: (g1 | g2 | g3)[k] for k in ("guide.N", "guide.M", "slot.N", "slot.M")}
        e["motor.torque"] = g1["motor.torque"]
        expected.append(e)
        on.append(cutting)
    assert any(on) and not all(on)  # the rows compared have the load on and off
    return rows, expected


def shaper(p, table, summary):
    """Crank O2A (O2 at (0, L) above O4), guide bar O4B through the block A, link BC,
    ram C on the line y = Y; θ = 2·asin(O2A/L), H = 2·O4B·sin(θ/2),
    Y = O4B·(1 + cos(θ/2))/2; the ram's limits with the crank at 360° − θ/2 (right)
    and 180° + θ/2 (left)."""
    g = 9.81
    L, r, l4 = p["L_O2O4"] * 1e-3, p["L_O2A"] * 1e-3, p["L_O4B"] * 1e-3
    l5, s4 = p["BC_ratio"] * l4, p["S4_ratio"] * l4
    half = math.asin(r / L)
    H, Y = 2 * l4 * math.sin(half), l4 * (1 + math.cos(half)) / 2
    K = (math.pi + 2 * half) / (math.pi - 2 * half)
    m4, m6, J4, P = p["G4"] / g, p["G6"] / g, p["J_S4"], p["P"]
    to_S6 = (-p["x_S6"] + 1j * p["y_S6"]) * 1e-3
    to_tool = (-p["x_S6"] - 1j * p["y_P"]) * 1e-3
    w2 = p["n2"] * math.pi / 30
    right, left = 360 - math.degrees(half), 180 + math.degrees(half)
    out = summary["outputs"]["guide"]
    assert out["stroke"] == pytest.approx(H, rel=1e-12)
    assert out["time_ratio"] == pytest.approx(K, rel=1e-9)
    np.testing.assert_allclose(limits(summary, "guide"), sorted([left, right]), atol=1e-7)
    x_right = l4 * math.sin(half) - math.sqrt(l5**2 - (Y - l4 * math.cos(half)) ** 2)
    rows, angles = _rows_and_angles(table, left)
    expected, on = [], []
    for phi in angles:
        A = crank(1j * L, r, phi, w2)
        bar = guide_bar(0j, A)
        B = on_link(Motion(0j), bar.omega, bar.alpha, l4 * np.exp(1j * bar.theta))
        S4 = on_link(Motion(0j), bar.omega, bar.alpha, s4 * np.exp(1j * bar.theta))
        five = rrp(B, l5, 1j * Y, 1 + 0j, -1)  # C left of B
        C = five.C
        S6, tool = Motion(C.z + to_S6, C.v, C.a), Motion(C.z + to_tool, C.v, C.a)
        cutting = C.v.real < -1e-9 * w2 * L and _band(x_right - C.z.real, 0.05 * H, 0.95 * H, H)
        ram = Body(m6, 0.0, S6.z, S6.a, forces=[(-1j * g * m6, S6.z), (P * cutting, tool.z)])
        g3 = solve_group(
            {"link": Body(), "ram": ram},
            [pin("B", "link", B.z), pin("C", "ram", C.z, other="link"),
             Unknown("guide.N", "normal", (("ram", 1),), C.z, 1j),
             Unknown("guide.M", "couple", (("ram", 1),))],
        )  # fmt: skip
        bar_body = Body(m4, J4, S4.z, S4.a, bar.alpha, [(-1j * g * m4, S4.z), (-g3["B"], B.z)])
        g2 = solve_group(
            {"block": Body(S=A.z), "bar": bar_body},
            [pin("A", "block", A.z),
             Unknown("slot.N", "normal", (("block", 1), ("bar", -1)), A.z,
                     1j * np.exp(1j * bar.theta)),
             Unknown("slot.M", "couple", (("block", 1), ("bar", -1))),
             pin("O4", "bar", 0j)],
        )  # fmt: skip
        g1 = solve_group(
            {"crank": Body(S=1j * L, forces=[(-g2["A"], A.z)])},
            [pin("O2", "crank", 1j * L), Unknown("motor.torque", "couple", (("crank", 1),))],
        )
        f = g1 | g2 | g3
        e = {**point("crank.A", A), **link("bar", bar.theta, bar.omega, bar.alpha)}
        e |= (
            point("bar.B", B) | point("bar", S4) | link("link", five.phi1, five.omega1, five.alpha1)
        )
        e |= point("ram.C", C) | point("ram", S6) | point("ram.tool", tool)
        for k in ("O2", "A", "O4", "B", "C"):
            e |= force(k, f[k])
        e |= {k: f[k] for k in ("guide.N", "guide.M", "slot.N", "slot.M", "motor.torque")}
        expected.append(e)
        on.append(cutting)
    assert any(on) and not all(on)  # the rows compared have the load on and off
    return rows, expected


def press(p, table, summary):
    """Crank AB about A = (x_A, −y_A), coupler BC, rocker CDE about D = 0 (C at +x of
    its axis, E at −DE), link EF, ram F on x = X_F; DE = (H/2)/sin(ψ/2), the rocker
    at ±ψ/2 at the limits, C1, C2 = CD·e^{∓iψ/2}: AB = (AC2 − AC1)/2,
    BC = (AC2 + AC1)/2; the ram at its top with crank and coupler folded (the crank
    pointing away from C1), at its bottom stretched (the crank pointing at C2)."""
    g = 9.81
    A0 = (p["x_A"] - 1j * p["y_A"]) * 1e-3
    H, psi = p["H"] * 1e-3, math.radians(p["psi"])
    lDE = H / 2 / math.sin(psi / 2)
    lCD, lEF = p["CD_ratio"] * lDE, p["EF_ratio"] * lDE
    C1, C2 = lCD * np.exp(-0.5j * psi), lCD * np.exp(0.5j * psi)
    lAB, lBC = (abs(C2 - A0) - abs(C1 - A0)) / 2, (abs(C2 - A0) + abs(C1 - A0)) / 2
    X = -lDE * (1 + math.cos(psi / 2)) / 2
    m2, m3, m5 = p["G2"] / g, p["G3"] / g, p["G5"] / g
    J2, J3, Q = p["J_S2"], p["J_S3"], p["Q"]
    w1 = -p["n1"] * math.pi / 30
    top = math.degrees(np.angle(C1 - A0)) + 180
    bottom = math.degrees(np.angle(C2 - A0)) % 360
    out = summary["outputs"]["guide"]
    assert out["stroke"] == pytest.approx(H, rel=1e-12)
    th = abs(top - bottom - 180)
    assert out["time_ratio"] == pytest.approx((180 + th) / (180 - th), rel=1e-9)
    np.testing.assert_allclose(limits(summary, "guide"), sorted([top % 360, bottom]), atol=1e-7)
    # the template's comment: the transmission angle at C stays above 35°
    d = (table["coupler.theta"] - table["rocker.theta"]) % 180
    assert np.min(np.minimum(d, 180 - d)) > 35
    E1 = -lDE * np.exp(-0.5j * psi)  # E with the ram at its top
    y_top = E1.imag - math.sqrt(lEF**2 - (X - E1.real) ** 2)
    # the branch of the RRR group: C at C1 at the top
    B1 = crank(A0, lAB, math.radians(top), w1)
    branch = min((1, -1), key=lambda s: abs(rrr(B1, lBC, Motion(0j), lCD, s).C.z - C1))
    rows, angles = _rows_and_angles(table, bottom)
    expected, on = [], []
    for phi in angles:
        B = crank(A0, lAB, phi, w1)
        two = rrr(B, lBC, Motion(0j), lCD, branch)
        th3, w3, a3 = two.phi2, two.omega2, two.alpha2  # the rocker along D -> C
        E = on_link(Motion(0j), w3, a3, -lDE * np.exp(1j * th3))
        S3 = on_link(Motion(0j), w3, a3, -p["DS3_ratio"] * lDE * np.exp(1j * th3))
        S2 = on_link(B, two.omega1, two.alpha1, p["BS2_ratio"] * lBC * np.exp(1j * two.phi1))
        four = rrp(E, lEF, X + 0j, 1j, -1)  # F below E
        F = four.C
        pressing = F.v.imag < -1e-9 * abs(w1) * lDE and _band(
            y_top - F.z.imag, 0.6 * H, 0.95 * H, H
        )
        ram = Body(m5, 0.0, F.z, F.a, forces=[(-1j * g * m5, F.z), (1j * Q * pressing, F.z)])
        g3 = solve_group(
            {"link": Body(), "ram": ram},
            [pin("E", "link", E.z), pin("F", "ram", F.z, other="link"),
             Unknown("guide.N", "normal", (("ram", 1),), F.z, -1 + 0j),
             Unknown("guide.M", "couple", (("ram", 1),))],
        )  # fmt: skip
        coupler = Body(m2, J2, S2.z, S2.a, two.alpha1, [(-1j * g * m2, S2.z)])
        rocker = Body(m3, J3, S3.z, S3.a, a3, [(-1j * g * m3, S3.z), (-g3["E"], E.z)])
        g2 = solve_group(
            {"coupler": coupler, "rocker": rocker},
            [pin("B", "coupler", B.z), pin("C", "rocker", two.C.z, other="coupler"),
             pin("D", "rocker", 0j)],
        )  # fmt: skip
        g1 = solve_group(
            {"crank": Body(S=A0, forces=[(-g2["B"], B.z)])},
            [pin("A", "crank", A0), Unknown("motor.torque", "couple", (("crank", 1),))],
        )
        f = g1 | g2 | g3
        e = {**point("crank.B", B), **link("coupler", two.phi1, two.omega1, two.alpha1)}
        e |= point("coupler", S2) | link("rocker", th3, w3, a3) | point("rocker.C", two.C)
        e |= point("rocker.E", E) | point("rocker", S3)
        e |= link("link", four.phi1, four.omega1, four.alpha1) | point("ram.F", F)
        for k in ("A", "B", "C", "D", "E", "F"):
            e |= force(k, f[k])
        e |= {k: f[k] for k in ("guide.N", "guide.M", "motor.torque")}
        expected.append(e)
        on.append(pressing)
    assert any(on) and not all(on)  # the rows compared have the load on and off
    return rows, expected


def jaw_crusher(p, table, summary):
    """Crank O2A about O2 = 0, coupler AB and rocker O4B (RRR), toggle BC and jaw O6C
    (RRR); the jaw's limits where crank and coupler are collinear: O2B = AB ± O2A,
    B on the rocker's circle (the jaw open with B stretched out along the crank)."""
    g = 9.81
    mm = {k: v * 1e-3 for k, v in p.items() if k.startswith(("L_", "x", "y"))}
    r, l3, l4, l5, l6 = (mm[k] for k in ("L_O2A", "L_AB", "L_O4B", "L_BC", "L_O6C"))
    O4, O6 = mm["x4"] - 1j * mm["y4"], -mm["x6"] + 1j * mm["y6"]
    m3, m4, m6 = p["G3"] / g, p["G4"] / g, p["G6"] / g
    J3, J4, J6, Q = p["J_S3"], p["J_S4"], p["J_S6"], p["Q"]
    w2 = -p["n2"] * math.pi / 30

    def collinear(reach, turn):  # the crank angle with O2B = reach, B below O2 -> O4
        cos_ = (reach**2 + abs(O4) ** 2 - l4**2) / (2 * reach * abs(O4))
        return (math.degrees(np.angle(O4) - math.acos(cos_)) + turn) % 360

    opened, closed = collinear(l3 + r, 0), collinear(l3 - r, 180)
    np.testing.assert_allclose(limits(summary, "O6"), sorted([opened, closed]), atol=1e-7)
    th = abs(opened - closed - 180)
    assert summary["outputs"]["O6"]["time_ratio"] == pytest.approx(
        (180 + th) / (180 - th), rel=1e-9
    )
    B_open = (l3 + r) * np.exp(1j * math.radians(opened))
    A1 = crank(0j, r, math.radians(opened), w2)
    s1 = min((1, -1), key=lambda s: abs(rrr(A1, l3, Motion(O4), l4, s).C.z - B_open))
    rows, angles = _rows_and_angles(table, closed)
    expected, on = [], []
    for phi in angles:
        A = crank(0j, r, phi, w2)
        three = rrr(A, l3, Motion(O4), l4, s1)
        B = three.C
        five = rrr(B, l5, Motion(O6), l6, +1)  # C to the left of B -> O6
        C = five.C
        th6, w6, a6 = five.phi2, five.omega2, five.alpha2
        S3 = on_link(A, three.omega1, three.alpha1, l3 / 2 * np.exp(1j * three.phi1))
        S4 = on_link(Motion(O4), three.omega2, three.alpha2, l4 / 2 * np.exp(1j * three.phi2))
        S6 = on_link(Motion(O6), w6, a6, mm["L_O6S6"] * np.exp(1j * th6))
        Qp = on_link(Motion(O6), w6, a6, mm["L_O6Q"] * np.exp(1j * th6))
        crushing = Qp.v.real < -1e-9 * abs(w2) * l6
        jaw = Body(m6, J6, S6.z, S6.a, a6, [(-1j * g * m6, S6.z), (Q * crushing, Qp.z)])
        g3 = solve_group(
            {"toggle": Body(), "jaw": jaw},
            [pin("B_toggle", "toggle", B.z), pin("C", "jaw", C.z, other="toggle"),
             pin("O6", "jaw", O6)],
        )  # fmt: skip
        coupler = Body(m3, J3, S3.z, S3.a, three.alpha1, [(-1j * g * m3, S3.z),
                                                          (-g3["B_toggle"], B.z)])  # fmt: skip
        rocker = Body(m4, J4, S4.z, S4.a, three.alpha2, [(-1j * g * m4, S4.z)])
        g2 = solve_group(
            {"coupler": coupler, "rocker": rocker},
            [pin("A", "coupler", A.z), pin("B_rocker", "rocker", B.z, other="coupler"),
             pin("O4", "rocker", O4)],
        )  # fmt: skip
        g1 = solve_group(
            {"crank": Body(forces=[(-g2["A"], A.z)])},
            [pin("O2", "crank", 0j), Unknown("motor.torque", "couple", (("crank", 1),))],
        )
        f = g1 | g2 | g3
        e = {**point("crank.A", A), **link("coupler", three.phi1, three.omega1, three.alpha1)}
        e |= point("coupler", S3) | link("rocker", three.phi2, three.omega2, three.alpha2)
        e |= point("rocker.B", B) | point("rocker", S4) | link("jaw", th6, w6, a6)
        e |= link("toggle", five.phi1, five.omega1, five.alpha1)
        e |= point("jaw.C", C) | point("jaw", S6) | point("jaw.Qp", Qp)
        for k in ("O2", "A", "B_rocker", "O4", "B_toggle", "C", "O6"):
            e |= force(k, f[k])
        e["motor.torque"] = f["motor.torque"]
        expected.append(e)
        on.append(crushing)
    assert any(on) and not all(on)  # the rows compared have the load on and off
    return rows, expected


SAW_POINTS = (("crank.A", "A"), ("rod", "S2"))  # result column -> the oracle's point
COMPONENTS = ("x", "y", "vx", "vy", "ax", "ay")


def saw(p, table, summary):
    """The offset slider-crank of tests/oracles/slider_crank_closed_form.py with the
    crank and rod synthesised here by the circle method: B1, B2 on the guide y = −e, H
    apart, seen from O under θ = 180(K − 1)/(K + 1); OB1 = b − a, OB2 = b + a."""
    g = 9.81
    K, H, e = p["K"], p["H"] * 1e-3, p["e"] * 1e-3
    th = math.pi * (K - 1) / (K + 1)
    R = H / (2 * math.sin(th))
    xm = math.sqrt(R**2 - (H / (2 * math.tan(th)) - e) ** 2)
    ob1, ob2 = math.hypot(xm - H / 2, e), math.hypot(xm + H / 2, e)
    a, b = (ob2 - ob1) / 2, (ob2 + ob1) / 2
    # the synthesis sees the chord under θ: the crank angles of the limits differ by 180° + θ
    left = 180 + math.degrees(math.atan2(-e, xm - H / 2))
    right = math.degrees(math.atan2(-e, xm + H / 2)) % 360
    assert (right - left) % 360 == pytest.approx(180 + math.degrees(th), abs=1e-9)
    out = summary["outputs"]["guide"]
    assert out["stroke"] == pytest.approx(H, rel=1e-12)
    assert out["time_ratio"] == pytest.approx(K, rel=1e-9)
    np.testing.assert_allclose(limits(summary, "guide"), sorted([left, right]), atol=1e-7)
    # the template's comment: the rod 2 to 2.5 times the crank, the pressure angle at B
    # (the rod against the guide) below 50°
    assert 2 <= b / a <= 2.5
    d = table["rod.theta"] % 180
    assert np.max(np.minimum(d, 180 - d)) < 50
    model = sc.SliderCrank(
        a=a, b=b, e=-e, r1=0.0, r2=p["S2_ratio"] * b, m1=0.0, m2=p["G2"] / g, m3=p["G3"] / g,
        J1=0.0, J2=p["J_S2"], omega1=p["n1"] * math.pi / 30, g=(0.0, -g), Fr=p["F"],
    )  # fmt: skip
    rows, angles = _rows_and_angles(table, right)
    k, f = sc.kinematics(model, np.array(angles)), sc.reactions(model, np.array(angles))
    expected = []
    for i in range(len(angles)):
        e_ = {f"{col}.{c}": k[f"{key}_{c}"][i] for col, key in SAW_POINTS for c in COMPONENTS}
        e_ |= {"saw.x": k["xB"][i], "saw.y": k["yB"][i], "saw.vx": k["vB"][i], "saw.ax": k["aB"][i]}
        e_ |= link("rod", k["phi2"][i], k["omega2"][i], k["alpha2"][i])
        for name in ("O", "A", "B"):
            e_ |= {f"{name}.Fx": f[f"F_{name}x"][i], f"{name}.Fy": f[f"F_{name}y"][i]}
        e_ |= {"guide.N": f["N"][i], "guide.M": f["M_slide"][i], "motor.torque": f["M1"][i]}
        expected.append(e_)
    return rows, expected


def test_the_docs_page_shows_every_row_of_every_template():
    """docs/templates.md holds each template's data table as the templates have it."""
    page = (ROOT / "docs" / "templates.md").read_text(encoding="utf-8")
    for t in templates():
        keys = list(next(iter(t.rows.values())))
        lines = ["| row | " + " | ".join(f"`{k}`" for k in keys) + " |"]
        lines.append("|---|" + "---:|" * len(keys))
        lines += [
            f"| {r} | " + " | ".join(f"{v:g}" for v in row.values()) + " |"
            for r, row in t.rows.items()
        ]
        assert "\n".join(lines) in page, t.name
        assert f"### `{t.name}` ({t.zh})" in page
