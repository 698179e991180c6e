"""docs/sensitivity.md, the slotting machine's worked example (the block written by
docs/scripts/sensitivity_example.py): its claims checked against what the file is written
in, without running it. ``mechanisms/slotting_machine.yaml`` builds its links from the
time ratio K and the stroke H, so the ram's time ratio is K and its stroke is H: their
derivatives are 1 and 0.001 m/mm, every other one of theirs 0, their ends at p ± t those
of K and H, their linearised σ t/3 of K and of H, and the sample's σ within a χ² bound of
it.  Whether the block is current (the script run again) is a slow check."""

from __future__ import annotations

import re

import pytest

from tests.helpers import ROOT, load_script, same_lines

PAGE = ROOT / "docs" / "sensitivity.md"
SCRIPT = ROOT / "docs" / "scripts" / "sensitivity_example.py"
BLOCK = re.compile(
    r"<!-- BEGIN slotting-sensitivity -->\n(.*?)\n?<!-- END slotting-sensitivity -->", re.S
)


def _block() -> str:
    return BLOCK.search(PAGE.read_text(encoding="utf-8")).group(1)


def _derivatives(block: str) -> dict[tuple[str, str], tuple[float, float, float, float]]:
    """(quantity, parameter) → (dQ/dp, error, Q(p − t), Q(p + t)) of the block's table."""
    out, quantity = {}, None
    for line in block.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 7 or not cells[2].startswith("`"):
            continue
        quantity = cells[0].strip("`") or quantity
        out[quantity, cells[2].strip("`")] = tuple(float(c) for c in cells[3:7])
    return out


def _spreads(block: str) -> dict[str, tuple[float, ...]]:
    """quantity → (mean, sd, linearised sd, 0.135 %, 50 %, 99.865 %)."""
    out = {}
    for line in block.split("Monte Carlo:")[1].splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[0].startswith("`"):
            out[cells[0].strip("`")] = tuple(float(c) for c in cells[1:])
    return out


def test_the_time_ratio_is_k_and_the_stroke_is_h():
    d = _derivatives(_block())
    assert len(d) == 16
    for (q, p), (value, error, *_) in d.items():
        if q not in ("guide.time_ratio", "guide.stroke"):
            continue
        want = {("guide.time_ratio", "K"): 1.0, ("guide.stroke", "H"): 0.001}.get((q, p), 0.0)
        # the block's 8 digits, and within a few of its own error estimates
        assert abs(value - want) <= 5e-8 * abs(want) + 4 * error, (q, p)
    assert d["guide.time_ratio", "K"][2:] == pytest.approx((1.98, 2.02), rel=1e-9)  # K = 2 ± 1 %
    assert d["guide.stroke", "H"][2:] == pytest.approx((0.0995, 0.1005), rel=1e-9)  # H = 100 ± 0.5


def test_the_monte_carlo_spreads_are_the_tolerances_of_k_and_h():
    from scipy.stats import chi2

    sp = _spreads(_block())
    n = 1000
    for q, sigma in (("guide.time_ratio", 0.02 / 3), ("guide.stroke", 0.5e-3 / 3)):
        mean, sd, linear, p_lo, median, p_hi = sp[q]
        assert linear == pytest.approx(sigma, rel=1e-3)  # the block's 4 digits
        ratio = (n - 1) * sd**2 / sigma**2
        assert chi2.ppf(0.0005, n - 1) < ratio < chi2.ppf(0.9995, n - 1), q
        assert p_lo < median < p_hi
    block = _block()
    counts = [int(c) for c in re.findall(r": (\d+) of 1000 designs outside", block)]
    lost = int(re.search(r"outside some limit or failed: (\d+) of 1000", block).group(1))
    assert max(counts) <= lost <= sum(counts)


def test_the_block_comparison_holds_the_numbers_to_their_line():
    """The comparison of the slow check below: round-off moves pass, a digit does not."""
    line = "| `guide.time_ratio` | 2 | `K` | 1 | 4.4e-11 | 1.98 | 2.02 |"
    same_lines(line.replace("4.4e-11", "1.8e-09"), line)
    with pytest.raises(AssertionError):
        same_lines(line.replace("2.02", "2.03"), line)
    with pytest.raises(AssertionError):
        same_lines(line.replace("`K`", "`H`"), line)


@pytest.mark.slow
def test_the_block_is_the_scripts():
    same_lines(load_script(SCRIPT).doc_block(), _block())
