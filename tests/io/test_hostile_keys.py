"""Hostile values in the keys the first fuzz did not reach (motion laws, flywheel
``ratio``, effort drivers, ``balance_at``, analysis start), hostile characters in
messages, the nesting and node limits, and a walk over every key the loader reads
(docs/errors.md, "Limits" and "Every number of a file")."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import kinetostatics as ks
from kinetostatics.base import limits
from kinetostatics.dynamics.stages import full_summary
from kinetostatics.errors import ModelError
from tests.keywalk import instrumented
from tests.seeds import SEEDS, SHIPPED

ROOT = Path(__file__).resolve().parents[2]
TEXT = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
MOTOR = "motor: {joint: O, motion: {speed: 300}}"
ANALYSIS = "analysis: {start: 0, sweep: 360, positions: 360}"


def _law(spec: str, slider: bool = False) -> str:
    text = TEXT.replace(ANALYSIS, "analysis: {positions: 8}")
    if slider:
        return text.replace("speed: rpm", "speed: mm/s").replace(
            MOTOR, f"motor: {{joint: slide, motion: {spec}}}"
        )
    return text.replace(MOTOR, f"motor: {{joint: O, motion: {spec}}}")


def _refused(text: str) -> str:
    with pytest.raises(ModelError) as info:
        ks.loads(text, file="h.yaml")
    message = str(info.value)
    assert "\x1b" not in message
    return message


# -- 1. motion laws within the sweep limits -------------------------------------------------
@pytest.mark.parametrize(
    "spec, slider, expected",
    [
        # 2e5 degrees back and forth: each value within the angle limit, the path 5.6 turns x 100
        # (the spline through the points overshoots them: the path is at least 120000 deg)
        (
            "{law: table, time: [0, 1, 2, 3, 4], value: [0, 30000, 0, 30000, 0]}",
            False,
            "deg over its duration, more than the limit of 100 turns (36000 deg)",
        ),
        (
            "{law: harmonic, centre: 0, amplitude: 20000, period: 100}",
            False,
            "the harmonic law moves the driver 80000 deg over its period, more than the limit of "
            "100 turns",
        ),
        # a slider law over 1000 km: within the length limit, 3 million times the rod
        (
            "{law: polynomial, coefficients: [440, -1e6], duration: 1}",
            True,
            "h.yaml:40:33: drivers.motor.motion: the polynomial law moves the driver 1e+06 mm "
            "over its duration, more than the limit of 1000 times the largest link (350 mm)",
        ),
    ],
)
def test_a_motion_law_travels_no_farther_than_a_sweep_may(spec, slider, expected):
    """The positions are followed along the law's path in bounded steps: a law may not make
    the driver travel farther than analysis.sweep may (MAX_TURNS, MAX_TRAVEL)."""
    message = _refused(_law(spec, slider))
    assert expected in message
    assert message.startswith(f"h.yaml:40:{33 if slider else 29}: drivers.motor.motion: the ")
    moved = float(re.search(r"moves the driver (\S+) ", message).group(1))
    assert moved > (350 * 1000 if slider else 36000)
    assert len(message.splitlines()) == 1


def test_a_polynomial_coefficient_that_overflows_in_si_is_refused_at_the_coefficient():
    text = _law("{law: polynomial, coefficients: [0, 1e308], duration: 1}").replace(
        "units: {", "units: {time: ms, ", 1
    )
    message = _refused(text)
    assert "drivers.motor.motion.coefficients[1]: c1 = 1e+308 is too large" in message


def test_huge_law_values_and_periods_are_refused_at_the_key():
    for spec, key in [
        ("{law: harmonic, centre: 0, amplitude: 1e12, period: 1}", "amplitude"),
        ("{law: table, time: [0, 1, 2], value: [0, 1e12, 0]}", "value[1]"),
        ("{law: harmonic, centre: 0, amplitude: 30, period: 1e-300}", "period"),
    ]:
        assert f"drivers.motor.motion.{key}: " in _refused(_law(spec))
    assert "reaches a speed" in _refused(
        _law("{law: polynomial, coefficients: [0, 1, 1e300], duration: 1}")
    )


# -- 2. a periodic table whose ends differ by round-off ---------------------------------------
def test_a_periodic_table_whose_ends_agree_to_round_off_loads_and_closes():
    """The ends differ by 1e-9 deg against a largest value of 100 deg: the loader's relative
    check passes it; scipy's periodic spline used to raise a bare ValueError."""
    model = ks.loads(
        _law("{law: table, time: [0, 1, 2], value: [0.001, 100, 0.001000000001], periodic: true}"),
        file="h.yaml",
    )
    law = model.drivers[0].motion
    start, end = (law.value(0.0, t)[0] for t in (0.0, law.duration))
    assert end == pytest.approx(start, abs=1e-15) and start == pytest.approx(np.radians(0.001))


def test_a_periodic_table_whose_ends_differ_is_refused():
    message = _refused(_law("{law: table, time: [0, 1, 2], value: [0, 100, 1], periodic: true}"))
    assert "drivers.motor.motion.value: a periodic table must end where it starts" in message


# -- 3. flywheel ratio; run writes nothing when it fails ----------------------------------------
@pytest.mark.parametrize(
    "ratio, word", [("1e-200", "too small"), ("1e-160", "too small"), ("1e308", "too large")]
)
def test_flywheel_ratio_out_of_range_is_refused(ratio, word):
    message = _refused(TEXT + f"flywheel: {{delta: 0.05, ratio: {ratio}}}\n")
    assert f"flywheel.ratio: {float(ratio):g} is {word}" in message


@pytest.mark.parametrize("ratio", ["1e-30", "1e18"])
def test_flywheel_ratio_at_its_limits_gives_valid_json(ratio, tmp_path):
    """J_motor = J_crank / ratio**2 (the speed ratio): finite at both limits, strict JSON."""
    from kinetostatics.cli import main

    path = tmp_path / "f.yaml"
    path.write_text(
        TEXT.replace(ANALYSIS, "analysis: {positions: 36}")
        + f"flywheel: {{delta: 0.05, ratio: {ratio}}}\n"
    )
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0

    def refuse(name):
        raise ValueError(f"{name} in summary.json")

    summary = json.loads((tmp_path / "out" / "summary.json").read_text(), parse_constant=refuse)
    fw = summary["flywheel"]
    assert fw["inertia"]["motor"] == pytest.approx(fw["inertia"]["crank"] / float(ratio) ** 2)


def test_run_writes_no_results_when_the_summary_fails(tmp_path, monkeypatch):
    """docs/errors.md: a failed run writes no results.csv (it used to be written before the
    summary, whose failure then left it alone)."""
    from kinetostatics.analysis import results
    from kinetostatics.cli import main

    def broken(self, *args, **kwargs):
        raise ZeroDivisionError("summary")

    monkeypatch.setattr(results.Result, "summary", broken)
    out = tmp_path / "out"
    with pytest.raises(ZeroDivisionError):
        main(["run", str(ROOT / "mechanisms" / "slider_crank.yaml"), "--out", str(out)])
    assert not out.exists() or not list(out.iterdir())


# -- 9. messages --------------------------------------------------------------------------------
def test_a_key_holding_a_newline_gives_one_line():
    text = TEXT.replace("  r1: 30 ", '  "r1\\nother.yaml:1:1: boom": 30 ', 1)
    with pytest.raises(ModelError) as info:
        ks.loads(text, file="h.yaml")
    lines = str(info.value).splitlines()
    assert len(lines) == len(info.value.problems) == 2
    assert lines[0].startswith("h.yaml:10:3: parameters.r1\\nother.yaml:1:1: boom: parameter name")
    assert all(line.startswith("h.yaml:") for line in lines)


def test_ansi_escapes_in_keys_and_names_are_escaped(tmp_path, capsys):
    from kinetostatics.cli import main

    text = TEXT.replace("  r1: 30 ", '  "r1\\e[31mRED\\u2028x": 30 ', 1).replace(
        "link: slider\n", 'link: "sl\\e[2Jider"\n', 1
    )
    path = tmp_path / "a.yaml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "\x1b" not in err and "\u2028" not in err
    assert "r1\\x1b[31mRED\\u2028x" in err and "sl\\x1b[2Jider" in err
    assert all(line.startswith(str(path)) for line in err.splitlines())


@pytest.mark.parametrize(
    "analysis, key, what",
    [
        ("start: 40000, sweep: 360", "analysis.start", "the start is 40000 deg"),
        (
            "start: 35900, sweep: 360",
            "analysis.sweep",
            "the end of the sweep (start + sweep) is 36260 deg",
        ),
        ("start: 0, sweep: 360, at: [40000]", "analysis.at[0]", "the position is 40000 deg"),
    ],
)
def test_a_revolute_run_stays_within_100_turns_of_zero(analysis, key, what):
    """Far from 0 the rounding of the driver angle (|ψ| × 2.2e-16) reaches the solver's
    tolerance (1e-12 L_ref): a start of 10^4 turns gave 'Newton did not converge (a
    singular position is near)' on the slider-crank, 200 turns on the geared five-bar."""
    message = _refused(TEXT.replace("start: 0, sweep: 360", analysis))
    assert (
        f"{key}: {what}; a revolute driver's coordinate must stay within ±100 turns "
        "(±36000 deg) of 0" in message
    )
    law = _law("{law: harmonic, centre: 3.6e6, amplitude: 10, period: 1}")
    assert (
        "the harmonic law reaches 3.60001e+06 deg; a revolute driver's coordinate must "
        "stay within ±100 turns" in _refused(law)
    )
    # the limit itself: 100 turns either side, analysed on the geared five-bar
    gear = (ROOT / "mechanisms" / "geared_fivebar.yaml").read_text()
    model = ks.loads(gear, file="g.yaml")
    start = np.degrees(model.analysis.start)
    for s0, sweep in [(35990 - start, 10), (-36000, 10)]:
        text = re.sub(
            r"analysis: \{[^}]*\}",
            f"analysis: {{start: {s0 + start}, sweep: {sweep}, positions: 3}}",
            gear,
        )
        assert len(ks.analyze(ks.loads(text, file="g.yaml"))) == 3


def test_analysis_start_beyond_the_angle_limit_is_refused_at_the_key():
    message = _refused(TEXT.replace("start: 0,", "start: 1e17,"))
    assert "analysis.start: 1e+17 deg (1.74533e+15 rad) is too large" in message


def test_non_ascii_letters_in_an_expression_are_refused_not_folded():
    """Python folds 'ℯ' (U+212F) to 'e' (NFKC): 100*ℯ silently meant 100*e, the offset."""
    message = _refused(TEXT.replace("value: 1000", "value: 100*ℯ"))
    assert (
        "loads.resistance.value: the character 'ℯ' (U+212F) at position 5 is not allowed" in message
    )
    assert "undefined parameter" in _refused(TEXT.replace("value: 1000", "value: 100*e2"))


def test_nesting_limit_counts_levels_of_lists_and_mappings():
    """docs/errors.md: 100 levels of lists and mappings (the top mapping is the first)."""

    def nested(levels):
        return TEXT.replace(
            "name: offset slider-crank", "name: " + "[" * (levels - 1) + "1" + "]" * (levels - 1)
        )

    assert "expected a name, got a list" in _refused(nested(limits.MAX_DEPTH))
    assert f"nested more than {limits.MAX_DEPTH} deep" in _refused(nested(limits.MAX_DEPTH + 1))


def test_expression_nesting_limit_counts_operations():
    from kinetostatics.base import expressions as ex

    n = ex.MAX_DEPTH
    for make in (
        lambda k: "-" * k + "1",
        lambda k: "sin(" * k + "1" + ")" * k,
        lambda k: "(" * k + "1" + ")" * k,
    ):
        assert ex.evaluate(make(n), {}) is not None
        with pytest.raises(ex.ExpressionError, match="nested too deeply"):
            ex.evaluate(make(n + 1), {})


@pytest.mark.timeout(120)  # 3 s on a quiet machine; 15-24 s when it was refused after reading
def test_a_long_flat_list_is_refused_while_it_is_read():
    """The node limit is applied while composing (it used to be applied after a 1 MB list
    of 330,000 numbers was built: 15-24 s and 350 MB); the message points at the node."""
    text = "junk: [" + ", ".join(["1"] * 200_000) + "]\n"
    message = _refused(text)  # the position in the message shows it stopped early
    assert re.match(
        rf"h\.yaml:1:\d+: more than {limits.MAX_NODES} YAML nodes; refused$", message
    ), message
    assert int(message.split(":")[2]) > 100_000


@pytest.mark.timeout(300)  # 4 s on a quiet machine (it was 54-73 s): a hang, not a slow one
def test_slide_friction_coefficient_of_5_is_analysed():
    """μ = 5 at the slide locks the slider-crank over two zones: the result says so
    (the friction check fails on the self-locked rows, which are empty), and every other
    row keeps its power balance with friction."""
    result = ks.analyze(
        ks.loads(TEXT.replace("coefficient: 0.10", "coefficient: 5"), file="h.yaml")
    )
    summary = full_summary(result)
    assert summary["checks"]["failed"] == ["friction"]
    assert "self-locking" in summary["checks"]["friction"]["where"]
    zones = summary["self_locking"]
    assert len(zones) >= 1 and all(z["from"] < z["to"] for z in zones)
    locked = np.isnan(result["motor.torque_friction"])
    assert locked.any() and not locked.all()
    assert summary["checks"]["power_friction"]["ok"]


# -- the key walk ---------------------------------------------------------------------------
def _walk():
    texts = {
        name: yaml.safe_dump(doc, sort_keys=False) for name, doc in {**SHIPPED, **SEEDS}.items()
    }
    with instrumented() as walk:
        for name, text in texts.items():
            ks.loads(text, file=name)  # every seed loads
    return walk


@pytest.fixture(scope="module")
def walk():
    return _walk()


def test_the_seeds_give_every_key_the_loader_accepts(walk):
    """So that the fuzz, which mutates the seeds, reaches every key."""
    missing = {p: sorted(walk.allowed[p] - walk.present[p]) for p in walk.allowed}
    missing[""] = [k for k in missing.get("", []) if k != "sweep"]  # the batch's section
    assert not {p: m for p, m in missing.items() if m}
    for p in (
        "drivers.*.motion",
        "drivers.*.effort",
        "drivers.*.effort.motor",
        "drivers.*.effort.curve",
        "drivers.*.effort.table",
        "flywheel",
        "analysis",
        "clearance.*",
        "clearance.*.contact",
        "loads.*.table",
        "loads.*.active[]",
    ):
        assert p in walk.allowed, p
    assert {
        "law",
        "centre",
        "amplitude",
        "period",
        "phase",
        "coefficients",
        "duration",
        "time",
        "value",
        "periodic",
        "speed",
    } <= walk.present["drivers.*.motion"]


def test_every_number_the_loader_reads_has_a_range(walk):
    """Each number is bounded by MAGNITUDE when it is read, or named in OWN_LIMITS with
    the limit that bounds it; docs/errors.md lists every one."""
    assert walk.unbounded <= set(limits.OWN_LIMITS), walk.unbounded - set(limits.OWN_LIMITS)
    assert set(limits.OWN_LIMITS) <= walk.unbounded  # no stale entry
    doc = (ROOT / "docs" / "errors.md").read_text(encoding="utf-8")
    read = {p for _, p in walk.read.values()}
    assert len(read) > 50
    missing = sorted(p for p in read if f"`{p}`" not in doc)
    assert not missing, f"docs/errors.md does not list {missing}"


def test_a_clearance_without_size_is_a_located_problem():
    """Found by the fuzz once its seeds reached the clearance section: a clearance entry
    without ``size`` raised a bare KeyError from the loader."""
    text = (ROOT / "mechanisms" / "ammunition_swing.yaml").read_text()
    assert "  B: {size: e2, " in text
    text = text.replace("  B: {size: e2, ", "  B: {", 1)
    message = _refused(text)
    assert re.search(r"h\.yaml:\d+:\d+: clearance\.B: missing required key 'size'", message), (
        message
    )


def test_clearances_in_a_file_without_drivers_are_a_located_problem():
    """Found by the fuzz (2026-11-29, ``drivers: {}`` in the ammunition swing): the
    clearances' start state assembled a linkage with no driver, and the loader died with a
    bare ``LinAlgError`` from the group's (non-square) Jacobian; it is now the structure
    error ``analyze`` gives such a file, located at ``drivers``."""
    doc = yaml.safe_load((ROOT / "mechanisms" / "ammunition_swing.yaml").read_text())
    assert doc["clearance"] and doc["drivers"]
    doc["drivers"] = {}
    with pytest.raises(ks.StructureError) as info:
        ks.loads(yaml.safe_dump(doc, sort_keys=False), file="h.yaml")
    message = str(info.value)
    assert message.startswith("h.yaml: drivers: "), message
    assert "motion drivers as the mobility (1); the file has 0" in message
