"""docs/python.md runs: its ```python blocks are executed in order, in one namespace,
in a temporary folder that holds the repository's mechanisms/ (matplotlib Agg)."""

import os
import re

import matplotlib
import pytest

from tests.helpers import ROOT

DOC = ROOT / "docs" / "python.md"
FENCE = re.compile(r"^```python\n(.*?)^```[ \t]*$", re.S | re.M)


def test_python_walkthrough_runs(tmp_path, monkeypatch):
    pytest.importorskip("pandas")
    pytest.importorskip("xarray")
    matplotlib.use("Agg")
    blocks = FENCE.findall(DOC.read_text(encoding="utf-8"))
    assert len(blocks) >= 6
    (tmp_path / "mechanisms").symlink_to(ROOT / "mechanisms")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "docs_python"}
    for k, code in enumerate(blocks, 1):
        try:
            exec(compile(code, f"docs/python.md block {k}", "exec"), namespace)
        except Exception as exc:
            raise AssertionError(f"docs/python.md block {k} failed: {exc!r}\n{code}") from exc
    assert (tmp_path / "torque.png").stat().st_size > 0
    assert (tmp_path / "torque_pandas.png").stat().st_size > 0
    assert sorted(os.listdir(tmp_path)) == ["mechanisms", "torque.png", "torque_pandas.png"]
