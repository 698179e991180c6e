"""The import paths from before the layer packages keep working (docs/architecture.md)."""

import importlib

import pytest

from kinetostatics import _aliases


@pytest.mark.parametrize("old", sorted(_aliases.OLD_PATHS))
def test_old_path_is_the_new_module(old):
    before = importlib.import_module(f"kinetostatics.{old}")
    now = importlib.import_module(f"kinetostatics.{_aliases.OLD_PATHS[old]}")
    assert before is now
    assert before.__spec__.name == now.__name__  # the module keeps its own spec


def test_documented_names():
    from kinetostatics.flywheel import design  # noqa: F401
    from kinetostatics.plotting import draw_mechanism  # noqa: F401

    import kinetostatics as ks
    from kinetostatics.analysis import analyze, kinetics  # noqa: F401
    from kinetostatics.dynamics import simulate  # noqa: F401
    from kinetostatics.yaml_io import MAGNITUDE, dump, load, loads  # noqa: F401

    assert ks.yaml_io.dump is dump and ks.positions is ks.kinematics.positions
