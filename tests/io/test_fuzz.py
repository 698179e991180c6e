"""Fuzzing: a mutated mechanism file is accepted or refused with a user error.

Every shipped file in ``mechanisms/`` is mutated and fed through the whole
pipeline: ``kinetostatics.loads`` (or ``load`` for byte-level edits), then,
only when it loads, ``build_system`` and ``analyze`` with at most
:data:`ANALYSED_POSITIONS` positions, and for a file with ``drive:`` or
``flywheel:`` the summary (the drive's sizing, the flywheel's design).  Each
stage must either succeed or raise :class:`kinetostatics.KinetostaticsError`;
any other exception fails the test, and so does an example that runs longer
than :data:`DEADLINE` seconds (a hard per-example deadline by ``SIGALRM``, which
interrupts a real hang).

Two kinds of mutation:

* *data level* (``test_fuzz_data_level``): the file is read with
  ``yaml.safe_load``, 1 to 4 edits are made to the Python structure and it is
  written back with ``yaml.safe_dump``: deleting keys, swapping value types
  (number, string, list, mapping, null, bool), odd numbers (nan, ±inf, 1e308,
  huge integers, negative, zero, tiny), random unicode text, unicode keys,
  deep nesting, renaming references (to another name of the file, a typo,
  or random text; also renaming a link everywhere), random expressions from a
  grammar that also produces forbidden constructs, and appended junk keys;
* *text level* (``test_fuzz_text_level``): random character edits of the
  text (insert, delete, replace, duplicate a line, hence duplicate keys, swap
  lines, truncate) with YAML punctuation, tabs, control and unicode
  characters; one example in four edits the UTF-8 *bytes* and goes through
  ``kinetostatics.load`` of a temporary file.

Number of cases: 1,000 by default, 350 data level and 650 text level (deterministic:
``derandomize=True``).  ``KINETOSTATICS_FUZZ_EXAMPLES=N`` runs about N cases
in all, 60 % data level and 40 % text level, with fresh randomness
(``KINETOSTATICS_FUZZ_SEED`` fixes it; with ``KINETOSTATICS_FUZZ_KEEP=DIR`` the counts
so far are also written to ``DIR/counts-*.json`` every 100 cases, for a run that is
stopped before its report).  The number of cases actually run and
their outcomes are reported as a :class:`FuzzReport` warning, so they appear in
the "warnings summary" of a normal pytest run, e.g.::

    KINETOSTATICS_FUZZ_EXAMPLES=100000 python -m pytest tests/io/test_fuzz.py -p no:cacheprovider

The record of the long run is in ``docs/errors.md``.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import os
import signal
import string
import tempfile
import threading
import time
import traceback
import warnings
from collections import Counter
from pathlib import Path

import pytest
import yaml

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, seed, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import kinetostatics as ks  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SOURCES = {
    p.name: p.read_text(encoding="utf-8") for p in sorted((ROOT / "mechanisms").glob("*.yaml"))
}
DATA = {name: yaml.safe_load(text) for name, text in SOURCES.items()}


# The seeds: the shipped files plus variants that use every section and option the loader
# accepts (tests/seeds.py; tests/io/test_hostile_keys.py checks that they cover every key).
from tests.seeds import SEEDS  # noqa: E402

for _name, _doc in SEEDS.items():
    DATA[_name] = _doc
    SOURCES[_name] = yaml.safe_dump(_doc, sort_keys=False)


DEFAULT_EXAMPLES = 350  # data level (most of the time: it analyses more)
DEFAULT_TEXT_EXAMPLES = 650  # text level: 1,000 cases in all by default
TOTAL = int(os.environ.get("KINETOSTATICS_FUZZ_EXAMPLES", "0") or 0)
LONG = TOTAL > 0
DATA_EXAMPLES = max(1, round(0.6 * TOTAL)) if LONG else DEFAULT_EXAMPLES
TEXT_EXAMPLES = max(1, TOTAL - DATA_EXAMPLES) if LONG else DEFAULT_TEXT_EXAMPLES
DEADLINE = float(os.environ.get("KINETOSTATICS_FUZZ_DEADLINE", "20"))  # s per example
ANALYSED_POSITIONS = 4
SEED = os.environ.get("KINETOSTATICS_FUZZ_SEED")
KEEP = (
    Path(os.environ["KINETOSTATICS_FUZZ_KEEP"])
    if os.environ.get("KINETOSTATICS_FUZZ_KEEP")
    else None
)  # folder for the cases slower than 1 s (and crashes)
CONTINUE = os.environ.get("KINETOSTATICS_FUZZ_CONTINUE", "") not in ("", "0")
"""Count crashes and hangs and go on (the test fails at the end) instead of stopping at the
first one and shrinking it: for long runs, to see every kind of crash at once."""


ALARM = hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
"""The hard deadline needs SIGALRM (POSIX, main thread); elsewhere only the time is reported."""


class FuzzReport(UserWarning):
    """The number of fuzz cases run and their outcomes (shown in the warnings summary)."""


class _Hang(BaseException):
    """Raised by the alarm; a BaseException so no ``except Exception`` in the library hides it."""


def _alarm(signum, frame):
    raise _Hang


def _settings(n: int):
    return settings(
        max_examples=n,
        deadline=None,
        database=None,
        derandomize=not LONG,
        print_blob=True,
        suppress_health_check=list(HealthCheck),
    )


def _seeded(f):
    return seed(int(SEED))(f) if SEED else f


# -- the pipeline -------------------------------------------------------------------
def exercise(counter: Counter, *, text: str | None = None, path: Path | None = None) -> str:
    """Load (``text`` or ``path``), build and analyse; the stage reached.

    Raises whatever the library raises except :class:`~kinetostatics.KinetostaticsError`,
    or an ``AssertionError`` past the deadline.
    """
    counter["cases"] += 1
    if ALARM:
        old = signal.signal(signal.SIGALRM, _alarm)
        signal.setitimer(signal.ITIMER_REAL, DEADLINE)
    t0 = time.perf_counter()
    stage = "load"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                model = ks.loads(text, file="fuzz.yaml") if path is None else ks.load(path)
                stage = "structure"
                a = model.analysis
                small = dataclasses.replace(
                    a, positions=min(a.positions, ANALYSED_POSITIONS), at=a.at[:2]
                )
                model = dataclasses.replace(model, analysis=small)
                system = ks.build_system(model)
                stage = "analyze"
                result = ks.analyze(system)
                assert len(result) >= 1
                if model.drive is not None or model.flywheel is not None:
                    stage = "summary"  # the drive's sizing and the flywheel's design
                    result.summary()
                stage = "accepted"
            except ks.NonFiniteResultError:
                raise  # the file's limits promise that a file that loads does not overflow
            except ks.KinetostaticsError as exc:
                assert str(exc).strip(), f"empty message from {type(exc).__name__}"
                stage = "refused at " + stage
    except _Hang:
        if not CONTINUE:
            raise AssertionError(
                f"no answer after {DEADLINE:g} s (stage {stage}): a hang"
            ) from None
        stage = f"CRASH: hang in {stage}"
    except Exception as exc:
        if not CONTINUE:
            raise
        frames = [
            f
            for f in traceback.extract_tb(exc.__traceback__)
            if "kinetostatics" in f.filename and "tests" not in Path(f.filename).parts
        ]
        where = f" at {Path(frames[-1].filename).name}:{frames[-1].lineno}" if frames else ""
        stage = f"CRASH: {type(exc).__name__}{where} in {stage}"
    finally:
        if ALARM:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)
    counter[stage] += 1
    elapsed = time.perf_counter() - t0
    counter["slowest"] = max(counter["slowest"], elapsed)
    crashed = stage.startswith("CRASH")
    if KEEP and counter["cases"] % 100 == 0:  # the counts so far, if the run is stopped
        KEEP.mkdir(parents=True, exist_ok=True)
        (KEEP / f"counts-{os.getpid()}-{id(counter)}.json").write_text(json.dumps(counter))
    if KEEP and (elapsed > 1.0 or crashed):  # for the record of a long run
        KEEP.mkdir(parents=True, exist_ok=True)
        name = (
            f"crash-{counter['cases']}.yaml"
            if crashed
            else f"slow-{elapsed:06.2f}s-{counter['cases']}.yaml"
        )
        (KEEP / name).write_bytes(
            (f"# {stage}\n" if crashed else "").encode()
            + (path.read_bytes() if path else text.encode("utf-8", "surrogatepass"))
        )
    return stage


def report(counter: Counter, what: str, wall: float) -> None:
    """Warn (visibly) how many cases ran and with which outcomes; fail on collected crashes."""
    outcomes = ", ".join(
        f"{k} {v}" for k, v in sorted(counter.items()) if k not in ("cases", "slowest")
    )
    message = (
        f"{what}: {counter['cases']} cases run in {wall:.1f} s ({outcomes}); "
        f"slowest example {counter['slowest']:.2f} s"
    )
    print(message)
    warnings.warn(FuzzReport(message), stacklevel=2)
    crashes = [k for k in counter if k.startswith("CRASH")]
    assert not crashes, f"{what}: " + "; ".join(f"{k} ({counter[k]} cases)" for k in crashes)


# -- values ---------------------------------------------------------------------------
ODD_NUMBERS = [
    float("nan"),
    float("inf"),
    -float("inf"),
    1e308,
    -1e308,
    1.7976931348623157e308,
    5e-324,
    -5e-324,
    0,
    0.0,
    -0.0,
    -1,
    -1e-9,
    1e-300,
    10**400,
    -(10**400),
    2**63,
    True,
    False,
    1e15,
    360,
    -360,
    1e6,
]
ODD_STRINGS = [
    "",
    " ",
    "nan",
    ".nan",
    ".inf",
    "-.inf",
    "1e999",
    "0x10",
    "1_000",
    "~",
    "null",
    "yes",
    "no",
    "on",
    "1/0",
    "asin(2)",
    "sqrt(-1)",
    "log(0)",
    "9**9**9",
    "10**308*10",
    "__import__('os').system('echo hi')",
    "().__class__",
    "(lambda: 1)()",
    "[x for x in ()]",
    "a.b",
    "open('x')",
    "e" * 1200,
    "(" * 80 + "1" + ")" * 80,
    "-" * 200 + "1",
    "1" + "+1" * 400,
    "é",
    "名前",
    "\u202e",
    "\x00",
    "\ufeff",
    "𝔞",
    "a\u0301",
    "'quoted'",
    "- item",
    "{a: 1}",
    "rev\u043elute",
    "revolute",
    "prismatic",
    "ground",
    "x",
    "+x",
    "mm",
    "deg",
    "rpm",
    "kg",
    "N",
    "N*m",
    "kg*m^2",
    "furlong",
    "m/s",
    "rad/s",
]

unicode_text = st.text(st.characters(codec=None), max_size=30)
names_like = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,12}", fullmatch=True)
numbers = st.one_of(
    st.sampled_from(ODD_NUMBERS),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e3),
)
scalars = st.one_of(
    numbers, st.sampled_from(ODD_STRINGS), unicode_text, names_like, st.none(), st.booleans()
)


def expressions(names: list[str]) -> st.SearchStrategy[str]:
    """Arithmetic from a grammar over the file's parameter names, with forbidden constructs."""
    leaf = st.one_of(
        st.integers(-1000, 10**20).map(str),
        st.floats(allow_nan=False, allow_infinity=False).map(repr),
        st.sampled_from(
            [
                "1e308",
                "1e-308",
                "0",
                "0.0",
                "pi",
                "e",
                "tau",
                "nan",
                "inf",
                "True",
                "None",
                "'s'",
                "x",
                "__builtins__",
                "1j",
            ]
        ),
        st.sampled_from(names or ["a"]).map(str),
    )
    good = [
        "sqrt",
        "sin",
        "cos",
        "tan",
        "asin",
        "acos",
        "atan",
        "atan2",
        "sind",
        "cosd",
        "tand",
        "asind",
        "acosd",
        "atand",
        "atan2d",
        "radians",
        "degrees",
        "exp",
        "log",
        "log10",
        "abs",
        "min",
        "max",
        "hypot",
        "floor",
        "ceil",
        "round",
    ]
    bad = ["__import__", "eval", "exec", "open", "getattr", "print", "pow", "sinn"]

    def extend(inner):
        return st.one_of(
            st.tuples(
                inner,
                st.sampled_from(
                    ["+", "-", "*", "/", "**", "%", "//", "<<", "&", " and ", "<", "@", "|"]
                ),
                inner,
            ).map(lambda t: f"{t[0]} {t[1]} {t[2]}"),
            inner.map(lambda x: f"({x})"),
            inner.map(lambda x: f"-{x}"),
            st.tuples(st.sampled_from(good + bad), st.lists(inner, max_size=3)).map(
                lambda t: f"{t[0]}({', '.join(t[1])})"
            ),
            st.tuples(inner, st.sampled_from([".__class__", "[0]", ".real", "()"])).map(
                lambda t: f"({t[0]}){t[1]}"
            ),
            inner.map(lambda x: f"lambda: {x}"),
            st.tuples(inner, inner).map(lambda t: f"{t[0]} if {t[1]} else 0"),
        )

    return st.recursive(leaf, extend, max_leaves=25)


# -- data-level mutation ----------------------------------------------------------------
def _paths(doc, prefix=()) -> list[tuple]:
    """Every path (tuple of keys and indices) in a YAML document, the root included."""
    out = [prefix]
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            out += _paths(v, prefix + (i,))
    return out


def _get(doc, path):
    for k in path:
        doc = doc[k]
    return doc


def _set(doc, path, value):
    if not path:
        return value
    _get(doc, path[:-1])[path[-1]] = value
    return doc


def _strings(doc) -> list[str]:
    """Every key and string value (the names a file refers to)."""
    out = []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out.append(str(k))
            out += _strings(v)
    elif isinstance(doc, list):
        for v in doc:
            out += _strings(v)
    elif isinstance(doc, str):
        out.append(doc)
    return out


def _rename_everywhere(doc, old: str, new):
    """Replace a name as a key and as a whole string value, all through the document."""
    if isinstance(doc, dict):
        return {(new if k == old else k): _rename_everywhere(v, old, new) for k, v in doc.items()}
    if isinstance(doc, list):
        return [_rename_everywhere(v, old, new) for v in doc]
    if isinstance(doc, str) and doc == old:
        return new
    return doc


def _nest(value, depth: int, kind: str):
    for _ in range(depth):
        value = [value] if kind == "list" else {"a": value}
    return value


MUTATIONS = (
    "delete",
    "type",
    "number",
    "string",
    "unicode_key",
    "nest",
    "reference",
    "rename_link",
    "expression",
    "junk_key",
    "copy_subtree",
    "analysis",
    "scale",
)
SCALES = [
    10.0**k
    for k in (
        -320,
        -300,
        -200,
        -160,
        -40,
        -31,
        -30,
        -29,
        -12,
        -9,
        -3,
        3,
        9,
        12,
        18,
        19,
        30,
        31,
        60,
        200,
        300,
        308,
    )
]
ANALYSIS_KEYS = ("start", "sweep", "positions", "at", "events")


@st.composite
def mutated_documents(draw):
    name = draw(st.sampled_from(sorted(DATA)))
    doc = copy.deepcopy(DATA[name])
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 3, 4]))):  # mostly one: it may still load
        kind = draw(st.sampled_from(MUTATIONS + ("number", "reference", "analysis", "scale")))
        paths = _paths(doc)
        leaves = [p for p in paths if not isinstance(_get(doc, p), (dict, list))]
        if leaves and draw(st.booleans()):  # values are where most of the checks are
            path = draw(st.sampled_from(leaves))
        else:
            path = draw(st.sampled_from(paths[1:] if len(paths) > 1 else paths))
        names = _strings(doc)
        params = (
            list(doc.get("parameters") or {})
            if isinstance(doc, dict) and isinstance(doc.get("parameters"), dict)
            else []
        )
        try:
            target = _get(doc, path)
        except (KeyError, IndexError, TypeError):
            continue
        if kind == "delete" and path:
            parent = _get(doc, path[:-1])
            del parent[path[-1]]
        elif kind == "type":
            value = draw(
                st.sampled_from(
                    [
                        draw(numbers),
                        str(target),
                        [target],
                        {"x": target},
                        None,
                        True,
                        [],
                        {},
                        [1, 2, 3],
                        {"type": "revolute"},
                    ]
                )
            )
            doc = _set(doc, path, value)
        elif kind == "number":
            doc = _set(doc, path, draw(numbers))
        elif kind == "string":
            doc = _set(doc, path, draw(st.one_of(st.sampled_from(ODD_STRINGS), unicode_text)))
        elif kind == "unicode_key":
            parent_path = path[:-1]
            parent = _get(doc, parent_path)
            if isinstance(parent, dict):
                key = draw(
                    st.one_of(
                        unicode_text,
                        st.sampled_from(
                            ["time", "angle", "friction", "1abc", "a b", "ground", "", "<<"]
                        ),
                        st.integers(),
                        st.none(),
                        st.booleans(),
                        st.floats(),
                    )
                )
                value = parent.pop(path[-1])
                parent[key] = value
        elif kind == "nest":
            depth = draw(st.sampled_from([1, 2, 5, 30, 99, 100, 101, 150, 400]))
            doc = _set(doc, path, _nest(target, depth, draw(st.sampled_from(["list", "map"]))))
        elif kind == "reference":
            choices = names + [n[:-1] for n in names if n] + [n + "x" for n in names]
            doc = _set(doc, path, draw(st.one_of(st.sampled_from(choices or ["x"]), unicode_text)))
        elif kind == "rename_link":
            links = doc.get("links") if isinstance(doc, dict) else None
            if isinstance(links, dict) and links:
                old = draw(st.sampled_from(sorted(map(str, links))))
                new = draw(st.one_of(names_like, unicode_text, st.sampled_from(names or ["x"])))
                doc = _rename_everywhere(doc, old, new)
        elif kind == "expression":
            doc = _set(doc, path, draw(expressions(params)))
        elif kind == "junk_key":
            parent = _get(doc, path[:-1]) if path else doc
            if isinstance(parent, dict):
                parent[draw(st.one_of(names_like, unicode_text))] = draw(scalars)
        elif kind == "analysis" and isinstance(doc, dict):
            if not isinstance(doc.get("analysis"), dict):
                doc["analysis"] = {}
            key = draw(st.sampled_from(ANALYSIS_KEYS))
            doc["analysis"][key] = draw(
                st.one_of(
                    numbers,
                    numbers,
                    numbers,
                    expressions(params),
                    st.lists(numbers, max_size=4),
                    scalars,
                )
            )
        elif kind == "scale":
            # a number of the file times a power of ten (or its negative): each key near and
            # beyond its limits, the laws, flywheel and efforts included
            numeric = [
                p
                for p in leaves
                if isinstance(_get(doc, p), (int, float)) and not isinstance(_get(doc, p), bool)
            ]
            if numeric:
                p = draw(st.sampled_from(numeric))
                factor = draw(st.sampled_from(SCALES)) * draw(st.sampled_from([1, 1, -1]))
                try:
                    doc = _set(doc, p, float(_get(doc, p)) * factor)
                except OverflowError:
                    doc = _set(doc, p, math.copysign(1e308, factor))
        elif kind == "copy_subtree":
            source = draw(st.sampled_from(paths))
            doc = _set(doc, path, copy.deepcopy(_get(doc, source)))
    return name, doc, draw(st.booleans())


def _dump(doc, allow_unicode: bool) -> str | None:
    try:
        return yaml.safe_dump(doc, allow_unicode=allow_unicode, sort_keys=False, width=80)
    except (yaml.YAMLError, RecursionError, ValueError):
        return None  # not representable (e.g. a nested structure past the dumper's limits)


def test_fuzz_data_level():
    counter: Counter = Counter()

    @_seeded
    @_settings(DATA_EXAMPLES)
    @given(mutated_documents())
    def run(case):
        name, doc, allow_unicode = case
        text = _dump(doc, allow_unicode)
        if text is None:
            counter["not dumpable"] += 1
            return
        exercise(counter, text=text)

    t0 = time.perf_counter()
    try:
        run()
    finally:
        report(counter, "data-level fuzz", time.perf_counter() - t0)
    assert counter["cases"] >= min(DATA_EXAMPLES, 50)


# -- text-level mutation ---------------------------------------------------------------
PUNCTUATION = list(":-[]{},#&*!|>'\"%@`?\t\n\r ") + [
    "\x00",
    "\x85",
    "\u2028",
    "\ufeff",
    "\ud800",
    "é",
    "名",
    "𝔞",
    "\u202e",
    "<<: *a",
    "&a ",
    "*a",
    "!!python/object:os.system ",
    "---\n",
    "...\n",
    "? ",
]
chars = st.one_of(
    st.sampled_from(PUNCTUATION), st.characters(codec=None), st.sampled_from(string.printable)
)


@st.composite
def mutated_texts(draw):
    name = draw(st.sampled_from(sorted(SOURCES)))
    text = SOURCES[name]
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(
            st.sampled_from(
                ["insert", "delete", "replace", "dup_line", "swap_lines", "truncate", "indent"]
            )
        )
        n = len(text)
        i = draw(st.integers(0, max(n - 1, 0)))
        lines = text.splitlines(keepends=True)
        if kind == "insert":
            text = text[:i] + "".join(draw(st.lists(chars, min_size=1, max_size=8))) + text[i:]
        elif kind == "delete":
            text = text[:i] + text[i + draw(st.integers(1, 40)) :]
        elif kind == "replace":
            text = text[:i] + draw(chars) + text[i + 1 :]
        elif kind == "dup_line" and lines:
            k = draw(st.integers(0, len(lines) - 1))
            lines.insert(k, lines[k])
            text = "".join(lines)
        elif kind == "swap_lines" and len(lines) > 1:
            k = draw(st.integers(0, len(lines) - 2))
            lines[k], lines[k + 1] = lines[k + 1], lines[k]
            text = "".join(lines)
        elif kind == "truncate":
            text = text[:i]
        elif kind == "indent" and lines:
            k = draw(st.integers(0, len(lines) - 1))
            lines[k] = draw(st.sampled_from([" ", "  ", "\t", "    "])) + lines[k]
            text = "".join(lines)
    as_bytes = draw(st.integers(0, 3)) == 0
    edits = []
    if as_bytes:
        for _ in range(draw(st.integers(0, 3))):
            edits.append((draw(st.integers(0, 10**6)), draw(st.integers(0, 255))))
    return text, as_bytes, edits


def test_fuzz_text_level():
    counter: Counter = Counter()
    tmp = Path(tempfile.mkdtemp(prefix="kinetostatics-fuzz-"))

    @_seeded
    @_settings(TEXT_EXAMPLES)
    @given(mutated_texts())
    def run(case):
        text, as_bytes, edits = case
        if not as_bytes:
            exercise(counter, text=text)
            return
        data = bytearray(text.encode("utf-8", "surrogatepass"))
        for pos, byte in edits:
            if data:
                data[pos % len(data)] = byte
        path = tmp / "fuzz.yaml"
        path.write_bytes(bytes(data))
        exercise(counter, path=path)

    t0 = time.perf_counter()
    try:
        run()
    finally:
        for p in tmp.iterdir():
            p.unlink()
        tmp.rmdir()
        report(counter, "text-level fuzz", time.perf_counter() - t0)
    assert counter["cases"] >= min(TEXT_EXAMPLES, 50)


# -- things that must never run, and must be refused quickly ------------------------------
BROKEN = ROOT / "tests" / "broken"


@pytest.mark.parametrize(
    "name, message",
    [
        ("forbidden_import.yaml", "attribute access is not allowed"),
        ("forbidden_attribute.yaml", "attribute access is not allowed"),
        ("forbidden_huge_power.yaml", "exponent too large"),
        ("alias_bomb.yaml", "alias bomb"),
    ],
)
@pytest.mark.timeout(30)  # bounded time: a hang fails it, a slow machine does not
def test_dangerous_files_refused_quickly_and_run_nothing(name, message, monkeypatch):
    """The whole pipeline, not just the evaluator: refused by ``load`` within a bounded
    time, and no process is started on the way."""
    ran = []
    monkeypatch.setattr(os, "system", lambda *a: ran.append(a) or 0)
    with pytest.raises(ks.ModelError, match=message):
        ks.load(BROKEN / name)
    assert not ran


@pytest.mark.parametrize(
    "expression",
    [
        "__import__('os').system('touch PWNED')",
        "__import__('os')",
        "().__class__",
        "().__class__.__base__.__subclasses__()",
        "9**9**9",
        "(9**9)**(9**9)",
        "10**10**10**10",
        "exp(exp(exp(10)))",
    ],
)
@pytest.mark.parametrize("where", ["parameter", "value"])
@pytest.mark.timeout(30)
def test_dangerous_expression_in_a_file_refused_quickly(expression, where, tmp_path, monkeypatch):
    """Each as a parameter and directly as a typed value (a link's mass)."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(os, "system", lambda *a: pytest.fail("os.system was called"))
    doc = copy.deepcopy(DATA["slider_crank.yaml"])
    if where == "parameter":
        doc["parameters"]["r1"] = expression
    else:
        doc["links"]["crank"]["mass"] = expression
    with pytest.raises(ks.ModelError) as info:
        ks.loads(yaml.safe_dump(doc, sort_keys=False), file="m.yaml")
    assert len(info.value.problems) == 1
    assert str(info.value).startswith("m.yaml:")
    assert not (tmp_path / "PWNED").exists()


@pytest.mark.parametrize("depth", [2, 9, 20])
@pytest.mark.timeout(60)
def test_billion_laughs_variants_refused_quickly(depth):
    """Alias bombs of several shapes (lists, mappings, merge keys) are refused in bounded time."""
    lines = ["a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for k in range(1, depth + 1):
        prev = f"*a{k - 1}"
        lines.append(f"a{k}: &a{k} [{', '.join([prev] * 10)}]")
    text = "\n".join(lines) + f"\nlinks: {{ground: {{points: {{O: [0, 0]}}}}}}\njoints: *a{depth}\n"
    merge = (
        "m0: &m0 {x: 1}\n"
        + "".join(
            f"m{k}: &m{k} {{<<: [{', '.join([f'*m{k - 1}'] * 10)}], y{k}: 1}}\n"
            for k in range(1, depth + 1)
        )
        + "links: {}\njoints: {}\n"
    )
    for source in (text, merge):
        try:
            ks.loads(source, file="bomb.yaml")
        except ks.KinetostaticsError:
            pass
    with pytest.raises(ks.ModelError, match="alias bomb" if depth >= 5 else "."):
        ks.loads(text, file="bomb.yaml")


def test_odd_numbers_are_finite_or_refused():
    """nan, inf and overflow as YAML numbers never reach the model."""
    for raw in (".nan", ".inf", "-.inf", "1e309", "-1e309", "1" * 400):
        doc = SOURCES["slider_crank.yaml"].replace("mass: 2\n", f"mass: {raw}\n", 1)
        with pytest.raises(ks.ModelError) as info:
            ks.loads(doc, file="m.yaml")
        assert "links.crank.mass" in str(info.value)
    assert math.isfinite(ks.loads(SOURCES["slider_crank.yaml"]).link("crank").mass)


# -- the command line and the documented limits --------------------------------------------
def test_cli_internal_error_keeps_its_traceback(monkeypatch, tmp_path):
    """A bug (any exception that is not a KinetostaticsError) is not turned into exit 2."""
    from kinetostatics import analysis
    from kinetostatics.cli import main

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(analysis, "analyze", broken)
    with pytest.raises(ZeroDivisionError, match="a bug"):
        main(["run", str(ROOT / "mechanisms" / "slider_crank.yaml"), "--out", str(tmp_path)])


def test_cli_user_error_in_the_solver_is_one_line(monkeypatch, tmp_path, capsys):
    """Assembly failure at run time: one line naming the group, the driver coordinate and
    the reason; exit status 2 (also checked for every broken file in test_broken_files)."""
    from kinetostatics.cli import main

    monkeypatch.chdir(BROKEN)
    assert main(["run", "rod_too_short.yaml", "--out", str(tmp_path)]) == 2
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith(
        "kinetostatics: RRP dyad {rod, slider} cannot assemble at "
        "motor = 0°: the links cannot reach"
    )


def test_errors_doc_states_the_limits_of_the_code():
    from kinetostatics.base import expressions, limits

    doc = (ROOT / "docs" / "errors.md").read_text(encoding="utf-8")
    for value, text in [
        (limits.MAX_FILE_BYTES, f"{limits.MAX_FILE_BYTES:,} bytes"),
        (limits.MAX_NODES, f"| {limits.MAX_NODES:,} |"),
        (limits.MAX_DEPTH, f"{limits.MAX_DEPTH} levels"),
        (limits.MAX_LINKS, f"| {limits.MAX_LINKS} |"),
        (limits.MAX_POSITIONS, f"1 to {limits.MAX_POSITIONS:,}"),
        (limits.MAX_TURNS, f"at most {limits.MAX_TURNS} turns"),
        (limits.MAX_TRAVEL, f"at most {limits.MAX_TRAVEL} × the largest link"),
        (
            limits.SPEED_RANGE,
            f"{limits.SPEED_RANGE[0]:g} ≤ \\|speed\\| ≤ {limits.SPEED_RANGE[1]:g}",
        ),
        (expressions.MAX_EXPRESSION_LENGTH, f"{expressions.MAX_EXPRESSION_LENGTH} characters"),
        (expressions.MAX_DEPTH, f"{expressions.MAX_DEPTH} levels"),
        (expressions.MAX_EXPONENT, f"≤ {expressions.MAX_EXPONENT:g}"),
    ]:
        assert text in doc, f"docs/errors.md does not state {value!r} as '{text}'"
    for name in (
        "KinetostaticsError",
        "ModelError",
        "StructureError",
        "AssemblyError",
        "SingularConfigurationError",
        "SelfLockingError",
        "NonFiniteResultError",
    ):
        assert f"`{name}`" in doc
