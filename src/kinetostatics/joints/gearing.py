"""The tooth data of a toothed pair (:class:`GearData`): what a gear or rack pair tells the
gear chapter (``methods/gears.py``) through the joint contract (``Presentation.gear_data``),
so that the chapter never asks a joint for its class.

The values are the file's, in SI: pitch radii in m, the pressure angle in rad; the
addendum and clearance coefficients h_a*, c* and the profile shifts x are dimensionless
(multiples of the module).  Each entry of ``teeth``, ``radii`` and ``shift`` belongs to the
link of the same place in ``links`` (link i, link j); a rack's own entries are ``None`` (its
radius is infinite), and so is a pinion's number of teeth when the file gives only its
radius.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["MESH_KINDS", "GearData"]

MESH_KINDS = ("external", "internal", "rack")


@dataclass(frozen=True)
class GearData:
    """The tooth data of one toothed pair.

    Parameters
    ----------
    joint : str
        The pair's name.
    mesh : str
        ``"external"``, ``"internal"`` (the larger gear is the annulus) or ``"rack"``.
    links : tuple of str
        (link i, link j) as in the joint; a rack pair's link i is the rack.
    teeth : tuple of int or None
        The numbers of teeth; ``None`` for the rack, or a pinion given by its radius only.
    radii : tuple of float or None
        The pitch radii, m; ``None`` for the rack.
    alpha : float
        The pressure angle of the reference profile, rad.
    addendum, clearance : float
        The addendum coefficient h_a* and the clearance coefficient c*.
    shift : tuple of float
        The profile shift coefficients x (0 for the rack).
    """

    joint: str
    mesh: str
    links: tuple[str, str]
    teeth: tuple[int | None, int | None]
    radii: tuple[float | None, float | None]
    alpha: float
    addendum: float = 1.0
    clearance: float = 0.25
    shift: tuple[float, float] = (0.0, 0.0)
