"""Pictures of a :class:`~kinetostatics.analysis.results.Result`.

Every public drawing function takes a ``Result`` and returns a matplotlib
``Figure`` built without ``pyplot`` (no global state; save it with
``fig.savefig(path)``).  matplotlib is imported inside the functions that draw,
so importing this module stays light.  The numbers behind the pictures come
from data functions that tests check against the results:

- :func:`mechanism_geometry` — every point, joint, link outline, block and
  guide drawn at one position (m);
- :func:`polygon` — the velocity or acceleration polygon at one position:
  absolute vectors from the pole and the relative vectors (ω × r, ω²r, α × r,
  sliding, Coriolis) that close it;
- :func:`link_frame_loads` — a joint's reaction in a link-fixed frame (polar
  diagrams);
- :func:`course_positions` — the course-design positions 1…12 and the load
  events (1′, 8′ …) among the rows.

Figures: :func:`draw_mechanism`, :func:`motion_diagram`,
:func:`reaction_curves`, :func:`torque_curves`, :func:`efficiency_curve`,
:func:`polar_diagrams`, :func:`polygon_figure`, :func:`plot_result`,
:func:`equivalent_moments` and :func:`energy_diagram` (a flywheel design); and
:func:`animate` writes a GIF (Pillow) or an MP4 (only when ffmpeg is on the
PATH).  Drawings and polygons are laid out to a true scale: printed at 100 %,
1 mm of paper is μ_l metres (μ_v m/s, μ_a m/s², μ_F N), as stated on them.

Conventions (docs/conventions.md, docs/theory.md): x right, y up, angles and moments
counter-clockwise positive; a joint's reaction is the force of its link i on
its link j; links are numbered 1, 2, … in the order of ``System.links`` and
the frame takes the next number, so ``F61`` is the frame (6) on the crank (1).
"""

from .animate import animate
from .curves import (
    _active_spans,  # noqa: F401  (tests/outputs/test_plotting.py uses it)
    efficiency_curve,
    motion_diagram,
    output_motion,
    plot_result,
    reaction_curves,
    torque_curves,
)
from .draw import draw_mechanism
from .energy import energy_diagram, equivalent_moments
from .polar import link_frame_loads, polar_diagrams
from .polygons import Polygon, PolygonChain, PolygonNode, polygon, polygon_figure
from .rows import analyze_for_pictures, course_positions, link_numbers, row_at, turns
from .scene import MechanismGeometry, mechanism_geometry
from .style import PictureError, nice_scale

__all__ = [
    "MechanismGeometry",
    "PictureError",
    "Polygon",
    "PolygonChain",
    "PolygonNode",
    "analyze_for_pictures",
    "animate",
    "course_positions",
    "draw_mechanism",
    "efficiency_curve",
    "energy_diagram",
    "equivalent_moments",
    "link_frame_loads",
    "link_numbers",
    "mechanism_geometry",
    "motion_diagram",
    "nice_scale",
    "output_motion",
    "plot_result",
    "polar_diagrams",
    "polygon",
    "polygon_figure",
    "reaction_curves",
    "row_at",
    "torque_curves",
    "turns",
]
