"""A corpus of broken mechanism files and the exact message each must produce.

Every file in ``tests/broken/`` is the offset slider-crank of
``mechanisms/slider_crank.yaml`` with one thing changed.  Its first comment
lines describe what it must do:

``# expect: <line>``
    one per problem, in order: the exact lines of ``str(exc)``, i.e.
    ``FILE:LINE:COL: key.path: message`` for a model error;
``# expect-re: <regex>``
    instead of ``expect`` where the message holds a computed number (matched
    with :func:`re.fullmatch`);
``# stage: load | structure | analyze``
    where the error must be raised: by ``kinetostatics.load`` (the default),
    by ``kinetostatics.build_system`` (the model loads) or by
    ``kinetostatics.analyze`` (the model loads and builds);
``# <text>``
    what was changed.

Paths: every file is loaded with the working directory set to
``tests/broken`` and its bare file name as the path, so the FILE part of a
message is just the file name (``negative_mass.yaml:23:11: ...``) and the
expected lines do not depend on where the repository lives.  The CLI is run
the same way: ``kinetostatics check NAME`` for load and structure errors,
``kinetostatics run NAME --out DIR`` for run-time errors; it must exit with 2
and print exactly the expected lines on stderr (a line that does not start
with the file name is prefixed with ``kinetostatics: ``), and no traceback.

To add a case: copy a file, change one thing, write the ``# expect:`` lines a
user would find helpful (improve the loader if its message is not), run this
test.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import pytest

import kinetostatics as ks
from kinetostatics.base.limits import MAX_FILE_BYTES
from kinetostatics.cli import main

BROKEN = Path(__file__).parents[1] / "broken"
MECHANISMS = Path(__file__).parents[2] / "mechanisms"
FILES = sorted(p.name for p in BROKEN.glob("*.yaml"))
STAGES = ("load", "structure", "analyze")


@dataclass(frozen=True)
class Expectation:
    lines: tuple[str, ...]  # exact lines or regular expressions
    regex: bool
    stage: str


def expectation(name: str) -> Expectation:
    """The ``# expect:``/``# expect-re:``/``# stage:`` header of a corpus file."""
    exact, regex, stage = [], [], "load"
    for line in (BROKEN / name).read_text(encoding="utf-8", errors="replace").splitlines():
        if not line.startswith("#"):
            break
        if line.startswith("# expect: "):
            exact.append(line[len("# expect: ") :])
        elif line.startswith("# expect-re: "):
            regex.append(line[len("# expect-re: ") :])
        elif line.startswith("# stage: "):
            stage = line[len("# stage: ") :].strip()
    assert bool(exact) != bool(regex), f"{name}: give '# expect:' or '# expect-re:' lines"
    assert stage in STAGES, f"{name}: unknown stage '{stage}'"
    return Expectation(tuple(exact or regex), bool(regex), stage)


def assert_lines(got: list[str], exp: Expectation) -> None:
    if exp.regex:
        assert len(got) == len(exp.lines), got
        for g, w in zip(got, exp.lines):
            assert re.fullmatch(w, g), f"{g!r} does not match {w!r}"
    else:
        assert got == list(exp.lines)


def run_pipeline(name: str) -> tuple[str, ks.KinetostaticsError | None]:
    """Load, build and analyse; return the stage that raised and the error."""
    stage = "load"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            model = ks.load(name)
            stage = "structure"
            system = ks.build_system(model)
            stage = "analyze"
            ks.analyze(system)
        except ks.KinetostaticsError as exc:
            return stage, exc
    return "none", None


def test_corpus_is_large_enough():
    assert len(FILES) >= 40


@pytest.mark.parametrize("name", FILES)
def test_broken_file_message(name, monkeypatch):
    exp = expectation(name)
    monkeypatch.chdir(BROKEN)
    stage, exc = run_pipeline(name)
    assert exc is not None, f"{name} was accepted"
    assert stage == exp.stage, f"raised at {stage}, expected at {exp.stage}: {exc}"
    assert_lines(str(exc).splitlines(), exp)
    if isinstance(exc, ks.ModelError):
        assert len(exc.problems) == len(exp.lines)


@pytest.mark.parametrize("name", FILES)
def test_broken_file_cli(name, monkeypatch, capsys, tmp_path):
    exp = expectation(name)
    monkeypatch.chdir(BROKEN)
    argv = ["check", name] if exp.stage != "analyze" else ["run", name, "--out", str(tmp_path)]
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if exp.stage == "analyze":
        assert not (tmp_path / "results.csv").exists()
    else:
        assert out == ""
    # one line per problem; a line that does not name the file names the program
    lines = err.splitlines()
    assert all(line.startswith((name, "kinetostatics: ")) for line in lines), lines
    assert_lines([line.removeprefix("kinetostatics: ") for line in lines], exp)


@pytest.mark.timeout(30)  # a hang, not a slow machine: it is refused in milliseconds
def test_alias_bomb_is_refused_quickly(monkeypatch):
    monkeypatch.chdir(BROKEN)
    with pytest.raises(ks.ModelError, match="alias"):
        ks.load("alias_bomb.yaml")


def _oversize(tmp_path: Path) -> tuple[str, int]:
    """A valid slider-crank padded with comments past the size limit."""
    text = (MECHANISMS / "slider_crank.yaml").read_text(encoding="utf-8")
    pad = "# " + "x" * 98 + "\n"
    text += pad * ((MAX_FILE_BYTES - len(text)) // len(pad) + 2)
    (tmp_path / "huge.yaml").write_text(text, encoding="utf-8")
    return "huge.yaml", len(text.encode("utf-8"))


@pytest.mark.timeout(30)
def test_file_over_size_limit(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    name, size = _oversize(tmp_path)
    assert size > MAX_FILE_BYTES
    with pytest.raises(ks.ModelError) as info:
        ks.load(name)
    assert str(info.value) == (
        f"{name}: the file is {size} bytes, more than the limit of {MAX_FILE_BYTES} bytes; refused"
    )


def test_file_over_size_limit_cli(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    name, size = _oversize(tmp_path)
    assert main(["check", name]) == 2
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    assert err.splitlines() == [
        f"{name}: the file is {size} bytes, more than the limit of {MAX_FILE_BYTES} bytes; refused"
    ]


def test_missing_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ks.ModelError) as info:
        ks.load("nowhere.yaml")
    assert str(info.value) == "nowhere.yaml: cannot read the file: No such file or directory"


@pytest.mark.parametrize("name", ["slider_crank.yaml", "slotting_machine.yaml"])
def test_shipped_examples_still_load(name):
    model = ks.load(MECHANISMS / name)
    assert ks.build_system(model).structure.mobility == 1
