"""docs/optimisation.md, the slotting machine's worked example (the block written by
docs/scripts/optimisation_example.py): its claims checked without trusting the search.

The optimum the page states is analysed afresh by ``ks.analyze`` (not the batch that the
search used); K and H are checked against their closed forms — the time ratio
(180° + θ)/(180° − θ) and the stroke 2·L_O3B·sin(θ/2), θ = 2·asin(L_O2A / L_O2O3) read off
the built links — and the optimum's ram line against X = L_O3B − L_BC·sin 10°, where the
pressure-angle limit is active with the bar horizontal.  Whether the block is current (the
search run again, ~10 s) is a check of the long run."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.batch.optimize_files import with_parameters
from kinetostatics.batch.variants import Template, analyze_variants
from kinetostatics.dynamics.stages import full_summary
from tests.golden.compare import NUMBER
from tests.helpers import ROOT, load_script, same_lines

SCRIPT = ROOT / "docs" / "scripts" / "optimisation_example.py"
FILE = ROOT / "mechanisms" / "slotting_machine.yaml"
LIMIT = 10.0  # the pressure-angle limit of the example, degrees


@pytest.fixture(scope="module")
def ex():
    return load_script(SCRIPT)


@pytest.fixture(scope="module")
def block(ex) -> str:
    return ex.doc_block()


@pytest.fixture(scope="module")
def optimum(block) -> dict[str, float]:
    found = dict(re.findall(r"`(\w+) = ([-+0-9.e]+)`", block.split("full precision:")[1]))
    return {k: float(v) for k, v in found.items()}


@pytest.fixture(scope="module")
def table(block) -> dict[str, tuple[float, float]]:
    """The block's table: label → (as written, optimum)."""
    out = {}
    for line in block.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 3 and re.fullmatch(r"-?[\d.]+", cells[1]):
            out[cells[0]] = (float(cells[1]), float(cells[2]))
    return out


def _model(parameters, positions=None) -> ks.Model:
    """The file with these parameter values written in (``with_parameters``, as
    best.yaml is written), read afresh."""
    text = with_parameters(FILE.read_text(encoding="utf-8"), Template.load(FILE).tree, parameters)
    return Template.loads(text, "best.yaml").model(positions=positions)


def _lengths(model: ks.Model) -> dict[str, float]:
    """Frame distance, crank, guide bar, rod (m) and the ram line's x (m), from the links."""

    def dist(link, p, q):  # a link's points are kept about its centre of mass
        pts = model.link(link).points
        return float(np.linalg.norm(pts[q] - pts[p]))

    frame = model.link("frame").points
    return {
        "L_O2O3": dist("frame", "O2", "O3"),
        "L_O2A": dist("crank", "O2", "A"),
        "L_O3B": dist("bar", "O3", "B"),
        "L_BC": dist("rod", "B", "C"),
        "X": float(frame["ram_guide"][0] - frame["O3"][0]),
    }


def _closed_form(lengths) -> tuple[float, float]:
    """(K, H in m) of a crank and slotted bar driving the ram through a rod."""
    theta = 2.0 * math.degrees(math.asin(lengths["L_O2A"] / lengths["L_O2O3"]))
    return (180.0 + theta) / (180.0 - theta), 2.0 * lengths["L_O3B"] * math.sin(
        math.radians(theta / 2)
    )


def _pressure_angle_max(result) -> float:
    """The largest angle between the rod (a two-force member: no mass, no load) and the
    ram's vertical motion, from the rod's angle."""
    theta = np.radians(np.asarray(result["rod.theta"], dtype=float))
    return float(np.degrees(np.max(np.arcsin(np.abs(np.cos(theta))))))


def test_the_optimum_keeps_k_and_h(optimum):
    """Analysed afresh at 720 positions, the optimum's time ratio and stroke are the file's
    K and H (to 1e-9) and their closed forms from its links."""
    model = _model(optimum, positions=720)
    assert model.link("rod").mass == 0.0 and model.link("crank").mass == 0.0
    s = full_summary(ks.analyze(model))["outputs"]["guide"]
    k, h = _closed_form(_lengths(model))
    assert s["time_ratio"] == pytest.approx(2.0, abs=1e-9) and k == pytest.approx(2.0, abs=1e-12)
    assert s["stroke"] == pytest.approx(0.100, abs=1e-12) and h == pytest.approx(0.1, abs=1e-14)


def test_the_stated_numbers_are_a_fresh_analysis(optimum, table):
    """The table's rows, from ks.analyze of the file and of the optimum written into it
    (the file's 360 positions, as the batch used), to the digits shown."""
    for column, params in ((0, {}), (1, optimum)):
        model = _model(params)
        r = ks.analyze(model)
        d = full_summary(r)["drivers"]["motor"]
        lengths = _lengths(model)
        assert table["peak motor torque, friction (N·m)"][column] == pytest.approx(
            d["peak_friction"], abs=6e-4
        )
        assert table["peak motor torque, no friction (N·m)"][column] == pytest.approx(
            d["peak"], abs=6e-4
        )
        rms = float(np.sqrt(np.mean(np.square(r["motor.torque_friction"]))))  # over the rows
        assert table["RMS motor torque over the rows, friction (N·m)"][column] == pytest.approx(
            rms, abs=6e-4
        )
        assert table["largest pressure angle at the ram (°)"][column] == pytest.approx(
            _pressure_angle_max(r), abs=6e-3
        )
        out = full_summary(r)["outputs"]["guide"]
        assert table["time ratio K"][column] == pytest.approx(out["time_ratio"], abs=6e-10)
        assert table["ram stroke H (mm)"][column] == pytest.approx(1000 * out["stroke"], abs=6e-10)
        named = (("frame", "L_O2O3"), ("crank", "L_O2A"), ("guide bar", "L_O3B"), ("rod", "L_BC"))
        for label, key in named:
            (row,) = [v for k, v in table.items() if k.startswith(label)]
            assert row[column] == pytest.approx(1000 * lengths[key], abs=6e-3)
        assert table["ram line X (mm)"][column] == pytest.approx(1000 * lengths["X"], abs=6e-3)


def test_the_optimum_beats_the_file_within_the_limit(optimum):
    """At 720 positions (finer than the search's 360) the optimum's peak torque with
    friction is below the file's and its pressure angle is at the 10° limit."""
    before = ks.analyze(_model({}, positions=720))
    after = ks.analyze(_model(optimum, positions=720))
    peak = [float(np.max(np.abs(r["motor.torque_friction"]))) for r in (before, after)]
    assert peak[1] < 0.99 * peak[0]
    assert _pressure_angle_max(after) == pytest.approx(LIMIT, abs=1e-7)
    assert _pressure_angle_max(before) < LIMIT


def test_the_ram_line_is_where_the_limit_is_active(ex, optimum):
    """Frame and rod at the bounds the page explains (upper, lower); the ram line where
    the rod makes 10° with it with the bar horizontal: X = L_O3B − L_BC·sin 10°."""
    assert optimum["L_O2O3"] == ex.VARY["L_O2O3"][1]
    assert optimum["BC_ratio"] == ex.VARY["BC_ratio"][0]
    bar = 50.0 / math.sin(math.radians(30.0))  # (H/2)/sin(θ/2), θ = 60° for K = 2
    x = bar - optimum["BC_ratio"] * bar * math.sin(math.radians(LIMIT))
    assert optimum["X"] == pytest.approx(x, abs=1e-7)


def test_the_batch_reads_k_and_h_as_their_closed_forms():
    """The batch's time ratio and stroke (what a constraint on K or H would read) equal
    the closed forms from the link lengths, for random designs in which K and H vary too
    — and the file's parameters K, H are what the built links give."""
    rng = np.random.default_rng(7)
    n = 12
    designs = [
        {
            "K": float(rng.uniform(1.3, 2.6)),
            "H": float(rng.uniform(60.0, 160.0)),
            "L_O2O3": float(rng.uniform(120.0, 200.0)),
            "BC_ratio": float(rng.uniform(0.8, 1.5)),
        }
        for _ in range(n)
    ]
    template = Template.load(FILE)  # its sketch follows K and H
    rows = analyze_variants(template, designs, positions=72, flywheel=False)
    for design, row in zip(designs, rows):
        assert row["status"] == "ok", row["reason"]
        k, h = _closed_form(_lengths(template.model(design)))
        assert row["guide.time_ratio"] == pytest.approx(k, rel=1e-9)
        assert row["guide.stroke"] == pytest.approx(h, rel=1e-9)
        assert k == pytest.approx(design["K"], rel=1e-12)
        assert h == pytest.approx(design["H"] / 1000.0, rel=1e-12)


def test_the_frame_distance_moves_only_the_friction_torque(optimum):
    """With K held the bar's motion against the crank's is the same at any frame distance
    and the crank and block have no mass: the peak torque without friction does not change
    (to 1e-9), the one with friction falls as the frame grows."""
    template = Template.load(FILE)
    frames = [120.0, 160.0, 200.0]
    rows = analyze_variants(
        template, [{**optimum, "L_O2O3": f} for f in frames], positions=72, flywheel=False
    )
    assert template.base.link("block").mass == 0.0
    plain = [r["motor.torque_peak"] for r in rows]
    assert plain == pytest.approx([plain[0]] * 3, rel=1e-9)
    friction = [r["motor.torque_friction_peak"] for r in rows]
    assert friction[0] > friction[1] > friction[2]


COUNTS = re.compile(r"^\d+ designs evaluated.*$", re.M)


def _counts(line: str) -> tuple[int, ...]:
    """(evaluated, feasible, breaking the limit, failed, analysed) of the counts' line."""
    m = re.match(
        r"(\d+) designs evaluated \((\d+) feasible, (\d+) breaking the pressure-angle "
        r"limit, (\d+) failed\); over the (\d+) that",
        line,
    )
    assert m, line
    return tuple(int(v) for v in m.groups())


@pytest.mark.slow
def test_the_block_is_current(ex, block):
    """The search run again (about 10 s) gives the block on the page: its table and the
    optimum to their printed digits.  How many designs the search evaluated follows the
    objective's last bits (its path: 778 on the machine that wrote the page, 770 on
    another CPU), so that line is held to its words, to counts that add up and to within
    5 % of the page's."""
    got = ex.block(ex.run())
    same_lines(COUNTS.sub("", got), COUNTS.sub("", block), rel=1e-9)
    (new,), (old,) = COUNTS.findall(got), COUNTS.findall(block)
    assert NUMBER.sub("#", new) == NUMBER.sub("#", old)
    for n, ok, breaking, failed, analysed in (_counts(new), _counts(old)):
        assert n == ok + breaking + failed and analysed == n - failed
    assert abs(_counts(new)[0] - _counts(old)[0]) <= 0.05 * _counts(old)[0]
