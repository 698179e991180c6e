"""Objectives and constraints of an optimisation: expressions over a batch row.

An expression is read by the safe evaluator of the ``parameters:`` block
(:mod:`kinetostatics.base.expressions`: numbers, names, ``+ - * / ** % //``, the
functions ``sqrt``, ``max``, ``sind``, …; never Python's ``eval``).  Its names are the
quantities of a variant's batch row (:func:`~kinetostatics.batch.variants.summary_row`:
``slide.stroke``, ``motor.torque_rms``, ``shaking.force_peak``, … in SI units) and the
file's parameters (in the file's units).  A dotted name is not Python, so each is replaced
by a plain identifier before parsing.

>>> c = Constraint.parse("slide.stroke >= 0.1")
>>> c.op, c.left.text, c.right.text
('>=', 'slide.stroke', '0.1')
>>> round(c.violation({"slide.stroke": 0.09}), 12)  # (0.1 - 0.09) / 0.1
0.1
>>> Expression("sqrt(shaking.force_rms**2 + 1)").value({"shaking.force_rms": 0.0})
1.0
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from ..base.expressions import CONSTANTS, ExpressionError, evaluate, names_in
from ..errors import KinetostaticsError, did_you_mean

__all__ = ["OptimizeError", "Expression", "Constraint", "INFEASIBLE", "FAILED"]

INFEASIBLE = 1e15  # the score of an infeasible design: INFEASIBLE·(1 + its violation)
FAILED = 1e18  # the score of a design the batch could not analyse

# a dotted name (member.quantity), not preceded by a letter, digit, '_' or '.' (1.5e3 is
# safe); its parts are names in any script (刨头.stroke), none starting with a digit
DOTTED = re.compile(r"(?<![\w.])((?!\d)\w+(?:\.(?!\d)\w+)+)")
RELATION = re.compile(r"(<=|>=|==|<|>|=)")


class OptimizeError(KinetostaticsError, ValueError):
    """An optimisation that cannot start: a bad --vary, objective or constraint."""


@dataclass(frozen=True)
class Expression:
    """An expression over a row's quantities and the file's parameters."""

    text: str
    code: str = field(init=False)  # the text with dotted names replaced
    names: dict[str, str] = field(init=False)  # identifier -> the name written

    def __post_init__(self) -> None:
        names: dict[str, str] = {}

        def plain(m: re.Match) -> str:
            key = f"_q{len(names)}_"
            for k, v in names.items():
                if v == m.group(1):
                    return k
            names[key] = m.group(1)
            return key

        code = DOTTED.sub(plain, self.text.strip())
        try:
            used = names_in(code)
        except ExpressionError as exc:
            raise OptimizeError(f"{self.text!r}: {exc}") from None
        for n in used - set(names):
            names[n] = n
        object.__setattr__(self, "code", code)
        object.__setattr__(self, "names", {k: v for k, v in names.items() if k in used})

    def check_names(self, known: Iterable[str], what: str) -> None:
        """OptimizeError naming a name that is neither a row quantity nor a parameter."""
        known = list(known)

        for name in self.names.values():
            if name not in known and name not in CONSTANTS:
                raise OptimizeError(
                    f"{what} {self.text!r}: no quantity or parameter '{name}'"
                    f"{did_you_mean(name, known)}"
                )

    def value(self, env: Mapping[str, object]) -> float:
        """The value for a row and its parameters ``env``; NaN where a name has no finite
        value (a quantity this variant lacks) or the arithmetic fails (0/0)."""
        local = {}
        for key, name in self.names.items():
            try:
                v = float(env[name])  # type: ignore[arg-type]
            except (KeyError, TypeError, ValueError):
                return math.nan
            if not math.isfinite(v):
                return math.nan
            local[key] = v
        try:
            return evaluate(self.code, local)
        except ExpressionError:
            return math.nan


@dataclass(frozen=True)
class Constraint:
    """``LEFT <= RIGHT`` or ``LEFT >= RIGHT`` (``<``, ``>`` read as the same; both sides
    expressions).  Its violation is the amount by which it fails, divided by |RIGHT|
    (by 1 when RIGHT is 0): 0 when it holds, NaN when a side has no value."""

    text: str
    left: Expression
    op: str
    right: Expression

    @classmethod
    def parse(cls, text: str) -> Constraint:
        parts = RELATION.split(text)
        if len(parts) != 3 or parts[1] not in ("<=", ">=", "<", ">"):
            raise OptimizeError(
                f"--subject-to {text!r}: expected 'EXPR <= EXPR' or 'EXPR >= EXPR' (one comparison)"
            )
        left, op, right = parts
        if not left.strip() or not right.strip():
            raise OptimizeError(f"--subject-to {text!r}: an expression is missing")
        op = {"<": "<=", ">": ">="}.get(op, op)
        return cls(text.strip(), Expression(left.strip()), op, Expression(right.strip()))

    @property
    def names(self) -> list[str]:
        return [*self.left.names.values(), *self.right.names.values()]

    def check_names(self, known: Iterable[str]) -> None:
        known = list(known)
        self.left.check_names(known, "--subject-to")
        self.right.check_names(known, "--subject-to")

    def violation(self, env: Mapping[str, object]) -> float:
        lhs, rhs = self.left.value(env), self.right.value(env)
        if math.isnan(lhs) or math.isnan(rhs):
            return math.nan
        excess = lhs - rhs if self.op == "<=" else rhs - lhs
        return max(0.0, excess) / (abs(rhs) if rhs != 0 else 1.0)

    def margin(self, env: Mapping[str, object]) -> float:
        """RIGHT − LEFT for ``<=`` (LEFT − RIGHT for ``>=``), divided as the violation:
        ≥ 0 where it holds (a local optimiser's inequality)."""
        lhs, rhs = self.left.value(env), self.right.value(env)
        if math.isnan(lhs) or math.isnan(rhs):
            return math.nan
        slack = rhs - lhs if self.op == "<=" else lhs - rhs
        return slack / (abs(rhs) if rhs != 0 else 1.0)
