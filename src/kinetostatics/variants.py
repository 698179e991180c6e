"""Variants of one mechanism: the same YAML with other parameter values.

A :class:`Template` reads and checks a file once; :meth:`Template.model`
builds the model of a variant (a mapping of parameter overrides, in the
file's units).  :func:`analyze_variants` analyses many variants and returns
one summary row each (:func:`summary_row`): a variant that fails is a row
with its reason, never an exception.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

from . import yaml_io
from .errors import KinetostaticsError
from .joints import Prismatic
from .model import Model

__all__ = ["Template", "analyze_variants", "summary_row", "ROW_UNITS"]


@dataclass(frozen=True, eq=False)
class Template:
    """A mechanism file read once, to build many variants from."""

    tree: Any                      # yaml_io.Entry of the checked file
    base: Model                    # the file as written

    @classmethod
    def load(cls, path: str | Path) -> "Template":
        text = Path(path).read_text(encoding="utf-8") if Path(path).is_file() else None
        if text is None:
            yaml_io.load(path)                      # raises the loader's message
        tree = yaml_io.compose(text, str(path))
        return cls(tree, yaml_io.build(tree))

    @classmethod
    def loads(cls, text: str, file: str = "<string>") -> "Template":
        tree = yaml_io.compose(text, file)
        return cls(tree, yaml_io.build(tree))

    @property
    def parameters(self) -> dict[str, float]:
        """The file's parameters with their values (file units)."""
        return dict(self.base.parameters)

    def model(self, overrides: Mapping[str, float] | None = None, *,
              positions: int | None = None) -> Model:
        """The variant's model (``ModelError`` if those values make it invalid);
        ``positions`` replaces ``analysis.positions``."""
        model = yaml_io.build(self.tree, overrides) if overrides else self.base
        if positions is not None:
            model = replace(model, analysis=replace(model.analysis, positions=int(positions),
                                                    at=()))
        return model


# -- summary rows ----------------------------------------------------------------------
ROW_UNITS = {
    "stroke": "m", "time_ratio": "1", "v_peak": "m/s", "a_peak": "m/s^2",
    "omega_peak": "rad/s", "alpha_peak": "rad/s^2", "reaction_peak": "N",
    "reaction_peak_friction": "N", "efficiency_min": "1", "efficiency_cycle": "1", "self_locking": "deg",
    "self_locking_positions": "1", "pressure_angle_max": "deg",
    "transmission_angle_min": "deg", "inertia": "kg*m^2", "inertia_net": "kg*m^2",
}


def _outputs(system) -> list[tuple[str, str, int]]:
    """The output members: undriven prismatic pairs (kind "slide") or, when there
    are none, the last group's last link (kind "link")."""
    driven = {d.joint.name for d in system.motion_drivers}
    slides = [("slide", j.name, k) for k, j in enumerate(system.model.joints)
              if isinstance(j, Prismatic) and j.name not in driven]
    if slides:
        return slides
    link = system.plans[-1].group.links[-1]
    return [("link", link, system.link_index(link))]


def _ranges(angle: np.ndarray, mask: np.ndarray) -> str:
    """Runs of consecutive positions where ``mask`` holds, as 'a–b; c–d' in deg."""
    if not mask.any():
        return ""
    idx = np.nonzero(mask)[0]
    breaks = np.nonzero(np.diff(idx) > 1)[0]
    starts = np.concatenate(([idx[0]], idx[breaks + 1]))
    ends = np.concatenate((idx[breaks], [idx[-1]]))
    return "; ".join(f"{angle[a]:.4g}–{angle[b]:.4g}" for a, b in zip(starts, ends))


def summary_row(result, flywheel: bool | None = None) -> dict[str, Any]:
    """The batch row of one analysed variant (names ``<member>.<quantity>``,
    units :data:`ROW_UNITS`): strokes and time ratios of the outputs, peak
    output speed and acceleration, peak and RMS driving effort without and
    with friction, minimum efficiency, self-locking ranges, peak reaction per
    joint, worst pressure/transmission angle, flywheel inertia when asked."""
    from .summary import output_strokes
    system = result.system
    cols = result.columns
    row: dict[str, Any] = {"status": "ok", "reason": "",
                           "full_cycle": bool(result.full_cycle)}
    strokes = output_strokes(result)
    for kind, name, k in _outputs(system):
        if kind == "slide":
            s = strokes.get(name, {})
            row[f"{name}.stroke"] = s.get("stroke", np.nan)
            row[f"{name}.time_ratio"] = s.get("time_ratio", np.nan)
            from .system import coordinate_gradient
            g = coordinate_gradient(system, result.q, k)
            v = np.einsum("...n,...n->...", g, result.qd)
            from .summary import _bias
            a = np.einsum("...n,...n->...", g, result.qdd) + _bias(system, result.q, result.qd, k)
            row[f"{name}.v_peak"] = float(np.max(np.abs(v)))
            row[f"{name}.a_peak"] = float(np.max(np.abs(a)))
        else:
            row[f"{name}.omega_peak"] = float(np.max(np.abs(cols[f"{name}.omega"])))
            row[f"{name}.alpha_peak"] = float(np.max(np.abs(cols[f"{name}.alpha"])))
    angle = cols["angle"] if "angle" in cols else cols["stroke"]
    for d in system.motion_drivers:
        word = "torque" if d.joint.angular else "force"
        key = f"{d.name}.{word}"
        for suffix in ("", "_friction_approx", "_friction"):
            if key + suffix in cols:
                arr = cols[key + suffix]
                row[f"{key}{suffix}_peak"] = float(np.nanmax(np.abs(arr)))
                row[f"{key}{suffix}_rms"] = float(np.sqrt(np.nanmean(arr * arr)))
        if key + "_friction" in cols:
            # the driving phase: both efforts drive in the sense of motion
            tau, tau_f = cols[key], cols[key + "_friction"]
            sense = np.sign(d.driver.motion.speed)
            driving = (tau * sense > 0) & (tau_f * sense > 0)
            row[f"{d.name}.efficiency_min"] = float(np.min(tau[driving] / tau_f[driving])) \
                if driving.any() else np.nan
            w_in, w_in_f = np.sum(tau) * sense, np.nansum(tau_f) * sense
            row[f"{d.name}.efficiency_cycle"] = float(w_in / w_in_f) if w_in_f > 0 else np.nan
    if "friction.status" in cols:
        locked = cols["friction.status"] == 2
        row["friction.self_locking_positions"] = int(np.count_nonzero(locked))
        row["friction.self_locking"] = _ranges(angle, locked)
    for j in system.model.joints:
        if f"{j.name}.Fx" not in cols:
            continue
        row[f"{j.name}.reaction_peak"] = float(np.max(np.hypot(cols[f"{j.name}.Fx"],
                                                               cols[f"{j.name}.Fy"])))
        if f"{j.name}.Fx_friction" in cols:
            magf = np.hypot(cols[f"{j.name}.Fx_friction"], cols[f"{j.name}.Fy_friction"])
            row[f"{j.name}.reaction_peak_friction"] = float(np.nanmax(magf)) \
                if np.isfinite(magf).any() else np.nan
    for name in cols:
        if name.endswith(".pressure_angle"):
            row[name + "_max"] = float(np.max(cols[name]))
        elif name.endswith(".transmission_angle"):
            row[name + "_min"] = float(np.min(np.minimum(cols[name], 180.0 - cols[name])))
    if flywheel or (flywheel is None and getattr(system.model, "flywheel", None) is not None):
        from .flywheel import design
        fw = design(result)
        row["flywheel.inertia"], row["flywheel.inertia_net"] = fw.inertia, fw.inertia_net
    return row


def failure_row(exc: BaseException) -> dict[str, Any]:
    """The row of a variant that could not be analysed: its reason, in one line."""
    reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    row: dict[str, Any] = {"status": "failed", "reason": reason, "full_cycle": False}
    for attr in ("group", "coordinate"):
        if getattr(exc, attr, None) is not None:
            row[f"failed.{attr}"] = str(getattr(exc, attr))
    return row


def analyze_variants(template: Template, overrides: Iterable[Mapping[str, float]], *,
                     positions: int | None = None, friction: bool | None = None,
                     flywheel: bool | None = None) -> list[dict[str, Any]]:
    """One :func:`summary_row` per variant, in order; failures are rows with their reason.

    ``positions`` replaces the file's number of positions; ``friction``
    (default: as the file) solves the friction solutions; ``flywheel``
    (default: when the file asks) adds the flywheel inertia."""
    from .analysis import analyze
    rows = []
    for ov in overrides:
        try:
            result = analyze(template.model(ov, positions=positions), friction=friction)
            rows.append(summary_row(result, flywheel=flywheel))
        except (KinetostaticsError, ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
            rows.append(failure_row(exc))
    return rows
