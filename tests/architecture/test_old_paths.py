"""The import paths from before the layer packages keep working (docs/architecture.md)."""

import importlib
import re

import pytest

from kinetostatics import _aliases


@pytest.mark.parametrize("old", sorted(_aliases.OLD_PATHS))
def test_old_path_is_the_new_module(old):
    before = importlib.import_module(f"kinetostatics.{old}")
    now = importlib.import_module(f"kinetostatics.{_aliases.OLD_PATHS[old]}")
    assert before is now
    assert before.__spec__.name == now.__name__  # the module keeps its own spec


def test_documented_names():
    from kinetostatics.flywheel import design  # noqa: F401
    from kinetostatics.plotting import draw_mechanism  # noqa: F401

    import kinetostatics as ks
    from kinetostatics.analysis import analyze, kinetics  # noqa: F401
    from kinetostatics.dynamics import simulate  # noqa: F401
    from kinetostatics.yaml_io import MAGNITUDE, dump, load, loads  # noqa: F401

    assert ks.yaml_io.dump is dump and ks.positions is ks.kinematics.positions


def test_nothing_else_uses_the_old_paths():
    """Only this file imports the old paths: the tests, their scripts, docs/scripts and the
    code the pages show use the new ones (docs/architecture.md, *Old import paths*)."""
    from tests.helpers import ROOT

    old = "|".join(sorted([*_aliases.OLD_PATHS, "yaml_io"]))
    uses = re.compile(
        rf"^\s*(from kinetostatics\.({old}) import|import kinetostatics\.({old})\b"
        rf"|from kinetostatics import .*\b({old})\b)|\bks\.({old})\b"
    )
    files = [*(ROOT / "tests").rglob("*.py"), *(ROOT / "docs").rglob("*.py")]
    files += [*(ROOT / "docs").glob("*.md"), ROOT / "README.md"]
    found = [
        f"{path.relative_to(ROOT)}:{n}: {line.strip()}"
        for path in sorted(files)
        if path.name != "test_old_paths.py"
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if uses.search(line)
        and (path.suffix == ".py" or line.lstrip().startswith(("from", "import")))
    ]
    assert not found, "\n".join(found)
