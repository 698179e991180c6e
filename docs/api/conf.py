"""Sphinx configuration of the API reference (docs/api.md): the public names of
kinetostatics, from their numpydoc docstrings.

    sphinx-build -W -b html docs/api OUT

``tests/architecture/test_public_api.py`` builds it with warnings as errors.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "src"))

import kinetostatics  # noqa: E402  (the checkout's package, above)

project = "kinetostatics"
author = "the kinetostatics authors"
release = version = kinetostatics.__version__

extensions = ["sphinx.ext.autodoc", "numpydoc"]
autodoc_member_order = "bysource"
autodoc_typehints = "signature"  # the types are in each docstring's Parameters
numpydoc_show_class_members = False  # the page lists the public methods itself
numpydoc_class_members_toctree = False

html_theme = "alabaster"
html_title = f"kinetostatics {release} API"
html_show_sourcelink = False
html_show_sphinx = False  # no link out of the repository's own pages
html_copy_source = False
