"""The public API (docs/api.md) shows itself: ``dir(kinetostatics)`` is ``__all__``, still
imported lazily."""

import json
import os
import subprocess
import sys
from pathlib import Path

import kinetostatics as ks

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"


def _env() -> dict[str, str]:
    """The environment, with this checkout's package first on the path."""
    path = [str(SRC), *filter(None, [os.environ.get("PYTHONPATH")])]
    return dict(os.environ, PYTHONPATH=os.pathsep.join(path))


def _fresh(code: str) -> str:
    """Run ``code`` in a new interpreter on this checkout's package; its stdout."""
    proc = subprocess.run(
        [sys.executable, "-c", code], env=_env(), cwd=ROOT, capture_output=True, text=True
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


# --- docstrings: numpydoc sections on every public callable (docs/api.md) -------------------

# numpydoc's checks left out, with why; every other check of numpydoc.validate applies.
IGNORED = {
    "SA01": "See Also is given where a related name helps, not required on every callable",
    "ES01": "an extended summary is optional: a one-line summary suffices for many methods",
    "GL01": "the summary starts on the line of the opening quotes (PEP 257, the project's "
    "style); numpydoc 1.8 asks for the next line, later versions accept both",
}


def public_callables() -> list[str]:
    """The dotted names of ``kinetostatics.__all__``'s callables and their public methods
    (the counts of tests/architecture/architecture_counts.py count the same)."""
    import inspect

    names = []
    for name in ks.__all__:
        obj = getattr(ks, name)
        if not callable(obj):
            continue
        names.append(f"kinetostatics.{name}")
        if inspect.isclass(obj) and not issubclass(obj, BaseException | Warning):
            names += [
                f"kinetostatics.{name}.{attr}"
                for attr, member in vars(obj).items()
                if not attr.startswith("_") and callable(member)
            ]
    return names


def test_the_public_callables_are_the_ones_counted():
    names = public_callables()
    assert len(names) == len(set(names)) >= 28  # 28 when docs/api.md was written
    assert "kinetostatics.Result.summary" in names and "kinetostatics.analyze" in names


def test_every_public_callable_has_valid_numpydoc_sections():
    from numpydoc.validate import validate

    problems = []
    for name in public_callables():
        for code, message in validate(name)["errors"]:
            if code not in IGNORED:
                problems.append(f"{name}: {code} {message}")
    assert not problems, "\n".join(problems)


def test_every_public_callable_has_typed_signatures():
    import inspect

    for name in public_callables():
        obj = ks
        for part in name.split(".")[1:]:
            obj = getattr(obj, part)
        sig = inspect.signature(obj)
        untyped = [p for n, p in sig.parameters.items() if n not in ("self", "cls")]
        untyped = [p.name for p in untyped if p.annotation is inspect.Parameter.empty]
        assert not untyped, (name, untyped)
        if not inspect.isclass(obj):
            assert sig.return_annotation is not inspect.Signature.empty, name


def test_the_examples_run(monkeypatch):
    """Each public docstring's Examples, those that need no file, run as doctests."""
    import doctest

    monkeypatch.chdir(ROOT)
    finder, runner = doctest.DocTestFinder(recurse=False), doctest.DocTestRunner()
    ran = 0
    for name in public_callables():
        obj = ks
        for part in name.split(".")[1:]:
            obj = getattr(obj, part)
        for test in finder.find(obj, name, globs={}):
            result = runner.run(test)
            assert result.failed == 0, name
            ran += sum(not e.options.get(doctest.SKIP) for e in test.examples)
    assert ran >= 20  # the Examples of the exceptions, loads and set_backend run


# --- types: py.typed, and mypy over the modules that define the public API -----------------


def _pyproject() -> dict:
    try:
        import tomllib
    except ImportError:  # Python 3.10: mypy brings tomli
        import tomli as tomllib
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_the_package_says_it_is_typed():
    assert (SRC / "kinetostatics" / "py.typed").is_file()
    data = _pyproject()["tool"]["setuptools"]["package-data"]["kinetostatics"]
    assert "py.typed" in data  # so the wheel has it (.ci/run checks the installed one)


def test_mypy_checks_every_module_that_defines_a_public_callable():
    import inspect

    files = set(_pyproject()["tool"]["mypy"]["files"])
    for name in public_callables():
        obj = ks
        for part in name.split(".")[1:]:
            obj = getattr(obj, part)
        path = Path(inspect.getsourcefile(obj)).resolve().relative_to(ROOT).as_posix()
        assert path in files, (name, path)
    assert "src/kinetostatics/__init__.py" in files


def _mypy(*args: str) -> subprocess.CompletedProcess:
    """mypy with the configuration of pyproject.toml ([tool.mypy]); its cache is kept in
    the temporary folder, so a run after the first takes about a second (the first one,
    about five seconds of CPU)."""
    import hashlib
    import tempfile

    cache = Path(tempfile.gettempdir()) / (
        "kinetostatics-mypy-" + hashlib.sha1(str(ROOT).encode()).hexdigest()[:12]
    )
    cmd = [sys.executable, "-m", "mypy", "--cache-dir", str(cache), "--no-color-output", *args]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)


def test_mypy_passes_on_the_public_modules():
    proc = _mypy()
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.startswith("Success: no issues found"), proc.stdout


# A user's script as a type checker sees it through py.typed: the lazy names have their
# types, and a wrong call is an error (mypy is told Python 3.10: assert_type from
# typing_extensions, whose stubs mypy carries).
USER_SCRIPT = """\
from pathlib import Path
from typing import Any

import numpy as np
from typing_extensions import assert_type

import kinetostatics as ks


def use(path: Path) -> None:
    model = ks.load(path, parameters={"r": 0.1})
    assert_type(model, ks.Model)
    result = ks.analyze(model, positions=np.radians([0.0, 90.0]), friction=False)
    assert_type(result, ks.Result)
    assert_type(result.summary(), dict[str, Any])
    assert_type(ks.build_system(model), ks.Result)  # line 16, wrong: a System
    ks.set_backend(3)  # line 17, wrong: a str
"""


def test_a_users_type_checker_sees_the_public_types(tmp_path):
    script = tmp_path / "script.py"
    script.write_text(USER_SCRIPT, encoding="utf-8")
    proc = _mypy(str(script))
    errors = [line for line in proc.stdout.splitlines() if ": error:" in line]
    assert [e.split(":")[1] for e in errors] == ["16", "17"], proc.stdout + proc.stderr


# --- the API reference: Sphinx over docs/api, warnings as errors --------------------------


def test_the_api_reference_builds_and_lists_the_public_api_only(tmp_path):
    """docs/api/ built by Sphinx with warnings as errors (a few seconds); its page has an
    entry for every public name and for nothing else, and links nowhere outside itself."""
    import re

    env = _env()
    out = tmp_path / "html"
    cmd = [sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", "docs/api", str(out)]
    proc = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    page = (out / "index.html").read_text(encoding="utf-8")
    entries = set(re.findall(r'<dt class="sig[^"]*" id="(kinetostatics[\w.]*)"', page))
    assert entries == {*public_callables(), "kinetostatics.__version__"}
    assert not re.search(r'(?:href|src)="(?:https?:)?//', page)  # nothing outside
    assert "Parameters" in page and "Examples" in page  # the numpydoc sections rendered
