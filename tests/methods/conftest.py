"""What the tests of the methods share: the kinematics of every shipped motion-driven file,
analysed once per session."""

from __future__ import annotations

import pytest

import kinetostatics as ks
from kinetostatics.analysis import analyze
from tests.helpers import ROOT, motion_driven


@pytest.fixture(scope="session")
def kinematics():
    """{file stem: its kinematics-only result} of every motion-driven shipped file."""
    return {
        name: analyze(ks.load(ROOT / "mechanisms" / f"{name}.yaml"), kinematics_only=True)
        for name in motion_driven()
    }
