"""A row does not depend on which other rows an analysis asks for.

For every shipped mechanism that ``analyze`` can run (motion drivers equal to the
mobility), the rows of a full-cycle run are compared with the same positions
analysed as a random subset (``positions=``), from another ``start`` over a short
``sweep``, as ``at:`` rows, and with ``events: true`` added: every column must agree
to 1e-9 of its scale over the cycle.  Loads switched by a ``travel`` band (the
slotting machine's cutting force) make this fail when the band's extreme is looked
for among the analysed rows only.
"""

from dataclasses import replace

import numpy as np
import pytest

import kinetostatics as ks
from tests.helpers import MECHANISMS

N = 72  # positions of the reference run (5° steps)
RTOL = 1e-9
SKIP = ("time", "travel", "friction.iterations")  # run-relative or solver bookkeeping


def _analysable(path):
    system = ks.build_system(ks.load(path))
    return len(system.motion_drivers) == system.structure.mobility


CASES = [p for p in MECHANISMS if _analysable(p)]


def _model(path, **analysis):
    model = ks.load(path)
    base = dict(sweep=2 * np.pi, positions=N, at=(), events=False)
    base.update(analysis)
    return replace(model, analysis=replace(model.analysis, **base))


def _compare(ref, rows, other, other_rows, scale, what):
    assert set(other.columns) == set(ref.columns), what
    for name in ref.columns:
        if name in SKIP:
            continue
        a, b = np.asarray(ref[name])[rows], np.asarray(other[name])[other_rows]
        if name.endswith(".theta") or name == "angle":  # unwrapped along each run
            d = (a - b + 180.0) % 360.0 - 180.0
        else:
            d = a - b
        both_nan = np.isnan(a) & np.isnan(b)
        bad = ~both_nan & ~(np.abs(d) <= RTOL * scale[name] + 1e-300)
        assert not bad.any(), (
            f"{what}: {name} differs at {np.count_nonzero(bad)} row(s), "
            f"e.g. {a[bad][0]!r} vs {b[bad][0]!r} (scale {scale[name]:.3g})"
        )


@pytest.fixture(scope="module", params=CASES, ids=[p.stem for p in CASES])
def reference(request):
    model = _model(request.param)
    ref = ks.analyze(model)
    assert ref.full_cycle
    scale = {}
    for name in ref.columns:
        col = np.asarray(ref[name], dtype=float)
        scale[name] = float(np.nanmax(np.abs(col), initial=0.0)) if np.isfinite(col).any() else 0.0
    unit = {}  # a column that stays ~0 (a fixed pivot) takes its unit's scale
    for name, s in scale.items():
        u = ref.units.get(name)
        unit[u] = max(unit.get(u, 0.0), s)
    scale = {
        name: max(
            s,
            (1.0 if name.startswith("power.residual") else 1e-6)  # a residual's
            * unit[ref.units.get(name)],
        )
        for name, s in scale.items()
    }  # scale: power's
    return request.param, model, ref, scale


def test_a_random_subset_of_positions(reference):
    path, model, ref, scale = reference
    rows = np.sort(np.random.default_rng(7).choice(N, size=7, replace=False))
    sub = ks.analyze(model, positions=ref.coordinate[rows])
    _compare(ref, rows, sub, np.arange(len(rows)), scale, "positions= subset")
    for k in rows[::2]:
        one = ks.analyze(model, positions=ref.coordinate[k : k + 1])
        _compare(ref, [k], one, [0], scale, f"the single position of row {k}")


def _sketch_at(result, k):
    """The model's sketch moved to where the run put each sketched point at row ``k`` (the
    sketch is a rough pose at ``analysis.start``: another start needs its own)."""
    from kinetostatics.kinematics.start import joint_points
    from kinetostatics.kinetics.forces import point_state

    system = result.system
    model = system.model
    moving = set(system.links)
    sketch = {}
    for key, pos in model.sketch.items():
        link, dot, name = key.partition(".")
        pairs = (
            [(link, model.link(link).points[name])] if dot else list(joint_points(model.joint(key)))
        )
        pairs = [(n, p) for n, p in pairs if n in moving]
        if not pairs:
            sketch[key] = pos
            continue
        n, p = pairs[0]
        sketch[key] = point_state(result.q[k], result.q[k], None, system.link_index(n), p)[0]
    return sketch


def test_another_start_and_a_short_sweep(reference):
    path, model, ref, scale = reference
    k0, n = 41, 6
    step = 2 * np.pi / N
    short = ks.analyze(
        replace(
            model,
            sketch=_sketch_at(ref, k0),
            analysis=replace(
                model.analysis, start=float(ref.coordinate[k0]), sweep=n * step, positions=n
            ),
        )
    )
    _compare(ref, (k0 + np.arange(n)) % N, short, np.arange(n), scale, "start/sweep")


def test_at_rows_and_event_rows(reference):
    path, model, ref, scale = reference
    rng = np.random.default_rng(11)
    at = tuple(float(a) for a in rng.uniform(0.0, 2 * np.pi, 3))
    extra = replace(model, analysis=replace(model.analysis, at=at, events=True))
    run = ks.analyze(extra)
    grid = np.isin(run.t, ref.t)
    assert np.count_nonzero(grid) == N
    _compare(ref, np.arange(N), run, np.nonzero(grid)[0], scale, "grid rows with at/events")
    alone = ks.analyze(model, positions=np.array(at))
    mine = [int(np.argmin(np.abs(run.t - t))) for t in alone.t]
    _compare(alone, np.arange(len(at)), run, mine, scale, "at rows")
    if run.events:
        coords = np.array([e.coordinate for e in run.events])
        ev = ks.analyze(model, positions=coords)
        mine = [int(np.argmin(np.abs(run.t - e.t))) for e in run.events]
        _compare(ev, np.arange(len(coords)), run, mine, scale, "event rows")


def test_events_of_a_partial_run_are_the_full_cycle_events_within_it(reference):
    """Sparse rows (here 4 rows 100° apart) find the same switches as the full cycle
    between their first and last row, not only those the rows happen to bracket (two
    switches of one condition between two rows cancel in a sign test)."""
    path, model, ref, scale = reference
    full = ks.analyze(model, events=True)
    period = 2 * np.pi / abs(model.drivers[0].motion.speed)
    rows = np.array([0, 20, 40, 60])
    part = ks.analyze(model, positions=ref.coordinate[rows], events=True)
    lo, hi = ref.t[rows[0]], ref.t[rows[-1]]
    want = [(e.load, e.condition, e.switch, e.t) for e in full.events if lo <= e.t <= hi]
    got = [(e.load, e.condition, e.switch, e.t) for e in part.events]
    assert [w[:3] for w in want] == [g[:3] for g in got]
    np.testing.assert_allclose(
        [g[3] for g in got], [w[3] for w in want], rtol=0, atol=1e-9 * period
    )


def test_a_start_moved_away_from_the_sketch_keeps_the_sketched_branch(reference):
    """``analysis.start`` moved with the sketch left where it was (a user changing only the
    start): the linkage is assembled at the sketched pose and carried along its branch, so
    the rows are the full cycle's rows at those angles."""
    path, model, ref, scale = reference
    k0, n = 41, 4
    step = 2 * np.pi / N
    moved = ks.analyze(
        replace(
            model,
            analysis=replace(
                model.analysis, start=float(ref.coordinate[k0]), sweep=n * step, positions=n
            ),
        )
    )
    _compare(ref, (k0 + np.arange(n)) % N, moved, np.arange(n), scale, "moved start")


def test_the_mirrored_pin_is_refused_whatever_the_start(root):
    """The sketch check is not bypassed by moving the start: the mirrored jaw crusher
    (one revolute of its three-link pin unsketched) is refused at any start."""
    model = ks.load(root / "tests" / "hard" / "jaw_crusher_mirrored.yaml")
    for start in (90.0, 200.0):
        with pytest.raises(ks.ModelError, match="sketch.C: C is assembled"):
            ks.analyze(
                replace(model, analysis=replace(model.analysis, start=np.radians(start))),
                friction=False,
            )
