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
from tests.architecture.architecture_counts import lazy_imports

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


def test_modules_stay_small():
    big = [
        f"{rel}: {text.count(chr(10))} lines"
        for rel, text in _modules()
        if text.count("\n") > MAX_LINES
    ]
    assert not big, big


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
