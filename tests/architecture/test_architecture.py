"""The architecture holds (docs/architecture.md): imports point down the layers with no
cycle (import-linter, pyproject.toml), ruff is clean, joint knowledge stays in joints/,
modules stay small, the tree in docs/architecture.md is the tree on disk, and its table of
lazy imports is the code's."""

from __future__ import annotations

import ast
import dataclasses
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from kinetostatics import joints
from tests.architecture.architecture_counts import (
    BY_DESIGN,
    DOC,
    DOCUMENTED,
    SHOWN,
    counts,
    function_length,
    hidden_caches,
    lazy_imports,
    shown,
    type_checks,
)

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "src" / "kinetostatics"
# the modules that may name pair types: each is a method defined for specific pairs
PAIR_SPECIFIC = {
    "kinematics/dyads.py": "closed-form dyads are R/P formulas",
    "outputs/plotting/polygons.py": "graphical velocity polygons are drawn for R and P pairs",
    "dynamics/clearance.py": "the clearance macro builds revolutes and a prismatic",
}
MAX_LINES = 600


def _tool(name: str) -> str:
    path = shutil.which(name) or str(Path(sys.executable).with_name(name))
    if not Path(path).exists():
        pytest.fail(f"{name} is not installed: python -m pip install -e '.[test]'")
    return path


def _run(*argv: str) -> None:
    p = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-4000:] + p.stderr[-2000:]


def test_import_contracts():
    """The layers, no use of the old paths inside the package, no cycles."""
    _run(_tool("lint-imports"), "--no-cache")


def test_ruff_lint():
    _run(_tool("ruff"), "check", ".")


def test_ruff_format():
    _run(_tool("ruff"), "format", "--check", ".")


def _modules():
    for path in sorted(PKG.rglob("*.py")):
        yield path.relative_to(PKG).as_posix(), path.read_text(encoding="utf-8")


def _joint_attributes() -> set[str]:
    """Attribute names that some joint types have and others lack (fields and members)."""
    names = [
        {f.name for f in dataclasses.fields(cls)} | {n for n in dir(cls) if not n.startswith("__")}
        for cls in joints.JOINT_TYPES.values()
    ]
    return set.union(*names) - set.intersection(*names)


def test_no_joint_sniffing_outside_joints():
    """Outside joints/ no code asks a joint for its class or probes its type's attributes."""
    classes = {cls.__name__ for cls in joints.JOINT_TYPES.values()}
    probes = _joint_attributes()
    bad = []
    for rel, text in _modules():
        if rel.startswith("joints/") or rel in PAIR_SPECIFIC:
            continue
        for node in ast.walk(ast.parse(text)):
            if not isinstance(node, ast.Call) or not isinstance(node.func, ast.Name):
                continue
            if node.func.id == "isinstance" and len(node.args) == 2:
                names = {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}
                if names & classes:
                    bad.append(f"{rel}:{node.lineno}: isinstance on a joint class")
            if node.func.id in ("hasattr", "getattr") and len(node.args) >= 2:
                attr = node.args[1]
                if isinstance(attr, ast.Constant) and attr.value in probes:
                    bad.append(f"{rel}:{node.lineno}: {node.func.id}(…, {attr.value!r})")
    assert not bad, "\n".join(bad)


def test_no_law_sniffing_outside_model():
    """Outside model/ no code asks a motion law for its class or probes its members: the
    readers ask every law through :class:`kinetostatics.model.Law`."""
    from kinetostatics import model
    from kinetostatics.model import motion

    types = (model.Law, model.MotionLaw, *motion.LAWS.values())
    members = {f.name for cls in types[1:] for f in dataclasses.fields(cls)}
    members |= {n for cls in types for n in vars(cls) if not n.startswith("__")}
    only_some = members - set(dir(model.Law)) - set(model.Law.__annotations__)
    bad = []
    for rel, text in _modules():
        if rel.startswith("model/"):
            continue
        for node in ast.walk(ast.parse(text)):
            if not isinstance(node, ast.Call) or not isinstance(node.func, ast.Name):
                continue
            if node.func.id == "isinstance" and len(node.args) == 2:
                names = {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}
                if names & {cls.__name__ for cls in types}:
                    bad.append(f"{rel}:{node.lineno}: isinstance on a motion-law class")
            if node.func.id in ("hasattr", "getattr") and len(node.args) >= 2:
                attr, obj = node.args[1], ast.unparse(node.args[0]).lower()
                if not isinstance(attr, ast.Constant) or attr.value not in members:
                    continue
                if attr.value in only_some or "motion" in obj or "law" in obj:
                    bad.append(f"{rel}:{node.lineno}: {node.func.id}(…, {attr.value!r}) on a law")
    assert not bad, "\n".join(bad)


def test_modules_stay_small():
    big = [
        f"{rel}: {text.count(chr(10))} lines"
        for rel, text in _modules()
        if text.count("\n") > MAX_LINES
    ]
    assert not big, big


def test_no_hidden_caches():
    """No value is kept on a frozen object or in a closure after construction unless
    docs/architecture.md names it ("What is computed once": the counter's DOCUMENTED) or
    it is the job of a mutable working object (BY_DESIGN); a listed site that went away
    leaves its list."""
    sites = hidden_caches()
    assert not sites["hidden"], sites["hidden"]
    listed = {(m, what.split(":")[0]) for m, _, what in sites["documented"]}
    assert set(DOCUMENTED) == listed, set(DOCUMENTED) ^ listed
    assert set(BY_DESIGN) == {m for m, _, _ in sites["by_design"]}


def test_docs_tree_is_the_tree():
    """Every module on disk is in the tree of docs/architecture.md, and nothing else is."""
    doc = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    block = doc.split("<!-- tree:begin -->", 1)[1].split("<!-- tree:end -->", 1)[0]
    listed, folder = set(), []
    for line in block.splitlines():
        m = re.match(r"^([ │├└─]*)([\w.]+/?)", line)
        if not m or not m.group(2).strip():
            continue
        depth = len(m.group(1)) // 4
        name = m.group(2)
        folder = folder[:depth]
        if name.endswith("/"):
            folder.append(name.rstrip("/"))
        else:
            listed.add("/".join([*folder, name]))
    on_disk = {rel for rel, _ in _modules()}
    assert sorted(on_disk - listed) == [], "modules missing from docs/architecture.md"
    assert sorted(listed - on_disk) == [], "docs/architecture.md lists modules that do not exist"


# -- function length ---------------------------------------------------------------------
MAX_FUNCTION_LINES = 60
_IO_SECTION = "one YAML section: its keys checked and read in turn, each with its message"
_CLI_OPTIONS = "the command's argparse declarations, one add_argument per option"
_FIGURE = "one figure: its axes, curves, labels and legend in drawing order"
_CHAPTER = "one part of the report: its blocks in reading order (a document, not logic)"
# {module:qualified name: why it may be longer than MAX_FUNCTION_LINES (def to last line,
# the docstring not counted)}
LONG_FUNCTIONS = {
    "base/document.py:compose": "one walk of the YAML event stream, a branch per node kind",
    "cli/batch.py:register": _CLI_OPTIONS,
    "cli/dynamics.py:register": _CLI_OPTIONS,
    "cli/pictures.py:register": _CLI_OPTIONS,
    "cli/dynamics.py:_simulate": "the simulate command: each option applied, then the files",
    "cli/pictures.py:_plot": "one branch per kind of picture",
    "dynamics/clearance.py:expand": "the clearance macro: journal, bushing, joints built in turn",
    "dynamics/contact.py:simulate_contact": "12 lines of keywords, 9 of doc; one integration loop",
    "dynamics/engine.py:Dynamics.__init__": "the engine's constant arrays, set up once, by kind",
    "dynamics/simulation.py:Simulation.table": "one table: a block of columns per quantity",
    "io/drive.py:DriveSection._drive": _IO_SECTION,
    "io/dump.py:dump": "Model → YAML: one block per section, in the file's order",
    "io/laws.py:LawSections._law": _IO_SECTION,
    "io/loads.py:LoadSections._load": _IO_SECTION,
    "io/loads.py:LoadSections._conditions": _IO_SECTION,
    "io/parameters.py:ParameterSections._parameters": _IO_SECTION,
    "io/settings.py:SettingSections._analysis": _IO_SECTION,
    "outputs/plotting/animate.py:_write": "the frames drawn and written, as GIF or MP4",
    "outputs/plotting/drive.py:torque_speed": _FIGURE,
    "outputs/plotting/energy.py:equivalent_moments": _FIGURE,
    "outputs/plotting/polar.py:polar_diagrams": _FIGURE,
    "outputs/plotting/polygons.py:polygon_figure": _FIGURE,
    "outputs/plotting/polygons.py:_polygon_sheet": _FIGURE,
    "outputs/plotting/scene.py:_Scene.__init__": "the drawing's geometry gathered once, by kind",
    "outputs/report/data.py:_data_blocks": _CHAPTER,
    "outputs/report/document.py:write_report": _CHAPTER,
    "outputs/report/drive.py:drive_blocks": _CHAPTER,
    "outputs/report/elements.py:element_blocks": _CHAPTER,
    "outputs/report/flywheel.py:flywheel_blocks": _CHAPTER,
    "outputs/report/pdf.py:write_pdf": "the PDF rendered block by block",
    "outputs/report/results.py:report_tables": _CHAPTER,
    "outputs/report/results.py:_summary_blocks": _CHAPTER,
    "structure/graph.py:structure": "the structure in its steps: graph, loops, mobility, groups",
}


def _long_functions() -> dict[str, int]:
    """{module:qualified name: lines} of every function and method (nested ones too)
    longer than MAX_FUNCTION_LINES, from its ``def`` to its last line, its docstring not
    counted (tests/architecture/architecture_counts.py's rule)."""

    def walk(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield prefix + child.name, child
                yield from walk(child, f"{prefix}{child.name}.")
            elif isinstance(child, ast.ClassDef):
                yield from walk(child, f"{prefix}{child.name}.")
            else:
                yield from walk(child, prefix)

    out = {}
    for rel, text in _modules():
        for name, fn in walk(ast.parse(text), ""):
            lines = function_length(fn)
            if lines > MAX_FUNCTION_LINES:
                out[f"{rel}:{name}"] = lines
    return out


def test_functions_stay_short():
    """No function is longer than MAX_FUNCTION_LINES unless LONG_FUNCTIONS says why; an
    entry whose function became short (or went) leaves the list."""
    long = _long_functions()
    unexplained = {k: v for k, v in long.items() if k not in LONG_FUNCTIONS}
    assert not unexplained, f"functions over {MAX_FUNCTION_LINES} lines: {unexplained}"
    stale = sorted(set(LONG_FUNCTIONS) - set(long))
    assert not stale, f"LONG_FUNCTIONS names functions that are short or gone: {stale}"
    assert all(why.strip() for why in LONG_FUNCTIONS.values())


def test_each_lazy_import_has_its_reason():
    """Outside cli/, the lazy imports of the package's own modules (inside a function) are
    those of the table in docs/architecture.md, module by module, each with its reason."""
    doc = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    block = doc.split("<!-- lazy:begin -->", 1)[1].split("<!-- lazy:end -->", 1)[0]
    table = {}
    for line in block.splitlines():
        m = re.match(r"^\| `([\w/]+\.py)` \| (\d+) \| (.*) \|$", line)
        if m:
            assert m.group(3).strip(), f"{m.group(1)}: no reason given"
            table[m.group(1)] = int(m.group(2))
    found = lazy_imports()
    wrong = [
        f"{rel}: {len(found.get(rel, []))} in the code (lines {found.get(rel, [])}), "
        f"{table.get(rel, 0)} in docs/architecture.md"
        for rel in sorted(set(found) | set(table))
        if len(found.get(rel, [])) != table.get(rel, 0)
    ]
    assert not wrong, "\n".join(wrong)


def test_no_type_told_apart_outside_its_home():
    """No motion law is asked for its class or probed outside model/, and no load or
    condition kind is compared by name outside kinetics/kinds.py in the layers that act on
    it (tests/architecture/architecture_counts.py, ``type_checks_outside_home``)."""
    assert type_checks() == []


def test_the_counts_on_the_page_are_the_code_s():
    """docs/architecture.md's table of counts ("now") is what the script counts today
    (``python tests/architecture/architecture_counts.py --write`` rewrites it)."""
    c = counts()
    page = shown(DOC.read_text(encoding="utf-8"))
    assert page == {key: str(c[key]) for key, _ in SHOWN}
