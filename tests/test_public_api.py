"""The public API (docs/api.md) shows itself: ``dir(kinetostatics)`` is ``__all__``, still
imported lazily."""

import json
import os
import subprocess
import sys
from pathlib import Path

import kinetostatics as ks

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"


def _fresh(code: str) -> str:
    """Run ``code`` in a new interpreter on this checkout's package; its stdout."""
    env = dict(os.environ, PYTHONPATH=str(SRC))
    proc = subprocess.run(
        [sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_dir_lists_every_public_name_and_no_internal_one():
    shown = set(dir(ks))
    assert set(ks.__all__) <= shown  # the lazy ones too (analyze, Result, …)
    private = {n for n in shown if not (n.startswith("__") and n.endswith("__"))}
    assert private == set(ks.__all__) - {"__version__"}
    # the submodules imported by `import kinetostatics` are attributes, but not API
    for internal in ("base", "errors", "io", "joints", "model", "outputs", "VERSION", "_aliases"):
        assert internal not in shown
        assert hasattr(ks, internal)  # still importable, not the API


def test_every_public_name_resolves_and_is_the_object_its_module_defines():
    from kinetostatics.analysis.pipeline import analyze
    from kinetostatics.analysis.results import Result
    from kinetostatics.base.kernels import set_backend
    from kinetostatics.batch.optimize import optimize
    from kinetostatics.structure.system import build_system

    for name in ks.__all__:
        assert getattr(ks, name) is not None, name
    assert ks.analyze is analyze and ks.Result is Result and ks.optimize is optimize
    assert ks.set_backend is set_backend and ks.build_system is build_system
    assert ks.__version__ == ks.VERSION
    assert ks.plotting is __import__("kinetostatics.outputs.plotting", fromlist=["x"])


def test_an_unknown_name_is_an_attribute_error():
    try:
        ks.no_such_name  # noqa: B018
    except AttributeError as e:
        assert "no_such_name" in str(e)
    else:
        raise AssertionError("no AttributeError")


def test_dir_keeps_the_import_light():
    """Listing the API imports none of the lazily loaded stages' heavy dependencies."""
    out = _fresh(
        "import json, sys, kinetostatics as ks; names = dir(ks); "
        "print(json.dumps([names, sorted(sys.modules)]))"
    )
    names, modules = json.loads(out)
    assert "analyze" in names and "Result" in names
    for heavy in ("matplotlib", "scipy.integrate", "kinetostatics.batch.optimize"):
        assert heavy not in modules, heavy
