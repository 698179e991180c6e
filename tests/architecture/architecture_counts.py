"""The architecture's counts, measured on the source tree (docs/architecture.md, "Counts").

    python tests/architecture/architecture_counts.py [--json]

Prints, for ``src/kinetostatics``:

- ``cycles``: the import cycles among the package's modules (strongly connected components
  of the module import graph, every import counted: module level, in functions, under
  ``TYPE_CHECKING``), and the modules they span;
- ``long_functions``: functions (and methods) longer than 60 lines, decorators and the
  docstring excluded;
- ``wide_functions``: functions taking 8 or more parameters (``self`` and ``cls`` not counted);
- ``lazy_imports``: imports of the package's own modules inside a function, and the modules
  that hold them (``cli/`` apart, where they keep the command's start light);
- ``hidden_caches``: values kept on a frozen object or in a closure after construction
  and documented nowhere: a ``cached_property``, a write into ``__dict__`` or into a dict
  named ``*memo*``/``*cache*``, ``object.__setattr__`` outside
  ``__post_init__``/``__setstate__``, a ``nonlocal``.  Not counted: ``system.memo`` (and a
  local name bound to a part of it), the one documented per-system memo; a module-level
  ``functools.cache`` on a pure function of its arguments (it hides nothing); the sites of
  :data:`DOCUMENTED`, each named in docs/architecture.md, "What is computed once", with its
  reason; and the sites of :data:`BY_DESIGN`, caches of *mutable working objects* (an
  optimisation's evaluated designs, an integrator's states, the YAML tree being read),
  which are their objects' job, not a frozen record's hidden state.  ``--json`` lists both
  apart (``documented_cache_sites``, ``by_design_cache_sites``);
- ``type_checks_outside_home``: code that tells types apart outside the module that owns
  them: ``isinstance`` against a motion-law class outside ``model/``; ``getattr``/``hasattr``
  of a law's member on a name that says law or motion outside ``model/``; a load or
  condition kind compared by its name (``x.kind ==``, ``in``, ``not in``) in ``kinetics/``
  (outside ``kinetics/kinds.py``, its home), ``dynamics/``, ``analysis/`` and the pictures
  (``outputs/plotting/``), on the names the code gives a load or a condition (an Assur
  group's or a polygon's ``kind`` is not a load's). The joints are checked by
  ``test_no_joint_sniffing_outside_joints``; the report's and the loader's wording of a
  kind is text, not dispatch, and is not counted;
- ``public_functions``: functions and classes that ``kinetostatics.__all__`` names, with
  their public methods, and how many have a typed signature and a numpydoc Parameters (or,
  with no parameter, Returns) section.

The numbers are read from the code, never from a run, so they can be compared across
commits: ``git archive COMMIT src | tar -x -C DIR`` and ``--root DIR`` measures that commit's
tree with this file's rules.  ``--write`` rewrites the "now" column of the table in
docs/architecture.md ("Counts"), which ``tests/architecture/test_architecture.py`` checks.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import inspect
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "src" / "kinetostatics"
LONG = 60
WIDE = 8


def _modules():
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(PKG)
        parts = list(rel.with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        yield ".".join(["kinetostatics", *parts]), path, ast.parse(path.read_text("utf-8"))


def _target(module: str, is_package: bool, node: ast.ImportFrom | ast.Import) -> list[str]:
    if isinstance(node, ast.Import):
        return [a.name for a in node.names if a.name.startswith("kinetostatics")]
    if node.level == 0:
        base = node.module or ""
        if not base.startswith("kinetostatics"):
            return []
    else:
        pkg = module.split(".") if is_package else module.split(".")[:-1]
        pkg = pkg[: len(pkg) - (node.level - 1)]
        base = ".".join(pkg + ([node.module] if node.module else []))
    return [base] + [f"{base}.{a.name}" for a in node.names]


def _graph():
    mods = {m: (p, t) for m, p, t in _modules()}
    edges: dict[str, set[str]] = {m: set() for m in mods}
    lazy: list[tuple[str, int]] = []
    for m, (path, tree) in mods.items():
        is_pkg = path.name == "__init__.py"
        for fn in ast.walk(tree):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for node in ast.walk(fn):
                    if isinstance(node, (ast.Import, ast.ImportFrom)) and _target(m, is_pkg, node):
                        lazy.append((m, node.lineno))
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for t in _target(m, is_pkg, node):
                    if t in mods and t != m:
                        edges[m].add(t)
    return edges, sorted(set(lazy))


def lazy_imports() -> dict[str, list[int]]:
    """The imports of the package's own modules inside a function, outside ``cli/``: the
    module's path under ``src/kinetostatics`` (``batch/variants.py``) → their lines."""
    paths = {m: p.relative_to(PKG).as_posix() for m, p, _ in _modules()}
    out: dict[str, list[int]] = {}
    for m, line in _graph()[1]:
        if not m.startswith("kinetostatics.cli"):
            out.setdefault(paths[m], []).append(line)
    return out


def _sccs(edges: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components with more than one module."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    sys.setrecursionlimit(10000)

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in edges:
        if v not in index:
            visit(v)
    return out


def _package_parents(edges: dict[str, set[str]]) -> dict[str, set[str]]:
    """Drop the edges a module has to the packages above it (importing ``a.b.c`` runs
    ``a/__init__`` and ``a/b/__init__``: not a dependency the code chose)."""
    return {m: {t for t in ts if not m.startswith(t + ".")} for m, ts in edges.items()}


def _functions():
    for m, _path, tree in _modules():
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield m, node


def function_length(fn: ast.FunctionDef) -> int:
    """Lines from the ``def`` to the end, the docstring not counted (a function's
    documentation is not its size)."""
    lines = fn.end_lineno - fn.lineno + 1
    first = fn.body[0]
    if (
        isinstance(first, ast.Expr)
        and isinstance(first.value, ast.Constant)
        and isinstance(first.value.value, str)
    ):
        lines -= first.end_lineno - first.lineno + 1
    return lines


def _params(fn: ast.FunctionDef) -> list[str]:
    a = fn.args
    names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    names += [x.arg for x in (a.vararg, a.kwarg) if x is not None]
    return [n for n in names if n not in ("self", "cls")]


def _cache_name(node: ast.AST, aliases: frozenset[str] = frozenset()) -> str | None:
    """The memo a subscript write or ``setdefault`` goes to, if its name says memo or cache
    (``system.memo``, the one documented per-system memo, and the local ``aliases`` bound to
    a part of it are not hidden)."""
    name = ast.unparse(node)
    if name == "system.memo" or name.endswith(".system.memo") or name in aliases:
        return None
    last = name.split(".")[-1].lower()
    return name if ("memo" in last or "cache" in last or last == "__dict__") else None


def _memo_aliases(fn: ast.AST) -> frozenset[str]:
    """Local names a function binds to a part of ``system.memo`` (``memo =
    system.memo.setdefault(...)``): writes through them go to the documented memo."""
    out = set()
    for node in ast.walk(fn):
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            value = ast.unparse(node.value)
            if isinstance(node.targets[0], ast.Name) and (
                value.startswith("system.memo") or ".system.memo" in value
            ):
                out.add(node.targets[0].id)
    return frozenset(out)


# memos keyed on the whole input of a pure function: (module, function) — see the docstring
KEYED_ON_INPUT = {("kinetostatics.joints.cam", "kept")}

# caches on frozen objects that docs/architecture.md ("What is computed once") names, with
# why each stays: (module, the site's text) -> reason
DOCUMENTED = {
    ("kinetostatics.analysis.results", "cached_property Result.checks"): (
        "the self-checks, the one lazy value of a Result: ~10 % of a first analysis"
    ),
    ("kinetostatics.structure.system", "object.__setattr__"): (
        "system_of: the compiled System kept on its model, keyed on the model's fingerprint"
    ),
    ("kinetostatics.structure.evaluation", "self.__dict__[...] ="): (
        "a constraint set's compiled kernels (numba backend only) and last read-only poses"
    ),
}
# caches that are the job of mutable working objects (not frozen records): (module) -> why
BY_DESIGN = {
    "kinetostatics.base.spec": "the YAML nodes being read keep their locations and checks",
    "kinetostatics.batch.designs": "an optimisation's designs evaluated so far (_Problem.cache)",
    "kinetostatics.dynamics.engine": "an integrator's last solved states (Dynamics._cache)",
    "kinetostatics.outputs.report.pdf": "the PDF being written: the widths it measured",
}


def _cache_sites() -> list[tuple[str, int, str]]:
    found = []
    keyed: set[tuple[str, int]] = set()
    for m, _path, tree in _modules():
        for fn in ast.walk(tree):
            if isinstance(fn, ast.FunctionDef) and (m, fn.name) in KEYED_ON_INPUT:
                keyed |= {(m, n) for n in range(fn.lineno, fn.end_lineno + 1)}
        for fn in ast.walk(tree):
            if isinstance(fn, ast.ClassDef):
                for item in fn.body:
                    decs = [ast.unparse(d) for d in getattr(item, "decorator_list", [])]
                    if any(d.split(".")[-1] == "cached_property" for d in decs):
                        found.append((m, item.lineno, f"cached_property {fn.name}.{item.name}"))
            if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            aliases = _memo_aliases(fn)
            for node in ast.walk(fn):
                if isinstance(node, ast.Nonlocal):
                    found.append((m, node.lineno, "nonlocal memo"))
                elif isinstance(node, ast.Assign):
                    for t in node.targets:
                        if isinstance(t, ast.Subscript) and _cache_name(t.value, aliases):
                            found.append((m, node.lineno, f"{_cache_name(t.value)}[...] ="))
                elif isinstance(node, ast.Call):
                    func = ast.unparse(node.func)
                    if func == "object.__setattr__" and fn.name not in (
                        "__post_init__",
                        "__setstate__",
                    ):
                        found.append((m, node.lineno, "object.__setattr__"))
                    elif (
                        isinstance(node.func, ast.Attribute)
                        and node.func.attr == "setdefault"
                        and _cache_name(node.func.value, aliases)
                    ):
                        found.append((m, node.lineno, f"{func}(...)"))
    return sorted({f for f in found if f[:2] not in keyed})


def hidden_caches() -> dict[str, list[tuple[str, int, str]]]:
    """The cache sites split: ``hidden`` (counted), ``documented``, ``by_design``."""
    out: dict[str, list] = {"hidden": [], "documented": [], "by_design": []}
    for m, n, what in _cache_sites():
        if (m, what) in DOCUMENTED:
            out["documented"].append((m, n, f"{what}: {DOCUMENTED[m, what]}"))
        elif m in BY_DESIGN:
            out["by_design"].append((m, n, f"{what}: {BY_DESIGN[m]}"))
        else:
            out["hidden"].append((m, n, what))
    return out


LAW_CLASSES = {"Law", "MotionLaw", "HarmonicLaw", "PolynomialLaw", "TableLaw"}
LAW_MEMBERS = {
    "kind", "own_run", "value", "start", "speed", "acceleration", "duration", "cyclic",
    "breaks", "to_spec", "coefficients", "periodic", "values", "amplitude", "period", "omega",
}  # fmt: skip
LOAD_NAMES = {"load", "ld", "c", "cond", "condition"}  # how the code names a load or condition
KIND_DISPATCH = ("kinetics/", "dynamics/", "analysis/", "outputs/plotting/")


def type_checks() -> list[str]:
    """The sites of ``type_checks_outside_home`` (module docstring)."""
    found = []
    for _m, path, tree in _modules():
        rel = path.relative_to(PKG).as_posix()
        for n in ast.walk(tree):
            if not isinstance(n, ast.Call) or not isinstance(n.func, ast.Name):
                continue
            if rel.startswith("model/"):
                continue
            args = n.args
            if n.func.id == "isinstance" and len(args) == 2:
                names = {x.id for x in ast.walk(args[1]) if isinstance(x, ast.Name)}
                if names & LAW_CLASSES:
                    found.append(f"{rel}:{n.lineno} isinstance of a law")
            elif n.func.id in ("getattr", "hasattr") and len(args) >= 2:
                member = args[1].value if isinstance(args[1], ast.Constant) else None
                owner = ast.unparse(args[0]).lower()
                if member in LAW_MEMBERS and ("law" in owner or "motion" in owner):
                    found.append(f"{rel}:{n.lineno} {n.func.id}(…, {member!r}) of a law")
        if rel.startswith(KIND_DISPATCH) and rel != "kinetics/kinds.py":
            for n in ast.walk(tree):
                if isinstance(n, ast.Compare) and any(
                    isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in n.ops
                ):
                    left = n.left
                    if (
                        isinstance(left, ast.Attribute)
                        and left.attr == "kind"
                        and isinstance(n.comparators[0], (ast.Constant, ast.Tuple, ast.Set))
                        and ast.unparse(left.value).split(".")[-1] in LOAD_NAMES
                    ):
                        found.append(f"{rel}:{n.lineno} {ast.unparse(n)}")
    return found


def _has_numpydoc(obj) -> bool:
    doc = inspect.getdoc(obj) or ""
    return any(f"\n{s}\n" + "-" * len(s) in f"\n{doc}" for s in ("Parameters", "Returns"))


def _typed(obj) -> bool:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return False
    params = [p for n, p in sig.parameters.items() if n not in ("self", "cls")]
    return all(p.annotation is not p.empty for p in params) and (
        sig.return_annotation is not sig.empty or inspect.isclass(obj)
    )


def _public() -> list[tuple[str, object]]:
    sys.path.insert(0, str(ROOT / "src"))
    ks = importlib.import_module("kinetostatics")
    out = []
    for name in ks.__all__:
        obj = getattr(ks, name)
        if not callable(obj):
            continue
        out.append((name, obj))
        if inspect.isclass(obj) and not issubclass(obj, BaseException | Warning):
            for attr, member in vars(obj).items():
                if attr.startswith("_") or not callable(member):
                    continue
                out.append((f"{name}.{attr}", member))
    return out


def counts() -> dict:
    edges, _ = _graph()
    lazy = lazy_imports()
    cycles = _sccs(_package_parents(edges))
    funcs = list(_functions())
    long = [(m, f.name, function_length(f)) for m, f in funcs]
    long = [x for x in long if x[2] > LONG]
    wide = [(m, f.name, len(_params(f))) for m, f in funcs if len(_params(f)) >= WIDE]
    public = _public()
    caches = hidden_caches()
    return {
        "cycles": len(cycles),
        "modules_in_cycles": sum(map(len, cycles)),
        "cycle_members": cycles,
        "long_functions": len(long),
        "wide_functions": len(wide),
        "lazy_imports_outside_cli": sum(map(len, lazy.values())),
        "modules_with_lazy_imports_outside_cli": len(lazy),
        "hidden_caches": len(caches["hidden"]),
        "modules_with_hidden_caches": len({m for m, _, _ in caches["hidden"]}),
        "hidden_cache_sites": [f"{m}:{n} {k}" for m, n, k in caches["hidden"]],
        "documented_caches": len(caches["documented"]),
        "documented_cache_sites": [f"{m}:{n} {k}" for m, n, k in caches["documented"]],
        "by_design_caches": len(caches["by_design"]),
        "by_design_cache_sites": [f"{m}:{n} {k}" for m, n, k in caches["by_design"]],
        "type_checks_outside_home": len(type_checks()),
        "type_check_sites": type_checks(),
        "public_callables": len(public),
        "public_typed": sum(_typed(o) for _, o in public),
        "public_numpydoc": sum(_has_numpydoc(o) for _, o in public),
        "long": [f"{m}.{n} ({k})" for m, n, k in sorted(long, key=lambda x: -x[2])],
        "wide": [f"{m}.{n} ({k})" for m, n, k in sorted(wide, key=lambda x: -x[2])],
    }


SHOWN = (  # the counts docs/architecture.md shows ("Counts"), in its order
    ("cycles", "import cycles among the package's modules"),
    ("modules_in_cycles", "modules in those cycles"),
    ("long_functions", "functions over 60 lines (docstring not counted)"),
    ("wide_functions", "functions with 8 or more parameters"),
    ("lazy_imports_outside_cli", "lazy imports of the package's modules outside cli/"),
    ("hidden_caches", "hidden caches"),
    ("type_checks_outside_home", "type checks outside their home"),
    ("public_callables", "public callables (`__all__` and their methods)"),
    ("public_typed", "… with a typed signature"),
    ("public_numpydoc", "… with numpydoc sections"),
)
BEGIN, END = "<!-- counts:begin -->", "<!-- counts:end -->"
DOC = ROOT / "docs" / "architecture.md"


def shown(text: str) -> dict[str, str]:
    """{count: value} of the table between the markers of ``text``'s "now" column."""
    block = text.split(BEGIN, 1)[1].split(END, 1)[0]
    labels = {label: key for key, label in SHOWN}
    out = {}
    for line in block.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 3 and cells[0] in labels:
            out[labels[cells[0]]] = cells[2]
    return out


def _write(c: dict) -> None:
    """Rewrite the "now" column of the table in docs/architecture.md (the "before" column
    is kept: it was measured once, on the commit it names)."""
    text = DOC.read_text(encoding="utf-8")
    head, rest = text.split(BEGIN, 1)
    block, tail = rest.split(END, 1)
    before = {}
    for line in block.splitlines():
        cells = [x.strip() for x in line.strip().strip("|").split("|")]
        if len(cells) == 3:
            before[cells[0]] = cells[1]
    title = [x.strip() for x in block.strip().splitlines()[0].strip().strip("|").split("|")]
    rows = [f"| {title[0]} | {title[1]} | {title[2]} |", "|---|---:|---:|"]
    rows += [f"| {label} | {before.get(label, '')} | {c[key]} |" for key, label in SHOWN]
    DOC.write_text(head + BEGIN + "\n" + "\n".join(rows) + "\n" + END + tail, encoding="utf-8")


def main(argv=None) -> int:
    global ROOT, PKG
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="every list, as JSON")
    ap.add_argument("--root", type=Path, help="measure the tree there (an export of a commit)")
    ap.add_argument("--write", action="store_true", help="docs/architecture.md's table")
    a = ap.parse_args(argv)
    if a.root is not None:
        ROOT, PKG = a.root.resolve(), a.root.resolve() / "src" / "kinetostatics"
    c = counts()
    if a.write:
        _write(c)
    if a.json:
        print(json.dumps(c, indent=1))
        return 0
    for k, v in c.items():
        if not isinstance(v, list):
            print(f"{k:40s} {v}")
    for comp in c["cycle_members"]:
        print("cycle:", " ".join(x.removeprefix("kinetostatics.") for x in comp))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
