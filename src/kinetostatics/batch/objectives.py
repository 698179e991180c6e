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
import sys
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from ..base.expressions import CONSTANTS, ExpressionError, evaluate, names_in
from ..errors import KinetostaticsError, did_you_mean

__all__ = ["OptimizeError", "Expression", "Constraint", "INFEASIBLE", "FAILED", "parse_vary"]

INFEASIBLE = 1e15  # the score of an infeasible design: INFEASIBLE·(1 + its violation)
FAILED = 1e18  # the score of a design the batch could not analyse
# |LO|, |HI| of a --vary at most half the largest float: the search's designs are
# midpoint + u·span, and both stay finite
MAX_BOUND = sys.float_info.max / 2

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


def parse_vary(items: Sequence[str] | Mapping[str, Sequence[float]]) -> dict[str, tuple]:
    """``["NAME=LO:HI", …]`` or ``{NAME: (LO, HI)}`` → ``{NAME: (LO, HI)}``."""
    out: dict[str, tuple[float, float]] = {}
    pairs = items.items() if isinstance(items, Mapping) else [_split_vary(t) for t in items]
    for name, bounds in pairs:
        try:
            lo, hi = (float(b) for b in bounds)
        except (TypeError, ValueError):
            raise OptimizeError(f"--vary {name}: expected LO:HI, got {bounds!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise OptimizeError(f"--vary {name}={lo:g}:{hi:g}: needs finite LO < HI")
        if max(abs(lo), abs(hi)) > MAX_BOUND:
            # the search works on the midpoint and the span, which must stay finite
            raise OptimizeError(
                f"--vary {name}={lo:g}:{hi:g}: bounds beyond ±{MAX_BOUND:.4g} (half the "
                "largest float) would give designs that are not finite numbers"
            )
        if name in out:
            raise OptimizeError(f"--vary {name}: named twice; give each parameter once")
        out[name] = (lo, hi)
    if not out:
        raise OptimizeError("nothing to vary: give --vary NAME=LO:HI")
    return out


def _split_vary(text: str) -> tuple[str, tuple[str, ...]]:
    name, eq, rest = text.partition("=")
    bounds = tuple(rest.split(":"))
    if not eq or not name.strip() or len(bounds) != 2:
        raise OptimizeError(f"--vary {text!r}: expected NAME=LO:HI")
    return name.strip(), bounds
