"""The branch a run follows does not depend on where its rows fall.

Change points (a dyad's two assemblies meet: the four-bar's pivots collinear)
must be crossed on the C¹ branch and reported wherever the rows are; a
near-toggle that never becomes singular must keep its branch.  Truth: the
closed forms of the four-bar (triangle geometry, the side of the line AD
changing at every crank angle 180° mod 360°, where the change-point four-bar's
coupler and rocker are stretched; the parallelogram stays a parallelogram) and
of the offset slider-crank (sin φ2 = (e − a sin φ1)/b, x_B = a cos φ1 + b cos φ2,
cos φ2 > 0 on the sketched branch).
"""

import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.kinematics import positions

CHANGE_POINT = "tests/hard/fourbar_change_point.yaml"


@pytest.fixture(params=["fast", "general"])
def path(request, monkeypatch):
    """Both position paths: the closed forms (fast) and Newton with continuation
    (general, the closed forms switched off)."""
    if request.param == "general":
        monkeypatch.setattr(positions, "closed_form_solvers", lambda system, drive: None)
    return request.param


GRIDS = [(24, 360), (360, 360), (361, 360), (720, 720)]  # (positions, sweep)
RNG = np.random.default_rng(20261123)
TIMES = np.sort(RNG.uniform(-0.8, 1.3, 37))  # 60 rpm: ψ = 90° + 360°·t


def _grid(text: str, n: int, sweep: int) -> str:
    return text.replace("sweep: 360, positions: 360", f"sweep: {sweep}, positions: {n}")


def _change_point_text() -> str:
    return open(CHANGE_POINT).read()


def _parallelogram_text() -> str:
    """Crank = rocker = 1, coupler = ground = 3 (as the sketch variants of
    test_hard_cases.py, by editing the file): change points at 0° and 180°."""
    return (
        _change_point_text()
        .replace("B: [2.5, 0]}, com: [1.25, 0]", "B: [3, 0]}, com: [1.5, 0]")
        .replace("B: [1.5, 0]}, com: [0.75, 0]", "B: [1, 0]}, com: [0.5, 0]")
        .replace("B: [2.46, 1.4]", "B: [3, 1]")
    )


def _fourbar_b(phi_deg, coupler=2.5, rocker=1.5, ground=3.0):
    """B of the change-point four-bar on the C¹ branch through the start at 90°
    (B above AD there): the side of AD changes at every 180° mod 360°."""
    phi = np.radians(phi_deg)
    a = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    d_pt = np.array([ground, 0.0])
    dv = a - d_pt
    d = np.hypot(dv[:, 0], dv[:, 1])
    e = dv / d[:, None]
    n = np.stack([-e[:, 1], e[:, 0]], axis=-1)
    x = (rocker**2 - coupler**2 + d * d) / (2 * d)
    h = np.sqrt(np.maximum(rocker**2 - x * x, 0.0))
    passes = np.floor((phi_deg - 180.0) / 360.0) - np.floor((90.0 - 180.0) / 360.0)
    side = np.where(passes % 2 == 0, -1.0, 1.0)  # at 90°: B left of D→A, i.e. above AD
    return d_pt + x[:, None] * e + (side * h)[:, None] * n


def _crossings(lo_deg, hi_deg, at=(180.0,)):
    """The crank angles in [lo, hi] congruent to one of ``at`` mod 360°."""
    out = [c + 360.0 * k for c in at for k in range(-3, 4)]
    return sorted(c for c in out if lo_deg <= c <= hi_deg)


def _runs(text, start=90.0, rpm=60.0, grids=GRIDS):
    """(label, crank angle of each row in degrees, result) for the grids, for
    random times (before and after the start) and for random crank angles."""
    model = ks.loads(text, file="grid.yaml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ks.NearSingularWarning)
        for n, sweep in grids:
            r = ks.analyze(ks.loads(_grid(text, n, sweep), file="grid.yaml"), kinematics_only=True)
            yield f"{n} positions over {sweep}°", start + r["travel"], r
        times = TIMES * 60.0 / rpm
        yield (
            "random times",
            start + 6.0 * rpm * times,
            ks.analyze(model, times=times, kinematics_only=True),
        )
        angles = RNG.uniform(0.0, 360.0, 29)  # taken in [start, start + 360°)
        r = ks.analyze(model, positions=np.radians(angles), kinematics_only=True)
        yield "random angles", start + np.mod(angles - start, 360.0), r


@pytest.mark.parametrize("which", ["change point", "parallelogram"])
def test_four_bar_follows_the_c1_branch_and_reports_the_same_change_points_on_every_grid(
    which, path
):
    parallelogram = which == "parallelogram"
    text, at = (
        (_parallelogram_text(), (0.0, 180.0)) if parallelogram else (_change_point_text(), (180.0,))
    )
    for label, phi, r in _runs(text):
        p1 = np.radians(phi)
        b = (
            np.stack([3.0 + np.cos(p1), np.sin(p1)], axis=-1)
            if parallelogram  # B = D + (A − O)
            else _fourbar_b(phi)
        )
        err = max(
            np.max(np.abs(r["rocker.B.x"] - b[:, 0])), np.max(np.abs(r["rocker.B.y"] - b[:, 1]))
        )
        assert err < 1e-9, (label, err)
        if parallelogram:
            assert np.max(np.abs(r["rocker.theta"] - r["crank.theta"])) < 1e-9, label
        expected = _crossings(min(phi.min(), 90.0), max(phi.max(), 90.0), at)
        found = [np.degrees(s.coordinate) for s in r.singular]
        assert [s.group for s in r.singular] == ["RRR dyad {coupler, rocker}"] * len(expected), (
            label
        )
        np.testing.assert_allclose(found, expected, atol=1e-6, err_msg=label)
        assert all(s.condition > 1e8 for s in r.singular), label


def test_change_point_between_rows_gives_the_rows_of_the_grid_that_hits_it(path):
    """361 positions step over 180°; its rows agree with the 360-position run's
    C¹ path at the same angles (interpolated in closed form above) and with a run
    at exactly those angles."""
    text = _change_point_text()
    r361 = ks.analyze(ks.loads(_grid(text, 361, 360), file="g.yaml"))
    k = int(np.argmin(np.abs(r361["angle"] - 269.5)))
    single = ks.analyze(ks.loads(text, file="g.yaml"), positions=[np.radians(r361["angle"][k])])
    assert single["rocker.theta"][0] == pytest.approx(r361["rocker.theta"][k], abs=1e-9)
    b = _fourbar_b(np.array([90.0 + r361["travel"][k]]))
    assert np.degrees(np.arctan2(b[0, 1], b[0, 0] - 3.0)) % 360 == pytest.approx(
        r361["rocker.theta"][k] % 360, abs=1e-9
    )
    assert len(r361.singular) == 1 and len(single.singular) == 1


SLIDER_CRANK = "mechanisms/slider_crank.yaml"


def _near_toggle_text() -> str:
    """Rod 1e-5 mm longer than crank + |offset|: cos φ2 = 4.1e-4 at 90°, never 0."""
    return open(SLIDER_CRANK).read().replace("b: 350", "b: 120.00001").replace("r2: 120", "r2: 60")


def test_near_toggle_slider_crank_keeps_its_branch_on_every_grid(path):
    a, b, e = 0.1, 0.12000001, -0.02
    grids = GRIDS if path == "fast" else [(24, 360), (361, 360)]  # Newton: slower
    for label, phi, r in _runs(_near_toggle_text(), start=0.0, rpm=300.0, grids=grids):
        p1 = np.radians(phi)
        s2 = (e - a * np.sin(p1)) / b
        x_b = a * np.cos(p1) + b * np.sqrt(1.0 - s2 * s2)
        assert r.singular == (), label
        err = np.max(np.abs(r["slider.x"] - x_b)) / np.max(np.abs(x_b))
        assert err < 1e-9, (label, err)
        y_rod = r["rod.y"] - a * np.sin(p1)  # centre of mass 60 mm along the rod
        assert np.max(np.abs(y_rod - 0.06 * s2)) < 1e-12, label


def test_near_toggle_as_shipped_start_is_exact_at_every_row(path):
    """The file as shipped (start 0°, 360 positions): 90° is a row; no singular
    position and the slider on the closed form at every row."""
    a, b, e = 0.1, 0.12000001, -0.02
    r = ks.analyze(ks.loads(_near_toggle_text(), file="sc.yaml"), friction=False)
    p1 = np.radians(r["angle"])
    s2 = (e - a * np.sin(p1)) / b
    x_b = a * np.cos(p1) + b * np.sqrt(1.0 - s2 * s2)
    assert r.singular == ()
    assert np.max(np.abs(r["slider.x"] - x_b)) / np.max(np.abs(x_b)) < 1e-9
    cond = r["rod_slider.cond"]
    assert r["angle"][np.argmax(cond)] == pytest.approx(90.0)
