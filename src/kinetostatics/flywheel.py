"""Flywheel sizing: the documented path; the code is :mod:`kinetostatics.dynamics.flywheel`."""

from .dynamics.flywheel import FlywheelDesign, design, energy_curve, verify

__all__ = ["FlywheelDesign", "design", "verify", "energy_curve"]
