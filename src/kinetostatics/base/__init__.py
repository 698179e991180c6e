"""Helpers without domain knowledge: the lowest layer."""
