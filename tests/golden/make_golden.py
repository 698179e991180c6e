"""Golden files of every shipped mechanism, written before a refactor and compared after.

    PYTHONPATH=src python tests/golden/make_golden.py

For each ``mechanisms/*.yaml`` this writes, under ``tests/golden/<name>/``, what
the command line gives: ``check.txt`` (``kinetostatics check``), and for a file
with its motion drivers ``results.csv.gz`` and ``summary.json``
(``kinetostatics run``) and ``geometry.json`` (the drawing data of
``plotting.mechanism_geometry`` at rows 0 and 100), for one without them ``simulation.csv.gz``
(``kinetostatics simulate --until 0.2 --no-plot``; ``UNTIL`` for some).
``tests/architecture/test_golden.py`` runs the same commands and compares.  Rewrite the files
only when a change of behaviour is intended, and say so in the commit.
"""

from __future__ import annotations

import contextlib
import gzip
import io
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
MECHANISMS = sorted((ROOT / "mechanisms").glob("*.yaml"))
SIMULATE = ["--until", "0.2", "--no-plot"]
UNTIL = {"andrews_squeezer": "0.03"}  # its benchmark's span (0.2 s took 36 s of the test run)


def _cli(argv: list[str]) -> tuple[int, str]:
    from kinetostatics.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(argv)
    return code, out.getvalue()


def produce(path: Path, folder: Path) -> dict[str, str]:
    """Run the commands on one mechanism file; returns {file name: text}."""
    files = {}
    code, text = _cli(["check", str(path)])
    files["check.txt"] = text.replace(str(path), path.name)
    out = folder / path.stem
    code, _ = _cli(["run", str(path), "--out", str(out)])
    if code == 0:
        files["results.csv"] = (out / "results.csv").read_text(encoding="utf-8")
        files["summary.json"] = (out / "summary.json").read_text(encoding="utf-8")
        files["geometry.json"] = geometry(path)
    else:
        sim = SIMULATE if path.stem not in UNTIL else ["--until", UNTIL[path.stem], "--no-plot"]
        code, _ = _cli(["simulate", str(path), "--out", str(out), *sim])
        assert code == 0, path
        files["simulation.csv"] = (out / "simulation.csv").read_text(encoding="utf-8")
    return files


def _plain(x):
    """A JSON-able copy of the drawing data (arrays to lists, records to dicts)."""
    import dataclasses

    import numpy as np

    if dataclasses.is_dataclass(x):
        return {f.name: _plain(getattr(x, f.name)) for f in dataclasses.fields(x)}
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (frozenset, set)):
        return sorted(_plain(v) for v in x)
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    return x


def geometry(path: Path) -> str:
    """``plotting.mechanism_geometry`` at rows 0 and 100, as JSON."""
    import json

    import kinetostatics as ks
    from kinetostatics.outputs import plotting

    result = ks.analyze(ks.load(path))
    rows = [plotting.mechanism_geometry(result, row) for row in (0, 100)]
    return json.dumps(_plain(rows), indent=1)


def write(name: str, text: str, folder: Path) -> None:
    if name.endswith(".csv"):
        data = gzip.compress(text.encode("utf-8"), compresslevel=9, mtime=0)
        (folder / f"{name}.gz").write_bytes(data)  # mtime 0: the same text, the same bytes
    else:
        (folder / name).write_text(text, encoding="utf-8")


def read(name: str, folder: Path) -> str:
    if name.endswith(".csv"):
        with gzip.open(folder / f"{name}.gz", "rt", encoding="utf-8") as f:
            return f.read()
    return (folder / name).read_text(encoding="utf-8")


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        for path in MECHANISMS:
            folder = HERE / path.stem
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir()
            for name, text in produce(path, Path(tmp)).items():
                write(name, text, folder)
            print(path.name, "->", ", ".join(sorted(p.name for p in folder.iterdir())))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT / "src"))
    raise SystemExit(main())
