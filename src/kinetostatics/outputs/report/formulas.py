"""The dimension synthesis: each parameter expression of the file as a formula with its value.

:func:`formula` writes an expression of the ``parameters:`` block in mathematical form
from its syntax tree (the parser of :mod:`kinetostatics.base.expressions`, so exactly what
the loader evaluated): Greek names as letters (``theta`` → θ, ``theta_1`` → θ_1), ``*`` as
×, ``-`` as −, powers 2 and 3 as ², ³, ``sqrt`` as √, ``abs`` as |…|, the trigonometry in
degrees (``sind``, ``asind``, …) as sin, arcsin, …, the one in radians marked ``_rad``
(``sin_rad``), parentheses only where the order of operations needs them.
:func:`synthesis_rows` gives the report's rows: ``θ = 180×(K − 1)/(K + 1) = 60``.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Mapping

from ...base.expressions import _parse

__all__ = ["formula", "symbol", "synthesis_rows"]

_GREEK = {
    "alpha": "α",
    "beta": "β",
    "gamma": "γ",
    "delta": "δ",
    "epsilon": "ε",
    "zeta": "ζ",
    "eta": "η",
    "theta": "θ",
    "kappa": "κ",
    "lambda": "λ",
    "mu": "μ",
    "nu": "ν",
    "xi": "ξ",
    "pi": "π",
    "rho": "ρ",
    "sigma": "σ",
    "tau": "τ",
    "phi": "φ",
    "chi": "χ",
    "psi": "ψ",
    "omega": "ω",
    "Gamma": "Γ",
    "Delta": "Δ",
    "Theta": "Θ",
    "Lambda": "Λ",
    "Sigma": "Σ",
    "Phi": "Φ",
    "Psi": "Ψ",
    "Omega": "Ω",
}
# the functions written by another name: degrees' trigonometry plain, radians' marked
_NAMES = {
    "sind": "sin",
    "cosd": "cos",
    "tand": "tan",
    "asind": "arcsin",
    "acosd": "arccos",
    "atand": "arctan",
    "atan2d": "atan2",
    "sin": "sin_rad",
    "cos": "cos_rad",
    "tan": "tan_rad",
    "asin": "arcsin_rad",
    "acos": "arccos_rad",
    "atan": "arctan_rad",
    "atan2": "atan2_rad",
    "log": "ln",
}
_DEGREES = ("sind", "cosd", "tand")
_OPS = {
    ast.Add: (" + ", 1),
    ast.Sub: (" − ", 1),
    ast.Mult: ("×", 2),
    ast.Div: ("/", 2),
    ast.Mod: (" mod ", 2),
    ast.FloorDiv: (" div ", 2),
    ast.Pow: ("^", 4),
}
_ATOM = 5  # a name, a number, a call
_SUPERSCRIPT = {2: "²", 3: "³"}


def symbol(name: str) -> str:
    """A parameter's name as a symbol: its leading Greek word as the letter (``theta2`` → θ2)."""
    m = re.match(r"^([A-Za-z]+)(.*)$", name)
    if m and m.group(1) in _GREEK:
        return _GREEK[m.group(1)] + m.group(2)
    return name


def _number(value) -> str:
    text = f"{value:.12g}"
    return text.replace("-", "−")


def _call(node: ast.Call) -> str:
    name = node.func.id
    args = [_text(a)[0] for a in node.args]
    if name == "sqrt":
        inner, prec = _text(node.args[0])
        return "√" + (inner if prec >= _ATOM else f"({inner})")
    if name == "abs":
        return f"|{args[0]}|"
    if name == "floor":
        return f"⌊{args[0]}⌋"
    if name == "ceil":
        return f"⌈{args[0]}⌉"
    if name in _DEGREES and isinstance(node.args[0], ast.Constant):
        args[0] += "°"  # sin(300°)
    return f"{_NAMES.get(name, name)}({', '.join(args)})"


def _binop(node: ast.BinOp) -> tuple[str, int]:
    op, prec = _OPS[type(node.op)]
    left, lp = _text(node.left)
    right, rp = _text(node.right)
    if isinstance(node.op, ast.Pow):
        left = left if lp >= _ATOM else f"({left})"
        value = node.right.value if isinstance(node.right, ast.Constant) else None
        if value in _SUPERSCRIPT and not isinstance(value, bool):
            return left + _SUPERSCRIPT[value], prec
        return f"{left}^{right if rp >= _ATOM else f'({right})'}", prec
    if lp < prec or (isinstance(node.op, ast.Div) and _is_div(node.left)):
        left = f"({left})"  # (H/2)/sin(θ/2), as it is written
    # a right operand of the same level keeps its parentheses: a − (b + c), a/(b×c)
    if rp < prec or (rp == prec and not isinstance(node.op, (ast.Add, ast.Mult))):
        right = f"({right})"
    return left + op + right, prec


def _is_div(node: ast.AST) -> bool:
    return isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div)


def _text(node: ast.AST) -> tuple[str, int]:
    """The formula of ``node`` and the binding level of its outermost operation."""
    if isinstance(node, ast.Expression):
        return _text(node.body)
    if isinstance(node, ast.Constant):
        return _number(node.value), _ATOM
    if isinstance(node, ast.Name):
        return symbol(node.id), _ATOM
    if isinstance(node, ast.Call):
        return _call(node), _ATOM
    if isinstance(node, ast.UnaryOp):
        inner, prec = _text(node.operand)
        sign = "−" if isinstance(node.op, ast.USub) else "+"
        return sign + (inner if prec >= 3 else f"({inner})"), 3
    return _binop(node)


def formula(text: str) -> str:
    """The expression ``text`` of the ``parameters:`` block in mathematical form.

    >>> formula("180*(K - 1)/(K + 1)")
    '180×(K − 1)/(K + 1)'
    >>> formula("L_O2O3*sind(theta/2)")
    'L_O2O3×sin(θ/2)'
    """
    return _text(_parse(text))[0]


def synthesis_rows(texts: Mapping[str, str], values: Mapping[str, float]) -> list[list[str]]:
    """``[name, "symbol = formula = value"]`` for each parameter written as an expression
    (a plain number is data, not synthesis), in the file's order."""
    rows = []
    for name, text in texts.items():
        tree = _parse(text)
        body = tree.body
        if isinstance(body, ast.Constant) or (
            isinstance(body, ast.UnaryOp) and isinstance(body.operand, ast.Constant)
        ):
            continue
        if name not in values:
            continue
        value = _number(float(f"{values[name]:.6g}"))
        rows.append([name, f"{symbol(name)} = {formula(text)} = {value}"])
    return rows
