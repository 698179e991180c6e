"""Tests for kinetostatics.base.expressions."""

import math

import pytest

from kinetostatics.base.expressions import (
    CONSTANTS,
    FUNCTIONS,
    MAX_EXPRESSION_LENGTH,
    ExpressionError,
    evaluate,
    evaluate_parameters,
    names_in,
)
from kinetostatics.base.literals import plain_number


def test_slotting_machine_course_design():
    p = evaluate_parameters(
        [
            ("K", 2),
            ("H", 100),
            ("L", "150"),
            ("theta", "180*(K-1)/(K+1)"),
            ("LO2A", "L*sind(theta/2)"),
            ("LO3B", "(H/2)/sind(theta/2)"),
            ("ramX", "LO3B*(1+cosd(theta/2))/2"),
        ]
    )
    assert p["theta"] == pytest.approx(60, abs=1e-12)
    assert p["LO2A"] == pytest.approx(75, abs=1e-12)
    assert p["LO3B"] == pytest.approx(100, abs=1e-12)
    assert p["ramX"] == pytest.approx(93.30127018922193, abs=1e-12)
    assert list(p) == ["K", "H", "L", "theta", "LO2A", "LO3B", "ramX"]
    assert all(type(v) is float for v in p.values())


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1 + 2*3", 7.0),
        ("2**10", 1024.0),
        ("-2**2", -4.0),
        ("7 % 3", 1.0),
        ("7 // 2", 3.0),
        ("+3", 3.0),
        ("degrees(pi)", 180.0),
        ("radians(180)", math.pi),
        ("atan2d(1, 1)", 45.0),
        ("atan2d(0, -1)", 180.0),
        ("atan2(1, 0)", math.pi / 2),
        ("asind(0.5)", 30.0),
        ("acosd(0.5)", 60.0),
        ("atand(1)", 45.0),
        ("tand(45)", 1.0),
        ("sqrt(16)", 4.0),
        ("log(e)", 1.0),
        ("log(8, 2)", 3.0),
        ("log10(1000)", 3.0),
        ("exp(0)", 1.0),
        ("abs(-3)", 3.0),
        ("min(3)", 3.0),
        ("min(3, 1, 2)", 1.0),
        ("max(3, 1, 2)", 3.0),
        ("hypot(3, 4)", 5.0),
        ("floor(2.7)", 2.0),
        ("ceil(2.1)", 3.0),
        ("round(2.6)", 3.0),
        ("tau/2", math.pi),
        ("1e3", 1000.0),
        ("(-8)**2", 64.0),
    ],
)
def test_values(text, expected):
    result = evaluate(text, {})
    assert type(result) is float
    assert result == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_numbers_pass_through_and_env():
    assert evaluate(3, {}) == 3.0 and type(evaluate(3, {})) is float
    assert evaluate(2.5, {}) == 2.5
    assert evaluate("a*b", {"a": 2.0, "b": 3.0}) == 6.0
    assert evaluate("e", {"e": 5.0}) == 5.0  # a variable shadows a constant
    assert evaluate("e", {}) == math.e


def test_public_tables():
    assert set(CONSTANTS) == {"pi", "e", "tau"}
    assert "inf" not in CONSTANTS
    assert {"sind", "atan2d", "log", "round", "hypot"} <= set(FUNCTIONS)
    assert MAX_EXPRESSION_LENGTH == 1000


def test_names_in():
    assert names_in("a + sin(b) * pi") == {"a", "b", "pi"}
    assert names_in("3") == set()
    with pytest.raises(ExpressionError):
        names_in("a +")
    with pytest.raises(ExpressionError, match="attribute"):
        names_in("a.b")
    with pytest.raises(ExpressionError, match="function 'sin'"):
        names_in("sin + 1")


def test_dependency_order_forward_references():
    p = evaluate_parameters([("c", "a + b"), ("a", "b * 2"), ("b", 1)])
    assert p == {"c": 3.0, "a": 2.0, "b": 1.0}
    assert list(p) == ["c", "a", "b"]


def test_parameter_shadowing_constant():
    assert evaluate_parameters([("e", 5), ("x", "2*e")]) == {"e": 5.0, "x": 10.0}


@pytest.mark.parametrize(
    ("items", "message"),
    [
        ([("a", "b"), ("b", "a")], "parameters form a cycle: a -> b -> a"),
        ([("a", "a + 1")], "parameters form a cycle: a -> a"),
        (
            [("x", 1), ("a", "b"), ("b", "c"), ("c", "a")],
            "parameters form a cycle: a -> b -> c -> a",
        ),
    ],
)
def test_cycles(items, message):
    with pytest.raises(ExpressionError) as info:
        evaluate_parameters(items)
    assert str(info.value) == message


def test_undefined_name_with_suggestion():
    with pytest.raises(ExpressionError) as info:
        evaluate_parameters([("L1", 10), ("L2", "Lx * 2")])
    assert str(info.value) == "parameter 'L2': undefined name 'Lx' (did you mean 'L1'?)"
    assert info.value.name == "L2"


def test_undefined_name_in_evaluate():
    with pytest.raises(
        ExpressionError, match=r"undefined name 'lenght' \(did you mean 'length'\?\)"
    ):
        evaluate("lenght * 2", {"length": 1.0})
    with pytest.raises(ExpressionError, match="undefined name 'zzz'$"):
        evaluate("zzz", {})


def test_reserved_and_bad_parameter_names():
    with pytest.raises(ExpressionError) as info:
        evaluate_parameters([("sin", 1)])
    assert str(info.value) == "parameter name 'sin' is reserved for a function"
    assert info.value.name == "sin"
    with pytest.raises(ExpressionError, match="duplicate"):
        evaluate_parameters([("a", 1), ("a", 2)])
    with pytest.raises(ExpressionError, match="invalid parameter name"):
        evaluate_parameters([("1a", 1)])


def test_bad_parameter_values():
    with pytest.raises(ExpressionError, match="parameter 'a'") as info:
        evaluate_parameters([("a", [1])])
    assert info.value.name == "a"
    with pytest.raises(ExpressionError, match="parameter 'a'"):
        evaluate_parameters([("a", True)])
    with pytest.raises(ExpressionError, match="parameter 'b': division by zero"):
        evaluate_parameters([("a", 0), ("b", "1/a")])


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("__import__('os').system('ls')", "attribute access|call of '__import__'"),
        ("__import__('os')", "call of '__import__' is not allowed"),
        ("().__class__", "attribute access is not allowed"),
        ("(1).__class__", "attribute access is not allowed"),
        ("a.b", "attribute access is not allowed"),
        ("[1][0]", "subscripts are not allowed"),
        ("a[0]", "subscripts are not allowed"),
        ("lambda: 1", "lambda"),
        ("[x for x in y]", "comprehensions"),
        ("(x for x in y)", "comprehensions"),
        ("{x: 1 for x in y}", "comprehensions"),
        ("1 if a else 2", "conditional expressions"),
        ("1 < 2", "comparisons"),
        ("a and b", "boolean operators"),
        ("not a", "unary operator"),
        ("~1", "unary operator"),
        ("1 << 2", "operator"),
        ("1 & 2", "operator"),
        ("'abc'", "strings are not allowed"),
        ("b'abc'", "strings are not allowed"),
        ("f'{a}'", "f-strings are not allowed"),
        ("(a := 1)", "assignment expressions"),
        ("max(*a)", "starred"),
        ("round(2.5, ndigits=1)", "keyword arguments"),
        ("round(**a)", "keyword arguments"),
        ("True", "boolean literal 'True' is not allowed"),
        ("None", "not allowed"),
        ("1j", "complex numbers are not allowed"),
        ("(1, 2)", "tuples"),
        ("[1, 2]", "lists"),
        ("foo(1)", "call of 'foo' is not allowed"),
        ("sinn(1)", r"call of 'sinn' is not allowed \(did you mean 'sin'\?\)"),
        ("sin(1)(2)", "only calls of named functions"),
        ("sin", "function 'sin' cannot be used as a variable"),
        ("sqrt(1, 2)", r"sqrt\(\) takes 1 argument"),
        ("log(1, 2, 3)", r"log\(\) takes 1 or 2"),
        ("max()", r"max\(\) takes at least 1"),
        ("1 +", "syntax error"),
        ("", "empty expression"),
        ("   ", "empty expression"),
        ("x = 1", "syntax error"),
        ("import os", "syntax error"),
        ("1e999", "not finite"),
        ("1" * 400, "too large"),
    ],
)
def test_forbidden(text, message):
    with pytest.raises(ExpressionError, match=message):
        evaluate(text, {"a": 1.0, "b": 2.0, "y": 3.0})


@pytest.mark.parametrize("value", [True, None, "1", [1], float("inf"), float("nan")])
def test_evaluate_rejects_non_numbers(value):
    if isinstance(value, str):
        assert evaluate(value, {}) == 1.0
        return
    with pytest.raises(ExpressionError):
        evaluate(value, {})


@pytest.mark.timeout(30)  # computed, 9**9**9 would not finish: a hang, not a slow machine
def test_huge_power_refused_quickly():
    with pytest.raises(ExpressionError, match="exponent too large"):
        evaluate("9**9**9", {})


@pytest.mark.parametrize("text", ["10.0**400", "2**1001", "exp(1000)", "1e308*10", "1e308+1e308"])
def test_overflow(text):
    with pytest.raises(ExpressionError, match="not finite|exponent too large"):
        evaluate(text, {})


def test_too_long():
    text = "+".join(["1"] * 5000)[:10000]
    assert len(text) >= 9999
    with pytest.raises(ExpressionError, match="too long"):
        evaluate(text, {})
    with pytest.raises(ExpressionError, match="too long"):
        names_in("a" * (MAX_EXPRESSION_LENGTH + 1))


@pytest.mark.parametrize(
    "text",
    ["(" * 200 + "1" + ")" * 200, "-" * 60 + "1", "sin(" * 60 + "1" + ")" * 60, "1" + "+1" * 60],
)
@pytest.mark.timeout(30)
def test_deep_nesting(text):
    with pytest.raises(ExpressionError, match="nested too deeply"):
        evaluate(text, {})


def test_moderate_nesting_ok():
    assert evaluate("(" * 40 + "1" + ")" * 40, {}) == 1.0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("1/0", "division by zero"),
        ("1 // 0", "division by zero"),
        ("1 % 0", "division by zero"),
        ("0**-1", "division by zero"),
        ("asin(2)", r"math domain error in asin\(2\)"),
        ("sqrt(-1)", r"math domain error in sqrt\(-1\)"),
        ("log(0)", r"math domain error in log\(0\)"),
        ("acosd(2)", "math domain error"),
        ("(-8)**(1/3)", "math domain error"),
    ],
)
def test_domain_errors(text, message):
    with pytest.raises(ExpressionError, match=message):
        evaluate(text, {})


def test_expression_error_is_value_error():
    err = ExpressionError("x")
    assert isinstance(err, ValueError)
    assert err.name is None


@pytest.mark.parametrize(
    "text",
    [
        "120",
        "-0",
        "-0.0",
        "+.5",
        " 7 ",
        "1_000",
        "1e-3",
        "-2.5e2",
        "1e999",
        "0x10",
        "True",
        "a",
        " a ",
        "pi",
        "e",
        "tau",
        "sin",
        "undefined_one",
        "-a",
        "a*2",
        "nan",
        "inf",
        "",
    ],
)
def test_short_cuts_give_what_the_whole_evaluation_gives(text):
    """A lone number or name is evaluated without walking its tree (most numbers of a
    file): the same value, or the same error, as the tree walk gives."""
    from kinetostatics.base import expressions as ex

    env = {"a": 2.5, "pi": 3.0}  # a parameter may shadow a constant

    def outcome(f):
        try:
            return ("value", f())
        except ExpressionError as exc:
            return ("error", str(exc))

    def walked():
        tree = ex._parse(text)
        ex._names_of(text)
        return ex._eval_node(tree, env)

    got, want = outcome(lambda: evaluate(text, env)), outcome(walked)
    assert got == want
    if got[0] == "value":
        assert math.copysign(1.0, got[1]) == math.copysign(1.0, want[1])  # -0 stays -0


def test_a_plain_number_is_read_without_parsing_to_what_evaluate_gives():
    """``plain_number`` (the loader's short cut for numbers written plainly) gives the
    value and sign ``evaluate`` gives, or None; never a value for a text ``evaluate``
    refuses or reads otherwise (``-0`` is +0.0, ``007`` a syntax error, ``1e400`` not
    finite)."""
    import random

    rng = random.Random(3)
    digits = "0123456789"
    cases = ["0", "-0", "0.0", "-0.0", "007", "00.5", "1_000", "1e400", "-1e400", "1e-400"]
    cases += [".5", "-.5", "5.", "1E+05", "0x10", "+5", " 5", "\u0663", "1e", "e5", "-", "."]
    cases += ["9" * 400, "9" * 1001, "4.9e-324", "1.7976931348623157e308", "1.8e308"]
    for _ in range(4000):
        whole = rng.choice(["0", "00", "7", "", "".join(rng.choices(digits, k=rng.randint(1, 25)))])
        part = rng.choice(["", ".", "." + "".join(rng.choices(digits, k=rng.randint(1, 20)))])
        power = rng.choice(["", "e" + str(rng.randint(-330, 330)), "E+0" + str(rng.randint(0, 9))])
        cases.append(rng.choice(["", "-", "+"]) + whole + part + power)
    read = 0
    for text in cases:
        fast = plain_number(text)
        if fast is None:
            continue
        read += 1
        value = evaluate(text, {})  # raises if the short cut read a text evaluate refuses
        assert fast == value and math.copysign(1.0, fast) == math.copysign(1.0, value), text
    assert read > 1000  # the short cut is taken for most of them
    for text in ("-0", "007", "1_000", "1e400", "+5", " 5", "\u0663", "9" * 1001):
        assert plain_number(text) is None, text
    for text in ("007", "1e400"):
        with pytest.raises(ExpressionError):
            evaluate(text, {})
