"""Variants of one mechanism: the same YAML with other parameter values.

A :class:`Template` reads and checks a file once; :meth:`Template.model`
builds the model of a variant (a mapping of parameter overrides, in the
file's units).  :func:`analyze_variants` analyses many variants and returns
one summary row each (:func:`summary_row`): a variant that fails is a row
with its reason, never an exception.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..analysis.locking import locking_zones
from ..base.arrays import runs
from ..base.document import compose, read_text
from ..dynamics.flywheel import design
from ..errors import KinetostaticsError
from ..kinematics.events import coordinate_rates, output_slides, output_strokes
from ..kinetics.reactions import effort_joints
from ..model import Model
from ..model.stacking import TopologyMismatch, signature, stack
from ..outputs.loading import build
from ..structure.system import coordinate_rate

__all__ = [
    "Template",
    "analyze_variants",
    "summary_row",
    "shaking_row",
    "ROW_UNITS",
    "RowNeeds",
    "row_needs",
]


@dataclass(frozen=True, eq=False)
class Template:
    """A mechanism file read once, to build many variants from."""

    tree: Any  # base.spec.Entry of the checked file
    base: Model  # the file as written

    @classmethod
    def load(cls, path: str | Path) -> Template:
        tree = compose(read_text(path), str(path))
        return cls(tree, build(tree))

    @classmethod
    def loads(cls, text: str, file: str = "<string>") -> Template:
        tree = compose(text, file)
        return cls(tree, build(tree))

    @property
    def parameters(self) -> dict[str, float]:
        """The file's parameters with their values (file units)."""
        return dict(self.base.parameters)

    def model(
        self, overrides: Mapping[str, float] | None = None, *, positions: int | None = None
    ) -> Model:
        """The variant's model (``ModelError`` if those values make it invalid);
        ``positions`` replaces ``analysis.positions``."""
        model = build(self.tree, overrides) if overrides else self.base
        if positions is not None:
            model = replace(
                model, analysis=replace(model.analysis, positions=int(positions), at=())
            )
        return model


# -- summary rows ---------------------------------------------------------------------
@dataclass(frozen=True)
class Quantity:
    """One quantity of a batch row, ``<member>.<name>``: its unit, whether it is a
    magnitude (never negative: a peak of |x|, an RMS, a stroke, a folded angle) or a
    signed value, and how it is computed from the run's columns (docs/batch.md lists
    them all from this table)."""

    unit: str
    sense: str  # "magnitude", "signed", "count" or "text"
    meaning: str


def _efforts() -> dict[str, Quantity]:
    out = {}
    for word, unit in (("torque", "N*m"), ("force", "N")):
        for suffix, what in (
            ("", "frictionless"),
            ("_friction_approx", "approximate friction solution"),
            ("_friction", "consistent friction solution"),
        ):
            column = f"`<driver>.{word}{suffix}`"
            out[f"<driver>.{word}{suffix}_peak"] = Quantity(
                unit, "magnitude", f"max |{column}| ({what})"
            )
            out[f"<driver>.{word}{suffix}_rms"] = Quantity(
                unit, "magnitude", f"√(mean of {column}²) ({what})"
            )
    return out


# The one table of a row's quantities, ``<member>.<quantity>`` (``<slide>``: each output
# slide; ``<link>``: the output link when there is no output slide; ``<driver>``: each
# motion driver, ``force`` for an effort at a prismatic joint; ``<joint>``: each joint;
# ``<member>``: each column ``*.pressure_angle``, of an RRP dyad or a cam joint;
# ``<dyad>``: each RRR dyad).  Every max, min and mean is over the run's rows where the
# column is finite (a singular row is NaN); a variant without a finite row gives NaN.
QUANTITIES: dict[str, Quantity] = {
    "<slide>.stroke": Quantity(
        "m",
        "magnitude",
        "largest − least slide coordinate between the slide's two exact stops (summary.json "
        "`outputs.<slide>.stroke`); empty when it does not stop exactly twice per cycle",
    ),
    "<slide>.time_ratio": Quantity(
        "1",
        "magnitude",
        "the slower stroke's time over the faster's (≥ 1; summary.json "
        "`outputs.<slide>.time_ratio`); empty as the stroke",
    ),
    "<slide>.v_peak": Quantity(
        "m/s", "magnitude", "max |sliding speed| of the slide (its coordinate's rate)"
    ),
    "<slide>.a_peak": Quantity("m/s^2", "magnitude", "max |its coordinate's second rate|"),
    "<link>.omega_peak": Quantity("rad/s", "magnitude", "max |`<link>.omega`|"),
    "<link>.alpha_peak": Quantity("rad/s^2", "magnitude", "max |`<link>.alpha`|"),
    **_efforts(),
    "<driver>.efficiency_min": Quantity(
        "1",
        "signed",
        "min of `<driver>.efficiency` (0 ≤ η ≤ 1 where defined: docs/friction.md); "
        "empty when it is defined nowhere",
    ),
    "<driver>.efficiency_cycle": Quantity(
        "1",
        "signed",
        "Σ τ·ċ / Σ τ_friction·ċ over the rows where both efforts are finite (ċ the relative "
        "speed of the joint that carries the effort); empty when the denominator is not > 0",
    ),
    "friction.self_locking_positions": Quantity("1", "count", "rows with `friction.status` = 2"),
    "friction.self_locking": Quantity(
        "deg",
        "text",
        "the self-locked zones of summary.json `self_locking` with their located edges, "
        "`from–to; …` in the driver coordinate",
    ),
    "<joint>.reaction_peak": Quantity(
        "N", "magnitude", "max |(`<joint>.Fx`, `<joint>.Fy`)| (frictionless reaction)"
    ),
    "<joint>.reaction_peak_friction": Quantity(
        "N", "magnitude", "max |(`<joint>.Fx_friction`, `<joint>.Fy_friction`)|"
    ),
    "<member>.pressure_angle_max": Quantity(
        "deg",
        "magnitude",
        "max |`<member>.pressure_angle`| (an RRP dyad's column is 0–90°; a cam's is "
        "signed: its worst angle is the largest magnitude, on the rise or the return)",
    ),
    "<dyad>.transmission_angle_min": Quantity(
        "deg",
        "magnitude",
        "min of min(μ, 180° − μ), μ = `<dyad>.transmission_angle` (0–90°)",
    ),
    "shaking.force_peak": Quantity("N", "magnitude", "max |(`shaking.Fx`, `shaking.Fy`)|"),
    "shaking.force_rms": Quantity("N", "magnitude", "√(mean of `shaking.Fx`² + `shaking.Fy`²)"),
    "shaking.moment_peak": Quantity("N*m", "magnitude", "max |`shaking.M`|"),
    "shaking.moment_rms": Quantity("N*m", "magnitude", "√(mean of `shaking.M`²)"),
    "flywheel.inertia": Quantity(
        "kg*m^2", "magnitude", "J_F of the flywheel's design (docs/dynamics.md)"
    ),
    "flywheel.inertia_net": Quantity(
        "kg*m^2", "signed", "J_F − J_e,mean: less the machine's own mean inertia"
    ),
}
# the unit of a row's column by its last name part (one unit per part)
ROW_UNITS = {name.rpartition(".")[2]: q.unit for name, q in QUANTITIES.items()}


@dataclass(frozen=True)
class RowNeeds:
    """The costly parts of a row that its reader needs: the friction solutions (every
    quantity with friction, the efficiencies, the self-locking), the outputs' strokes and
    time ratios (a Newton on time per slide) and the self-locked zones' located edges
    (the friction solution at each edge).  A part not needed is not computed: its
    quantities are absent from the row (friction, zones) or empty (strokes).  ``parts``:
    the groups of the row's quantities (:data:`ROW_PARTS`) to reduce from the columns,
    None for all; a group left out is absent from the row."""

    friction: bool = True
    strokes: bool = True
    zones: bool = True
    parts: frozenset[str] | None = None


# the groups of a row's quantities, each with the words of its names (a name with one of
# them belongs to it: on the safe side, a name may belong to several)
ROW_PARTS: dict[str, tuple[str, ...]] = {
    "outputs": (".stroke", ".time_ratio", ".v_peak", ".a_peak", ".omega_peak", ".alpha_peak"),
    "efforts": ("torque", "force", "efficiency"),
    "locking": ("self_locking",),
    "reactions": ("reaction",),
    "shaking": ("shaking",),
    "angles": ("angle",),
}


def row_needs(names: Iterable[str] | None) -> RowNeeds:
    """What the quantities ``names`` read (None: the whole row).  By the names' words, on
    the safe side: a name with ``friction`` or ``efficiency`` in it needs the friction
    solutions, one ending ``.stroke`` or ``.time_ratio`` the strokes,
    ``friction.self_locking`` the zones, and a name with a word of a group of
    :data:`ROW_PARTS` that group (a parameter's name that reads so only costs time).

    >>> row_needs(["motor.torque_rms", "a"])
    RowNeeds(friction=False, strokes=False, zones=False, parts=frozenset({'efforts'}))
    >>> row_needs(["motor.torque_friction_rms", "slide.stroke"]).parts == {"efforts", "outputs"}
    True
    """
    if names is None:
        return RowNeeds()
    names = list(names)
    return RowNeeds(
        friction=any("friction" in n or "efficiency" in n for n in names),
        strokes=any(n.endswith((".stroke", ".time_ratio")) for n in names),
        zones="friction.self_locking" in names,
        parts=frozenset(
            part for part, words in ROW_PARTS.items() for n in names if any(w in n for w in words)
        ),
    )


def _finite(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(x, its finite rows' mask) over the last axis."""
    x = np.asarray(x, dtype=float)
    return x, np.isfinite(x)


def peak(x: np.ndarray) -> np.ndarray:
    """Max |x| over the finite rows (last axis); NaN where there is none."""
    x, ok = _finite(x)
    with np.errstate(invalid="ignore"):
        m = np.max(np.where(ok, np.abs(x), -np.inf), axis=-1)
    return np.where(np.any(ok, axis=-1), m, np.nan)


def least(x: np.ndarray) -> np.ndarray:
    """Min of x over the finite rows (last axis); NaN where there is none."""
    x, ok = _finite(x)
    m = np.min(np.where(ok, x, np.inf), axis=-1)
    return np.where(np.any(ok, axis=-1), m, np.nan)


def rms(x: np.ndarray) -> np.ndarray:
    """√(mean x²) over the finite rows (last axis); NaN where there is none."""
    x, ok = _finite(x)
    n = np.count_nonzero(ok, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, np.sqrt(np.sum(np.where(ok, x * x, 0.0), axis=-1) / n), np.nan)


def _outputs(system) -> list[tuple[str, str, int]]:
    """The output members: the output slides (kind "slide",
    :func:`~kinetostatics.kinematics.events.output_slides`) or, when there are none, the last
    group's last link (kind "link")."""
    slides = [("slide", j.name, k) for k, j in output_slides(system)]
    if slides:
        return slides
    link = system.plans[-1].group.links[-1]
    return [("link", link, system.link_index(link))]


def _ranges(angle: np.ndarray, mask: np.ndarray) -> str:
    """Runs of consecutive positions where ``mask`` holds, as 'a–b; c–d' in deg."""
    return "; ".join(f"{angle[a]:.4g}–{angle[b]:.4g}" for a, b in runs(mask))


def _zones(result) -> str:
    """The self-locked zones of one result with their located edges
    (:func:`~kinetostatics.analysis.locking.locking_zones`, summary.json ``self_locking``), as
    'a–b; c–d' (a zone wrapping past 360° is one zone, e.g. '358.516494–1.483505980'); an edge
    beyond a run that is not a full cycle is '…'."""
    text = lambda v: "…" if v is None else f"{v:.10g}"  # noqa: E731
    return "; ".join(f"{text(z['from'])}–{text(z['to'])}" for z in locking_zones(result))


def summary_row(
    result,
    flywheel: bool | None = None,
    strokes: dict | None = None,
    zones: bool = True,
    parts: frozenset[str] | None = None,
) -> dict[str, Any]:
    """The batch row of one analysed variant (names ``<member>.<quantity>``,
    units :data:`ROW_UNITS`): strokes and time ratios of the outputs, peak
    output speed and acceleration, peak and RMS driving effort without and
    with friction, minimum efficiency, self-locking ranges, peak reaction per
    joint, worst pressure/transmission angle, flywheel inertia when asked.

    Every quantity reduces over the last (positions) axis, so a stacked
    result ``(V, N)`` gives arrays ``(V,)`` (:func:`split_rows` makes rows);
    ``strokes`` are :func:`~kinetostatics.kinematics.events.output_strokes` (computed
    when not given); ``zones`` False leaves out ``friction.self_locking`` (of one
    result: its zones' located edges, a friction solution at each); ``parts``: the groups
    of :data:`ROW_PARTS` to compute (None: all; :func:`row_needs`)."""
    system = result.system
    cols = result.columns
    row: dict[str, Any] = {"status": "ok", "reason": "", "full_cycle": bool(result.full_cycle)}
    if parts is None or "outputs" in parts:
        row.update(_output_row(result, output_strokes(result) if strokes is None else strokes))
    if parts is None or "efforts" in parts:
        row.update(_effort_row(result))
    if "friction.status" in cols and (parts is None or "locking" in parts):
        row.update(_locking_row(result, zones))
    if parts is None or "reactions" in parts:
        row.update(_reaction_row(cols, system.model.joints))
    if "shaking.Fx" in cols and (parts is None or "shaking" in parts):
        row.update(shaking_row(cols))
    for name in cols if parts is None or "angles" in parts else ():
        if name.endswith(".pressure_angle"):  # a cam's is signed: its largest magnitude
            row[name + "_max"] = peak(cols[name])
        elif name.endswith(".transmission_angle"):
            row[name + "_min"] = least(np.minimum(cols[name], 180.0 - cols[name]))
    if flywheel or (flywheel is None and getattr(system.model, "flywheel", None) is not None):
        fw = design(result)
        row["flywheel.inertia"], row["flywheel.inertia_net"] = fw.inertia, fw.inertia_net
    return {
        k: (v.item() if isinstance(v, np.ndarray) and v.ndim == 0 else v) for k, v in row.items()
    }


def _output_row(result, strokes: dict) -> dict[str, Any]:
    """The outputs' quantities: a slide's stroke, time ratio and peak speed and
    acceleration; a rotating output's peak angular speed and acceleration."""
    system, cols = result.system, result.columns
    row: dict[str, Any] = {}
    for kind, name, k in _outputs(system):
        if kind == "slide":
            s = strokes.get(name, {})
            row[f"{name}.stroke"] = s.get("stroke", np.nan)
            row[f"{name}.time_ratio"] = s.get("time_ratio", np.nan)
            v, a = coordinate_rates(system, result.q, result.qd, result.qdd, k)
            row[f"{name}.v_peak"], row[f"{name}.a_peak"] = peak(v), peak(a)
        else:
            row[f"{name}.omega_peak"] = peak(cols[f"{name}.omega"])
            row[f"{name}.alpha_peak"] = peak(cols[f"{name}.alpha"])
    return row


def _effort_row(result) -> dict[str, Any]:
    """Each motion driver's effort: peak and RMS without and with friction, and with
    friction the least efficiency and the cycle's (input work without over with it)."""

    system, cols = result.system, result.columns
    row: dict[str, Any] = {}
    for d, k_eff in zip(system.motion_drivers, effort_joints(system)):
        word = "torque" if system.model.joints[k_eff].angular else "force"  # at balance_at
        key = f"{d.name}.{word}"
        for suffix in ("", "_friction_approx", "_friction"):
            if key + suffix in cols:
                row[f"{key}{suffix}_peak"] = peak(cols[key + suffix])
                row[f"{key}{suffix}_rms"] = rms(cols[key + suffix])
        if key + "_friction" in cols:
            tau, tau_f = cols[key], cols[key + "_friction"]
            # the effort's joint's relative speed (the driver's own, or balance_at's)
            rel = coordinate_rate(system, result.q, result.qd, k_eff)
            row[f"{d.name}.efficiency_min"] = least(cols[f"{d.name}.efficiency"])
            with np.errstate(divide="ignore", invalid="ignore"):
                both = np.isfinite(tau) & np.isfinite(tau_f)  # input work ∝ Σ effort·speed
                w_in = np.sum(np.where(both, tau * rel, 0.0), axis=-1)  # over the rows
                w_in_f = np.sum(np.where(both, tau_f * rel, 0.0), axis=-1)  # with both
                row[f"{d.name}.efficiency_cycle"] = np.where(w_in_f > 0, w_in / w_in_f, np.nan)
    return row


def _locking_row(result, zones: bool = True) -> dict[str, Any]:
    """The self-locked rows' count and (``zones``) their ranges of the driver's angle (or
    stroke)."""
    cols = result.columns
    angle = cols["angle"] if "angle" in cols else cols["stroke"]
    locked = cols["friction.status"] == 2
    row: dict[str, Any] = {"friction.self_locking_positions": np.count_nonzero(locked, axis=-1)}
    if zones:
        row["friction.self_locking"] = (
            _zones(result)
            if locked.ndim == 1
            else np.array([_ranges(a, m) for a, m in zip(angle, locked)], dtype=object)
        )
    return row


def _reaction_row(cols, joints) -> dict[str, Any]:
    """Each joint's peak reaction magnitude, without and with friction (NaN: singular rows)."""
    row: dict[str, Any] = {}
    for j in joints:
        if f"{j.name}.Fx" not in cols:
            continue
        row[f"{j.name}.reaction_peak"] = peak(np.hypot(cols[f"{j.name}.Fx"], cols[f"{j.name}.Fy"]))
        if f"{j.name}.Fx_friction" in cols:
            row[f"{j.name}.reaction_peak_friction"] = peak(
                np.hypot(cols[f"{j.name}.Fx_friction"], cols[f"{j.name}.Fy_friction"])
            )
    return row


def shaking_row(cols) -> dict[str, Any]:
    """Peak and RMS over the rows of the shaking force's magnitude |(Fx, Fy)| (N) and of the
    shaking moment about the ground origin (N·m), the force and moment the moving links
    exert on the frame (columns ``shaking.Fx``, ``shaking.Fy``, ``shaking.M``): rows
    ``shaking.force_peak``, ``shaking.force_rms``, ``shaking.moment_peak``,
    ``shaking.moment_rms``.  The RMS is over the analysed rows, as the driving effort's (the
    rows of a full cycle are equally spaced in time at constant speed: the cycle's RMS);
    singular rows (NaN) are left out, a variant without a finite row gives NaN."""
    out = {}
    force = np.hypot(cols["shaking.Fx"], cols["shaking.Fy"])
    for word, v in (("force", force), ("moment", cols["shaking.M"])):
        out[f"shaking.{word}_peak"], out[f"shaking.{word}_rms"] = peak(v), rms(v)
    return out


def split_rows(row: dict[str, Any], n: int) -> list[dict[str, Any]]:
    """Rows of ``n`` variants from one row of arrays ``(n,)`` (scalars repeat)."""
    out = []
    for v in range(n):
        out.append(
            {
                k: (
                    val[v].item()
                    if isinstance(val, np.ndarray) and val.dtype != object
                    else val[v]
                    if isinstance(val, np.ndarray)
                    else val
                )
                for k, val in row.items()
            }
        )
    return out


def failure_row(exc: BaseException) -> dict[str, Any]:
    """The row of a variant that could not be analysed: its reason, in one line."""
    reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    row: dict[str, Any] = {"status": "failed", "reason": reason, "full_cycle": False}
    for attr in ("group", "coordinate"):
        if getattr(exc, attr, None) is not None:
            row[f"failed.{attr}"] = str(getattr(exc, attr))
    return row


def analyze_variants(
    template: Template,
    overrides: Iterable[Mapping[str, float]],
    *,
    positions: int | None = None,
    friction: bool | None = None,
    flywheel: bool | None = None,
    vectorise: bool = True,
    needs: Iterable[str] | None = None,
) -> list[dict[str, Any]]:
    """One :func:`summary_row` per variant, in order; failures are rows with their reason.

    ``positions`` replaces the file's number of positions; ``friction``
    (default: as the file) solves the friction solutions; ``flywheel``
    (default: when the file asks) adds the flywheel inertia.  Variants are
    analysed all at once where :mod:`~kinetostatics.analysis.vectorised` can, one by
    one otherwise (``vectorise=False``: always one by one) — with the same rows.
    ``needs``: the row quantities that will be read (:func:`row_needs`; default all):
    the parts of the row none of them needs are not computed.
    """
    return _analyze_variants(
        template, overrides, positions, friction, flywheel, vectorise, needs=needs
    )[0]


def _analyze_variants(  # noqa: PLR0913  analyze_variants' keywords, positional inside the batch
    template: Template,
    overrides,
    positions=None,
    friction=None,
    flywheel=None,
    vectorise=True,
    needs=None,
) -> tuple[list[dict[str, Any]], list[dict[str, float] | None], int]:
    """(rows, parameters, alone): :func:`analyze_variants` (the same arguments), with each
    variant's parameters as its model has them (None where the model could not be built:
    the row says why) and the number of variants analysed one by one (outside the
    vectorised analysis, or left by it)."""
    overrides = list(overrides)
    need = row_needs(needs)
    if not need.friction:
        friction = False
    rows: list[dict[str, Any] | None] = [None] * len(overrides)
    models: dict[int, Model] = {}
    for v, ov in enumerate(overrides):
        try:
            models[v] = template.model(ov, positions=positions)
        except (KinetostaticsError, ValueError, ArithmeticError) as exc:
            rows[v] = failure_row(exc)
    parameters = [models[v].parameters if v in models else None for v in range(len(rows))]
    wants_flywheel = flywheel or (flywheel is None and template.base.flywheel is not None)
    if vectorise and not wants_flywheel and len(models) > 1:
        _vectorised_rows(models, rows, friction, need)
    from ..analysis.pipeline import analyze

    alone = 0
    for v, model in models.items():
        if rows[v] is not None:
            continue
        alone += 1
        try:
            result = analyze(model, friction=friction)
            strokes = None if need.strokes else {}
            rows[v] = summary_row(
                result, flywheel=flywheel, strokes=strokes, zones=need.zones, parts=need.parts
            )
        except (KinetostaticsError, ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
            rows[v] = failure_row(exc)
    return rows, parameters, alone


def _vectorised_rows(
    models: dict[int, Model], rows: list, friction: bool | None, need: RowNeeds
) -> None:
    """Fill ``rows`` of the variants the vectorised analysis takes, group by topology."""
    import warnings

    from ..analysis import vectorised

    try:  # one topology (the usual case): no signatures needed
        groups = {(): (list(models), stack(list(models.values())))}
    except TopologyMismatch:
        groups = {}
        for v, m in models.items():
            groups.setdefault(signature(m), ([], None))[0].append(v)
    for members, stacked in groups.values():
        if len(members) < 2:
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                with np.errstate(all="ignore"):
                    st = vectorised.analyze_stacked(
                        [models[v] for v in members], friction=friction, stacked=stacked
                    )
                    strokes = vectorised.output_strokes(st) if need.strokes else {}
                    row = summary_row(
                        vectorised.as_result(st),
                        flywheel=False,
                        strokes=strokes,
                        zones=need.zones,
                        parts=need.parts,
                    )
        except (
            vectorised.Unsupported,  # LeftOver included
            TopologyMismatch,
            ValueError,  # a joint's formulas that do not broadcast its stacked numbers
            TypeError,  # (docs/extending.md): the per-variant analysis takes them
            IndexError,
            ArithmeticError,
            np.linalg.LinAlgError,
        ):
            continue  # the per-variant analysis takes them, exactly
        for i, exc in st.failed.items():  # the error their own analysis raises
            rows[members[i]] = failure_row(exc)
        analysed = [members[i] for i in st.members]  # the others: one by one
        for v, ok, r in zip(analysed, st.ok, split_rows(row, len(analysed)), strict=True):
            if ok and not (need.zones and r.get("friction.self_locking_positions")):
                rows[v] = r  # a locked zone's edges: one by one
