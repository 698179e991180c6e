"""A 360-frame animation of the slotting machine (issue "Pictures": under 60 s
on the 2-core machine), with and without the force overlay; wall time from
loading the YAML to the written GIF, analysis included.

    python tests/benchmarks/bench_animation.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from _common import ROOT

import kinetostatics as ks
from kinetostatics.outputs import plotting as pl


def once(out: Path, forces: bool) -> float:
    t0 = time.perf_counter()
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    result = pl.analyze_for_pictures(model, frames=360, events=False)
    pl.animate(result, out, forces=forces, paths=["rod.C"])
    return time.perf_counter() - t0


def main() -> None:
    from PIL import Image

    with tempfile.TemporaryDirectory() as tmp:
        for forces in (False, True):
            out = Path(tmp) / f"slotting_{'forces' if forces else 'plain'}.gif"
            wall = once(out, forces)
            with Image.open(out) as im:
                frames = im.n_frames
            print(
                f"slotting machine, {frames} frames{' with forces' if forces else ''}: "
                f"{wall:.1f} s ({out.stat().st_size / 1e6:.1f} MB)  target < 60 s"
            )


if __name__ == "__main__":
    main()
