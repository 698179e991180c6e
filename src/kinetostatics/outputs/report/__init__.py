"""The course-design report: one self-contained Markdown and HTML document.

:func:`write_report` analyses a mechanism over a full cycle with rows at the
course-design positions (1…12 from ``analysis.start`` in the sense of motion,
and the load events 1′, 8′ …), and writes to a folder:

- ``report.md`` (images in ``img/``) and ``report.html`` (images embedded,
  no outside files);
- ``results.csv`` and ``summary.json`` of that analysis (the tables of the
  report are rows of this CSV, at full precision in the CSV and to 5
  significant digits in the report; the column ``CSV row`` gives the data row,
  counted from 1 below the header);
- the pictures in ``img/``.

Sections: data, structure (Assur groups), results summary, the mechanism
drawing, tables of positions, velocities, accelerations, reactions and
the balancing torque at the course-design positions (all, or the student's
``positions``), the curves, the velocity and acceleration polygons at chosen
positions, polar diagrams, a section on the springs
and dampers when the file has ``elements:`` (their data and their length, force, energy
and power at the course-design positions, in the file's units), a flywheel section
when the summary has a ``flywheel`` entry and a drive-sizing section when it has a ``drive``
entry.
"""

from .document import ReportError, write_report
from .results import (
    _summary_blocks,  # noqa: F401  (tests/io/test_hostile_numbers.py uses it)
    report_tables,
)

__all__ = ["ReportError", "report_tables", "write_report"]
