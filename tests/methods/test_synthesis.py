"""The dimension synthesis (outputs/report/formulas.py): the parameter expressions as formulas.

Two truths the formatter does not use: the formulas of the slotting machine and the shaper
written by hand from their files, and the value of each formula read back — its text
translated to Python by a reverse table in this test and evaluated by
base/expressions.py — which equals the loaded parameter, so no parenthesis was lost.
"""

from __future__ import annotations

import re

import pytest

import kinetostatics as ks
from kinetostatics.base.expressions import evaluate
from kinetostatics.outputs.report.data import _data_blocks
from kinetostatics.outputs.report.formulas import formula, synthesis_rows
from tests.helpers import MECHANISMS, ROOT

SLOTTING = {
    "theta": "θ = 180×(K − 1)/(K + 1) = 60",
    "L_O2A": "L_O2A = L_O2O3×sin(θ/2) = 75",
    "L_O3B": "L_O3B = (H/2)/sin(θ/2) = 100",
    "L_BC": "L_BC = BC_ratio×L_O3B = 100",
    "X": "X = L_O3B×(1 + cos(θ/2))/2 = 93.3013",
    "phi3": "φ3 = atan2(−L_O2A×sin(300°), L_O2O3 − L_O2A×cos(300°)) = 30",
}
SHAPER = {
    "L_BC": "L_BC = 0.25×L_O3B = 135",
    "half": "half = arcsin(L_O2A/L_O2O3) = 16.8264",
    "H": "H = 2×L_O3B×sin(half) = 312.632",
    "Y": "Y = L_O3B×(1 + cos(half))/2 = 528.44",
}
_BACK = [  # the formula's notation back to the parser's, longest first
    ("arcsin_rad", "asin"),
    ("arccos_rad", "acos"),
    ("arctan_rad", "atan"),
    ("atan2_rad", "atan2"),
    ("sin_rad", "sin"),
    ("cos_rad", "cos"),
    ("tan_rad", "tan"),
    ("arcsin", "asind"),
    ("arccos", "acosd"),
    ("arctan", "atand"),
    ("atan2(", "atan2d("),
    ("ln(", "log("),
    ("°", ""),
    ("×", "*"),
    ("−", "-"),
    ("²", "**2"),
    ("³", "**3"),
    ("^", "**"),
    (" mod ", "%"),
    (" div ", "//"),
]
_GREEK_BACK = {"θ": "theta", "φ": "phi", "β": "beta", "α": "alpha", "ψ": "psi", "γ": "gamma"}


def _python(text: str, names: dict[str, str]) -> str:
    for a, b in _BACK:
        text = text.replace(a, b)
    text = re.sub(r"\b(sin|cos|tan)\(", r"\1d(", text)  # degrees: plain sin is sind
    text = text.replace("_radd(", "(")  # undo the line above on the radians' names
    text = re.sub(r"√\(", "sqrt(", text)
    text = re.sub(r"√(\w+)", r"sqrt(\1)", text)
    text = re.sub(r"\|([^|]*)\|", r"abs(\1)", text)
    for letter, word in _GREEK_BACK.items():
        text = text.replace(letter, word)
    return text


@pytest.mark.parametrize(("name", "expected"), [("slotting_machine", SLOTTING), ("shaper", SHAPER)])
def test_the_textbook_files_show_their_formulas_written_by_hand(name, expected):
    model = ks.load(ROOT / "mechanisms" / f"{name}.yaml")
    rows = dict(synthesis_rows(model.parameter_texts, model.parameters))
    assert rows == expected
    for key, text in rows.items():  # the printed value is the loader's, to 6 digits
        printed = float(text.rsplit("=", 1)[1].replace("−", "-"))
        exact = evaluate(model.parameter_texts[key], model.parameters)
        assert printed == pytest.approx(exact, rel=1e-5)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_each_formula_read_back_gives_the_parameter(path):
    model = ks.load(path)
    for key, text in model.parameter_texts.items():
        shown = formula(text)
        back = _python(shown, {})
        assert evaluate(back, model.parameters) == pytest.approx(
            model.parameters[key], rel=1e-12, abs=1e-12
        ), (key, text, shown, back)


def test_plain_numbers_are_data_not_synthesis():
    rows = synthesis_rows({"K": "2", "n": "-3", "t": "2*K"}, {"K": 2.0, "n": -3.0, "t": 4.0})
    assert rows == [["t", "t = 2×K = 4"]]


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("a - (b + c)", "a − (b + c)"),
        ("a - b + c", "a − b + c"),
        ("a/(b*c)", "a/(b×c)"),
        ("(a + b)**2", "(a + b)²"),
        ("-x**2", "−x²"),
        ("sqrt(rb**2 - e**2)", "√(rb² − e²)"),
        ("abs(alpha1 - 2)", "|α1 − 2|"),
        ("a**(1/3)", "a^(1/3)"),
    ],
)
def test_parentheses_where_the_order_needs_them(text, shown):
    assert formula(text) == shown


def test_the_data_chapter_holds_the_synthesis_in_both_languages():
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    system = ks.build_system(model)
    for lang, caption in (("en", "Dimension synthesis"), ("zh", "尺寸综合")):
        tables = [b for b in _data_blocks(model, system, lang) if hasattr(b, "rows")]
        (table,) = [t for t in tables if caption in str(getattr(t, "caption", ""))]
        assert [r[1] for r in table.rows] == list(SLOTTING.values())


def test_an_override_is_a_number_and_has_no_formula():
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml", parameters={"theta": 50.0})
    assert "theta" not in model.parameter_texts
    rows = dict(synthesis_rows(model.parameter_texts, model.parameters))
    assert "theta" not in rows and rows["L_O2A"].startswith("L_O2A = L_O2O3×sin(θ/2) = ")
