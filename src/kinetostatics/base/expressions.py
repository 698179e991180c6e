"""Safe arithmetic evaluation of the ``parameters:`` block of model files.

Expressions are parsed with :func:`ast.parse` and evaluated by walking the
syntax tree against a whitelist; Python's ``eval``/``exec`` are never used.
Only numbers, variable names, the constants in :data:`CONSTANTS`, the
operators ``+ - * / ** % //`` (and unary ``+``/``-``), parentheses and calls
of the functions in :data:`FUNCTIONS` are accepted. All arithmetic is done on
Python floats and every result is checked to be finite.

Examples
--------
>>> evaluate("L*sind(theta/2)", {"L": 150.0, "theta": 60.0})
74.99999999999999
>>> evaluate_parameters([("K", 2), ("theta", "180*(K-1)/(K+1)")])
{'K': 2.0, 'theta': 60.0}
"""

from __future__ import annotations

import ast
import functools
import math
import numbers
import unicodedata
from collections.abc import Callable, Iterable, Mapping, Sequence
from types import MappingProxyType

from .names import is_name, is_word_character

__all__ = [
    "CONSTANTS",
    "FUNCTIONS",
    "MAX_EXPRESSION_LENGTH",
    "ExpressionError",
    "evaluate",
    "evaluate_parameters",
    "names_in",
]

MAX_EXPRESSION_LENGTH = 1000
"""Longest accepted expression, in characters."""

MAX_DEPTH = 50
"""Deepest accepted nesting (syntax-tree depth and parenthesis depth)."""

MAX_EXPONENT = 1000.0
"""Largest accepted absolute value of the right operand of ``**``."""


class ExpressionError(ValueError):
    """A parameter expression is malformed, refers to an unknown name, or fails to evaluate.

    Parameters
    ----------
    message : str
        Human-readable description of the problem.
    name : str or None, optional
        Name of the parameter at fault, if known.

    Attributes
    ----------
    name : str or None
        Name of the parameter at fault, or None.
    """

    def __init__(self, message: str, name: str | None = None) -> None:
        super().__init__(message)
        self.name = name


def _sind(x: float) -> float:
    return math.sin(math.radians(x))


def _cosd(x: float) -> float:
    return math.cos(math.radians(x))


def _tand(x: float) -> float:
    return math.tan(math.radians(x))


def _asind(x: float) -> float:
    return math.degrees(math.asin(x))


def _acosd(x: float) -> float:
    return math.degrees(math.acos(x))


def _atand(x: float) -> float:
    return math.degrees(math.atan(x))


def _atan2d(y: float, x: float) -> float:
    return math.degrees(math.atan2(y, x))


def _min(*args: float) -> float:
    return min(args)


def _max(*args: float) -> float:
    return max(args)


# name -> (function, minimum arity, maximum arity or None for unbounded)
_SIGNATURES: dict[str, tuple[Callable[..., float], int, int | None]] = {
    "sqrt": (math.sqrt, 1, 1),
    "sin": (math.sin, 1, 1),
    "cos": (math.cos, 1, 1),
    "tan": (math.tan, 1, 1),
    "asin": (math.asin, 1, 1),
    "acos": (math.acos, 1, 1),
    "atan": (math.atan, 1, 1),
    "atan2": (math.atan2, 2, 2),
    "sind": (_sind, 1, 1),
    "cosd": (_cosd, 1, 1),
    "tand": (_tand, 1, 1),
    "asind": (_asind, 1, 1),
    "acosd": (_acosd, 1, 1),
    "atand": (_atand, 1, 1),
    "atan2d": (_atan2d, 2, 2),
    "radians": (math.radians, 1, 1),
    "degrees": (math.degrees, 1, 1),
    "exp": (math.exp, 1, 1),
    "log": (math.log, 1, 2),
    "log10": (math.log10, 1, 1),
    "abs": (abs, 1, 1),
    "min": (_min, 1, None),
    "max": (_max, 1, None),
    "hypot": (math.hypot, 1, None),
    "floor": (math.floor, 1, 1),
    "ceil": (math.ceil, 1, 1),
    "round": (round, 1, 1),
}

FUNCTIONS: Mapping[str, Callable[..., float]] = MappingProxyType(
    {name: sig[0] for name, sig in _SIGNATURES.items()}
)
"""Whitelisted functions callable from expressions (radians; the ``*d`` ones degrees)."""

CONSTANTS: Mapping[str, float] = MappingProxyType({"pi": math.pi, "e": math.e, "tau": math.tau})
"""Named constants; a variable of the same name (e.g. an eccentricity ``e``) shadows them."""

_BINARY_OPS: dict[type[ast.operator], str] = {
    ast.Add: "+",
    ast.Sub: "-",
    ast.Mult: "*",
    ast.Div: "/",
    ast.Pow: "**",
    ast.Mod: "%",
    ast.FloorDiv: "//",
}

_FORBIDDEN: dict[type[ast.AST], str] = {
    ast.Attribute: "attribute access is not allowed",
    ast.Subscript: "subscripts are not allowed",
    ast.Lambda: "lambda expressions are not allowed",
    ast.ListComp: "comprehensions are not allowed",
    ast.SetComp: "comprehensions are not allowed",
    ast.DictComp: "comprehensions are not allowed",
    ast.GeneratorExp: "comprehensions are not allowed",
    ast.IfExp: "conditional expressions are not allowed",
    ast.Compare: "comparisons are not allowed",
    ast.BoolOp: "boolean operators are not allowed",
    ast.JoinedStr: "f-strings are not allowed",
    ast.FormattedValue: "f-strings are not allowed",
    ast.NamedExpr: "assignment expressions (:=) are not allowed",
    ast.Starred: "starred arguments are not allowed",
    ast.keyword: "keyword arguments are not allowed",
    ast.List: "lists are not allowed",
    ast.Tuple: "tuples are not allowed",
    ast.Set: "sets are not allowed",
    ast.Dict: "dicts are not allowed",
    ast.Slice: "slices are not allowed",
    ast.Await: "await is not allowed",
    ast.Yield: "yield is not allowed",
    ast.YieldFrom: "yield is not allowed",
}


def _fmt(x: float) -> str:
    """Format a number compactly for error messages."""
    return f"{x:.12g}"


def _suggest(word: str, candidates: Iterable[str]) -> str:
    """Return ``" (did you mean 'x'?)"`` for the closest candidate, or ``""``."""
    import difflib  # on the error path only

    matches = difflib.get_close_matches(word, sorted(set(candidates)), n=1, cutoff=0.5)
    return f" (did you mean '{matches[0]}'?)" if matches else ""


def _to_float(value: object) -> float:
    """Convert a literal number to a finite float, refusing bools and complex numbers."""
    if type(value) is float and math.isfinite(value):  # the usual case, without the ABC
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ExpressionError(f"expected a number or expression, got {type(value).__name__}")
    try:
        result = float(value)
    except OverflowError:
        raise ExpressionError("number is too large") from None
    if not math.isfinite(result):
        raise ExpressionError("number is not finite")
    return result


def _check_depth(tree: ast.AST) -> None:
    """Refuse syntax trees nested deeper than :data:`MAX_DEPTH` (iteratively)."""
    # A level is an operation (an expression node with operands): ``-(-1)`` is nested 2
    # deep, ``1`` 0 deep; operator and context nodes (``USub``, ``Load``) are not levels.
    stack: list[tuple[ast.AST, int, int]] = [(tree, 0, 0)]
    while stack:
        node, depth, nodes = stack.pop()
        level = depth + (
            isinstance(node, ast.expr) and not isinstance(node, (ast.Constant, ast.Name))
        )
        if level > MAX_DEPTH or nodes > 4 * MAX_DEPTH:
            raise ExpressionError(f"expression is nested too deeply (more than {MAX_DEPTH} levels)")
        stack.extend((child, level, nodes + 1) for child in ast.iter_child_nodes(node))


def _check_node(node: ast.AST) -> None:
    """Refuse any construct outside the whitelist."""
    if (message := _FORBIDDEN.get(type(node))) is not None:  # the parser's own classes
        raise ExpressionError(message)
    if isinstance(node, ast.Constant):
        value = node.value
        if isinstance(value, bool):
            raise ExpressionError(f"boolean literal '{value}' is not allowed")
        if isinstance(value, (str, bytes)):
            raise ExpressionError("strings are not allowed")
        if isinstance(value, complex):
            raise ExpressionError("complex numbers are not allowed")
        if not isinstance(value, (int, float)):
            raise ExpressionError(f"literal '{value!r}' is not allowed")
    elif isinstance(node, ast.BinOp):
        if type(node.op) not in _BINARY_OPS:
            raise ExpressionError(f"operator '{type(node.op).__name__}' is not allowed")
    elif isinstance(node, ast.UnaryOp):
        if not isinstance(node.op, (ast.UAdd, ast.USub)):
            raise ExpressionError(f"unary operator '{type(node.op).__name__}' is not allowed")
    elif isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name):
            if isinstance(node.func, ast.Attribute):
                raise ExpressionError("attribute access is not allowed")
            raise ExpressionError("only calls of named functions are allowed")
        fname = node.func.id
        if fname not in FUNCTIONS:
            raise ExpressionError(f"call of '{fname}' is not allowed" + _suggest(fname, FUNCTIONS))
        if node.keywords:
            raise ExpressionError("keyword arguments are not allowed")
        _, lo, hi = _SIGNATURES[fname]
        n = len(node.args)
        if n < lo or (hi is not None and n > hi):
            expected = (
                str(lo) if lo == hi else (f"{lo} or {hi}" if hi is not None else f"at least {lo}")
            )
            raise ExpressionError(f"{fname}() takes {expected} argument(s), got {n}")
    elif isinstance(node, ast.Name):
        pass
    elif not isinstance(node, (ast.Expression, ast.Load, ast.operator, ast.unaryop)):
        raise ExpressionError(f"'{type(node).__name__}' is not allowed")


def _parse(text: str) -> ast.Expression:
    """Parse and validate an expression string, returning its syntax tree.

    Trees are cached by text (they are never modified): a batch of variants
    re-reads the same expressions with other parameter values.
    """
    if not isinstance(text, str):
        raise ExpressionError(f"expected a number or expression, got {type(text).__name__}")
    return _parse_cached(text)


@functools.lru_cache(maxsize=4096)
def _parse_cached(text: str) -> ast.Expression:
    if not isinstance(text, str):
        raise ExpressionError(f"expected a number or expression, got {type(text).__name__}")
    if len(text) > MAX_EXPRESSION_LENGTH:
        raise ExpressionError(
            f"expression is too long ({len(text)} characters, at most {MAX_EXPRESSION_LENGTH})"
        )
    if not text.strip():
        raise ExpressionError("empty expression")
    if not text.isascii():
        # a name may be written in any script (曲柄), in the form Python's parser gives it
        # (NFKC): anything else beyond ASCII is refused, as '100*ℯ' would read as '100*e'
        bad = [k for k, ch in enumerate(text) if ord(ch) > 127 and not is_word_character(ch)]
        if not bad and unicodedata.normalize("NFKC", text) != text:
            bad = [next(k for k, ch in enumerate(text) if ord(ch) > 127)]
        if bad:
            k = bad[0]
            ch = text[k]
            shown = f"'{ch}'" if ch.isprintable() else ascii(ch)[1:-1]
            raise ExpressionError(
                f"the character {shown} (U+{ord(ch):04X}) at position "
                f"{k + 1} is not allowed in an expression: numbers and operators are "
                "plain ASCII, names are letters, digits and _"
            )
    depth = max_depth = 0
    for ch in text:
        if ch in "([{":
            depth += 1
            max_depth = max(max_depth, depth)
        elif ch in ")]}":
            depth -= 1
    if max_depth > MAX_DEPTH:
        raise ExpressionError(f"expression is nested too deeply (more than {MAX_DEPTH} levels)")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"syntax error in '{text.strip()}': {exc.msg}") from None
    except (RecursionError, MemoryError):
        raise ExpressionError("expression is nested too deeply") from None
    except ValueError as exc:  # e.g. null bytes
        raise ExpressionError(f"invalid expression: {exc}") from None
    _check_depth(tree)
    for node in ast.walk(tree):
        _check_node(node)
    return tree


def _variable_names(tree: ast.AST) -> list[str]:
    """Variable names in order of first appearance (function names in call position excluded)."""
    called: set[int] = set()  # a call's function: ast.walk meets the call first
    names: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            called.add(id(node.func))
        elif isinstance(node, ast.Name) and id(node) not in called:
            if node.id in FUNCTIONS:
                raise ExpressionError(f"function '{node.id}' cannot be used as a variable")
            if node.id not in names:
                names.append(node.id)
    return names


def names_in(text: str) -> set[str]:
    """Names (variables, not functions) an expression refers to.

    Parameters
    ----------
    text : str
        The expression.

    Returns
    -------
    set of str
        Variable names used, including constant names such as ``pi`` (which
        a variable of the same name would shadow).

    Raises
    ------
    ExpressionError
        On a syntax error or a forbidden construct.
    """
    return set(_names_of(text))


@functools.lru_cache(maxsize=4096)
def _names_of(text: str) -> tuple[str, ...]:
    return tuple(_variable_names(_parse(text)))


def _finite(value: float, what) -> float:
    if isinstance(value, complex) or not math.isfinite(value):
        raise ExpressionError(f"result is not finite in {what}")
    return float(value)


class _Operation(tuple):  # '2 / 0', formatted for an error only (a build evaluates thousands)
    def __str__(self) -> str:
        return f"{_fmt(self[0])} {self[1]} {_fmt(self[2])}"


def _eval_node(node: ast.AST, env: Mapping[str, float]) -> float:
    """Evaluate a validated syntax-tree node."""
    if isinstance(node, ast.Expression):
        return _eval_node(node.body, env)
    if isinstance(node, ast.Constant):
        return _to_float(node.value)
    if isinstance(node, ast.Name):
        if node.id in env:
            return _to_float(env[node.id])
        if node.id in CONSTANTS:
            return CONSTANTS[node.id]
        raise ExpressionError(f"undefined name '{node.id}'" + _suggest(node.id, [*env, *CONSTANTS]))
    if isinstance(node, ast.UnaryOp):
        operand = _eval_node(node.operand, env)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.BinOp):
        return _eval_binop(node, env)
    if isinstance(node, ast.Call):
        assert isinstance(node.func, ast.Name)
        fname = node.func.id
        args = [_eval_node(arg, env) for arg in node.args]
        call = f"{fname}({', '.join(_fmt(a) for a in args)})"
        try:
            result = FUNCTIONS[fname](*args)
        except (ValueError, TypeError):
            raise ExpressionError(f"math domain error in {call}") from None
        except OverflowError:
            raise ExpressionError(f"result is not finite in {call}") from None
        except ZeroDivisionError:
            raise ExpressionError(f"division by zero in {call}") from None
        return _finite(float(result), call)
    raise ExpressionError(f"'{type(node).__name__}' is not allowed")  # pragma: no cover


def _eval_binop(node: ast.BinOp, env: Mapping[str, float]) -> float:
    """Evaluate a binary operation with overflow and domain checks."""
    left, right = _eval_node(node.left, env), _eval_node(node.right, env)
    symbol = _BINARY_OPS[type(node.op)]
    what = _Operation((left, symbol, right))
    try:
        if symbol == "+":
            result = left + right
        elif symbol == "-":
            result = left - right
        elif symbol == "*":
            result = left * right
        elif symbol == "/":
            result = left / right
        elif symbol == "%":
            result = left % right
        elif symbol == "//":
            result = left // right
        else:
            if abs(right) > MAX_EXPONENT:
                raise ExpressionError(
                    f"exponent too large in {what} (|exponent| > {MAX_EXPONENT:g})"
                )
            if left < 0 and not right.is_integer():
                raise ExpressionError(f"math domain error in {what}")
            result = left**right
    except ZeroDivisionError:
        raise ExpressionError(f"division by zero in {what}") from None
    except OverflowError:
        raise ExpressionError(f"result is not finite in {what}") from None
    return _finite(result, what)


def evaluate(text: str | int | float, env: Mapping[str, float]) -> float:
    """Evaluate one expression with the given variables.

    Parameters
    ----------
    text : str or int or float
        The expression; a number passes through as a float.
    env : mapping of str to float
        Variable values. Variables shadow constants of the same name.

    Returns
    -------
    float
        The finite result.

    Raises
    ------
    ExpressionError
        If the expression is malformed, refers to an unknown name, or fails to
        evaluate (division by zero, domain error, overflow).
    """
    if not isinstance(text, str):
        return _to_float(text)
    kind, value = _shape(text)
    if kind is _NUMBER:
        return value
    if kind is _NAME and value in env:
        return _to_float(env[value])
    tree = _parse(text)
    _names_of(text)  # refuses a function used as a variable
    return _eval_node(tree, env)


_NUMBER, _NAME, _OTHER = "number", "name", "other"


@functools.lru_cache(maxsize=4096)
def _shape(text: str) -> tuple[str, object]:
    """What an expression is, for :func:`evaluate`'s short cuts (most numbers of a file are
    written as numbers): a number, with its value as the evaluation gives it; one
    variable's name; or anything else (an error included: the evaluation reports it)."""
    try:
        body = _parse(text).body
        if isinstance(body, ast.Name):
            return (_NAME, body.id) if _names_of(text) else (_OTHER, None)
        if isinstance(body, ast.Constant) or (
            isinstance(body, ast.UnaryOp) and isinstance(body.operand, ast.Constant)
        ):
            return _NUMBER, _eval_node(body, {})
    except ExpressionError:
        pass
    return _OTHER, None


def _check_parameter_name(name: object) -> str:
    if not is_name(name, expression=True):
        raise ExpressionError(f"invalid parameter name {name!r}", None)
    if name in FUNCTIONS:
        raise ExpressionError(f"parameter name '{name}' is reserved for a function", name)
    return name


def _dependency_order(deps: Mapping[str, list[str]]) -> list[str]:
    """Order parameters so each comes after its dependencies; raise on cycles."""
    done: set[str] = set()
    order: list[str] = []
    for root in deps:
        if root in done:
            continue
        path: list[str] = [root]
        on_path = {root}
        iters = [iter(deps[root])]
        while iters:
            child = next(iters[-1], None)
            if child is None:
                node = path.pop()
                on_path.discard(node)
                iters.pop()
                done.add(node)
                order.append(node)
            elif child in on_path:
                cycle = path[path.index(child) :] + [child]
                raise ExpressionError(f"parameters form a cycle: {' -> '.join(cycle)}", child)
            elif child not in done:
                path.append(child)
                on_path.add(child)
                iters.append(iter(deps[child]))
    return order


def evaluate_parameters(items: Sequence[tuple[str, object]]) -> dict[str, float]:
    """Evaluate an ordered list of ``(name, expression)`` pairs.

    Each expression may refer to any other parameter (before or after it);
    parameters are evaluated in dependency order.

    Parameters
    ----------
    items : sequence of (str, object)
        Parameter names with their expressions (strings) or numbers.

    Returns
    -------
    dict of str to float
        Parameter values, in the order given.

    Raises
    ------
    ExpressionError
        With a message naming the parameter (e.g. ``"parameter 'L2': undefined
        name 'Lx' (did you mean 'L1'?)"``) and ``.name`` set to it, or for a
        dependency cycle (``"parameters form a cycle: a -> b -> a"``).
    """
    exprs: dict[str, object] = {}
    for item in items:
        name, expr = item
        _check_parameter_name(name)
        if name in exprs:
            raise ExpressionError(f"duplicate parameter '{name}'", name)
        exprs[name] = expr

    trees: dict[str, ast.Expression | float] = {}
    deps: dict[str, list[str]] = {}
    for name, expr in exprs.items():
        try:
            if isinstance(expr, str):
                tree = _parse(expr)
                used = _names_of(expr)  # kept by text, as the trees: a batch re-reads them
                for var in used:
                    if var not in exprs and var not in CONSTANTS:
                        known = [n for n in exprs if n != name]
                        raise ExpressionError(
                            f"undefined name '{var}'" + _suggest(var, [*known, *CONSTANTS])
                        )
                trees[name] = tree
                deps[name] = [var for var in used if var in exprs]
            else:
                trees[name] = _to_float(expr)
                deps[name] = []
        except ExpressionError as exc:
            raise ExpressionError(f"parameter '{name}': {exc}", name) from None

    values: dict[str, float] = {}
    for name in _dependency_order(deps):
        tree = trees[name]
        if isinstance(tree, float):
            values[name] = tree
            continue
        try:
            values[name] = _eval_node(tree, values)
        except ExpressionError as exc:
            raise ExpressionError(f"parameter '{name}': {exc}", name) from None
    return {name: values[name] for name in exprs}
