"""What a file says for sizing its parts (docs/sizing.md): the bearings and pins of its
revolutes, the sections and materials of its links, as frozen data in SI.

Read by :mod:`kinetostatics.io.sizing` from the keys ``bearing:`` and ``pin:`` of a
revolute and ``section:`` and ``material:`` of a link; the stage
:mod:`kinetostatics.sizing` computes with them.  Nothing here computes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from ..errors import Location

__all__ = ["BearingSpec", "PinSpec", "SectionSpec", "MaterialSpec", "SizingSpec"]

BEARING_TYPES = ("ball", "roller", "plain")
SHEAR_PLANES = {"single": 1, "double": 2}
SECTION_SHAPES = {  # shape -> its dimensions (the keys of ``section:``), required ones
    "rectangle": ("width", "height"),
    "circle": ("diameter",),
    "tube": ("diameter", "thickness"),
    "I": ("height", "width", "web", "flange"),
}


@dataclass(frozen=True)
class BearingSpec:
    """``bearing:`` of a revolute: ``kind`` ball, roller or plain; ``C`` the basic dynamic
    load rating (N, rolling); ``width`` b and ``diameter`` d (m: a plain bearing's length
    and bore, a rolling bearing's bore); the plain bearing's limits ``p_max`` (Pa),
    ``v_max`` (m/s), ``pv_max`` (Pa·m/s); None where not given."""

    kind: str
    C: float | None = None
    width: float | None = None
    diameter: float | None = None
    p_max: float | None = None
    v_max: float | None = None
    pv_max: float | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class PinSpec:
    """``pin:`` of a revolute: its ``diameter`` (m), ``shear`` "single" or "double", the
    eye's width ``eye_width`` (m; None: no bearing pressure on the eyes)."""

    diameter: float
    shear: str = "single"
    eye_width: float | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class SectionSpec:
    """``section:`` of a link: ``shape`` (a key of :data:`SECTION_SHAPES`) and its
    ``dimensions`` (m), the depth (``height``, ``diameter``) in the plane of motion."""

    shape: str
    dimensions: Mapping[str, float]
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class MaterialSpec:
    """``material:`` of a link: the ultimate ``S_ut``, yield ``S_y`` and endurance ``S_e``
    strengths (Pa), None where not given."""

    S_ut: float | None = None
    S_y: float | None = None
    S_e: float | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class SizingSpec:
    """The sizing data of a file, by joint (bearings, pins) and by link (sections,
    materials)."""

    bearings: Mapping[str, BearingSpec] = field(default_factory=dict)
    pins: Mapping[str, PinSpec] = field(default_factory=dict)
    sections: Mapping[str, SectionSpec] = field(default_factory=dict)
    materials: Mapping[str, MaterialSpec] = field(default_factory=dict)

    def __bool__(self) -> bool:
        return bool(self.bearings or self.pins or self.sections)
