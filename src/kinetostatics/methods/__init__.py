"""Layer 7, methods: the graded methods of a course design, computed as stages.

A graphical course design (图解法) is graded on its methods as well as its numbers: the
vector equations of each group, the force polygons, the balancing moment checked by
Joukowski's lever and by the power method, the instant centres, the cam's and the gears'
design.  Each method here is a stage: a function of a
:class:`~kinetostatics.analysis.results.Result` (and the positions asked for) that returns a
frozen record with a JSON-safe ``to_dict()``, computed from the same generic pipeline for
any topology the YAML allows.  Its caller (``report``, ``plot``) passes the records to the
outputs, which only format them, and writes ``methods.json`` (docs/methods.md).
"""
