"""Shared helpers of the ``tests/benchmarks/accuracy_*.py`` scripts (docs/accuracy.md).

Each script prints Markdown blocks between ``<!-- BEGIN accuracy:<name> -->``
and ``<!-- END accuracy:<name> -->``; ``--update`` rewrites the same blocks in
``docs/accuracy.md``; ``--quick`` times with fewer repeats.  Columns whose
header is in :data:`TIMING` hold wall times: they change from run to run and
machine to machine (``tests/docs/test_docs_accuracy.py`` checks every other cell).
"""

from __future__ import annotations

import contextlib
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
for p in (ROOT, ROOT / "tests" / "benchmarks", ROOT / "docs" / "scripts"):
    if str(p) not in sys.path:
        sys.path.insert(0, str(p))

from _common import best_of as _best_of  # noqa: E402  (tests/benchmarks/_common.py)

import kinetostatics as ks  # noqa: E402
from kinetostatics.kinematics import (  # noqa: E402
    closed_path,
    continuation,
    dyads,
    newton,
    positions,
    start,
)

DOC = ROOT / "docs" / "accuracy.md"
IMG = ROOT / "docs" / "img"
PLACEHOLDER = "·"
REPEAT = 7


def best_of(f, repeat: int | None = None) -> float:
    """Best wall time of one call of f (s): tests/benchmarks/_common.py ``best_of``."""
    return _best_of(f, repeat=REPEAT if repeat is None else repeat)


def system(name: str) -> ks.System:
    """A fresh system of ``mechanisms/<name>.yaml`` (or a path)."""
    path = ROOT / "mechanisms" / f"{name}.yaml" if "/" not in name else ROOT / name
    return ks.build_system(ks.load(path))


# ------------------------------------------------------------------ solver knobs
@contextlib.contextmanager
def general_path():
    """Disable the closed-form dyads: every group goes through the Newton path.

    Systems built inside the block cache the choice (build them inside it)."""
    saved = dyads.closed_form
    dyads.closed_form = lambda *a, **k: None
    try:
        yield
    finally:
        dyads.closed_form = saved


# the modules of the position solve: each holds its own binding of an imported name
SOLVE_MODULES = (newton, continuation, start, closed_path, positions)


@contextlib.contextmanager
def knobs(**values):
    """Temporarily set names of the position solve (TOL, COARSE_STEP…, or a function
    such as ``group_newton``) in every module of :data:`SOLVE_MODULES` that holds them."""
    saved = []
    for k, v in values.items():
        holders = [m for m in SOLVE_MODULES if hasattr(m, k)]
        if not holders:
            raise AttributeError(f"no module of the position solve has {k!r}")
        for m in holders:
            saved.append((m, k, getattr(m, k)))
            setattr(m, k, v)
    try:
        yield
    finally:
        for m, k, v in reversed(saved):
            setattr(m, k, v)


# ------------------------------------------------------------------ errors
def column_error(x: np.ndarray, ref: np.ndarray) -> float:
    """max over columns of max|x − ref| / max|ref|; columns with ref ≡ 0 skipped."""
    x, ref = np.atleast_2d(x.T).T, np.atleast_2d(ref.T).T
    scale = np.max(np.abs(ref), axis=0)
    keep = scale > 1e-12 * np.max(scale)
    return float(np.max(np.max(np.abs(x - ref), axis=0)[keep] / scale[keep]))


def pose_error(system: ks.System, q: np.ndarray, ref: np.ndarray) -> float:
    """max |Δx|, |Δy| over L_ref and |Δθ| in rad (angles wrapped)."""
    d = q - ref
    d[..., 2::3] = (d[..., 2::3] + np.pi) % (2 * np.pi) - np.pi
    d[..., 0::3] /= system.l_ref
    d[..., 1::3] /= system.l_ref
    return float(np.max(np.abs(d)))


def slider_crank_state(p, phi: np.ndarray):
    """(q, q̇, q̈) of the closed form in the library's layout (tests/oracles)."""
    from tests.oracles import slider_crank_closed_form as cf

    return cf.state(p, phi)


# ------------------------------------------------------------------ tables
@dataclass
class Table:
    """A Markdown table; ``timing`` names the columns holding wall times."""

    header: list[str]
    rows: list[list[str]] = field(default_factory=list)
    timing: set[str] = field(default_factory=set)

    def add(self, *cells) -> None:
        self.rows.append([str(c) for c in cells])

    def markdown(self) -> str:
        lines = ["| " + " | ".join(self.header) + " |", "|" + "---|" * len(self.header)]
        lines += ["| " + " | ".join(r) + " |" for r in self.rows]
        return "\n".join(lines)


def ms(seconds: float | None) -> str:
    return PLACEHOLDER if seconds is None else f"{seconds * 1e3:.3g}"


def us(seconds: float | None) -> str:
    return PLACEHOLDER if seconds is None else f"{seconds * 1e6:.3g}"


def e(x: float) -> str:
    return f"{x:.1e}"


def block(name: str, body: str) -> str:
    return f"<!-- BEGIN accuracy:{name} -->\n{body.strip()}\n<!-- END accuracy:{name} -->"


def update_doc(blocks: dict[str, str]) -> None:
    """Replace the blocks of docs/accuracy.md by the new ones (each must exist)."""
    text = DOC.read_text()
    for name, body in blocks.items():
        pat = re.compile(
            rf"<!-- BEGIN accuracy:{re.escape(name)} -->.*?<!-- END accuracy:{re.escape(name)} -->",
            re.S,
        )
        if not pat.search(text):
            raise SystemExit(f"docs/accuracy.md has no block accuracy:{name}")
        text = pat.sub(lambda _m, name=name, body=body: block(name, body), text)
    DOC.write_text(text)


def save_figure(fig, name: str) -> list[Path]:
    """Lay out, write ``docs/img/<name>`` and close a figure; the list of paths written."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    path = IMG / name
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]


def main(build, argv=None) -> None:
    """Command line of a script: ``build(timing: bool) -> (blocks, plot)``."""
    global REPEAT
    argv = sys.argv[1:] if argv is None else argv
    if "--quick" in argv:
        REPEAT = 3
    blocks, plot = build(timing=True)
    for name, body in blocks.items():
        print(block(name, body))
        print()
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        IMG.mkdir(exist_ok=True)
        for path in plot():
            print(f"wrote {path.relative_to(ROOT)}")
    if "--update" in argv:
        update_doc(blocks)
        print(f"updated {DOC.relative_to(ROOT)}")
