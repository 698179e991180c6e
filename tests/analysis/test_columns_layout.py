"""A result's column names, units and name → (group, index) map are made once per system
and shared by its results (analysis/columns.py): the results of one system read the
same map, a column added to one result's columns leaves the other's alone, and the names
and units are those of a system built afresh."""

import numpy as np

import kinetostatics as ks


def test_results_of_one_system_share_the_layout_and_not_their_additions():
    model = ks.load("mechanisms/slider_crank.yaml")
    a, b = ks.analyze(model), ks.analyze(model, positions=np.radians([0.0, 45.0]))
    assert list(a.columns) == list(b.columns) and a.units == b.units
    assert a.columns._where is b.columns._where  # one map for the system
    a.units["x"] = "m"  # each result's units are its own dict
    assert "x" not in b.units
    a.columns.add(["extra"], lambda: (np.zeros(len(a.t)),))
    assert "extra" in a.columns and "extra" not in b.columns
    fresh = ks.analyze(ks.load("mechanisms/slider_crank.yaml"))
    assert list(fresh.columns) == list(b.columns) and fresh.units == b.units
