"""The names a user gives: links, joints, points, loads, drivers, parameters.

A name is a Python identifier (:meth:`str.isidentifier`): letters of any script, digits
and ``_``, not starting with a digit — ``crank``, ``O2``, ``曲柄``, ``F_切削`` — and it is
written in Unicode's NFKC form, the form Python's parser gives a name, so that a parameter
``ℌ`` or ``ﬁ`` is not silently read as ``H`` or ``fi`` in an expression.  Such a name has
no ``.`` (the result columns are ``<link>.omega``, ``<joint>.Fx``), no space and no
operator, so it parses as one name in an expression and as one member in a column.

>>> is_name("曲柄"), is_name("O2"), is_name("main-motor"), is_name("2A"), is_name("ﬁ")
(True, True, False, False, False)
>>> suggestion("main-motor"), suggestion("2A"), suggestion("ﬁ")
('main_motor', '_2A', 'fi')
"""

from __future__ import annotations

import keyword
import unicodedata

__all__ = ["is_name", "is_word_character", "suggestion", "SCHEMA_PATTERN"]

# The same names as far as a JSON Schema's regular expression can tell them: no ASCII
# character but letters, digits and _, no white space, not starting with a digit.  The
# class is written in escapes that ECMA-262 (editors) and Python's re (validators) read
# alike; characters beyond ASCII are left to the loader.
_REFUSED = r"\x00-\x2F\x3A-\x40\x5B-\x5E\x60\x7B-\x7F\s"
SCHEMA_PATTERN = rf"^[^{_REFUSED}0-9][^{_REFUSED}]*$"


def is_name(name: object, *, expression: bool = False) -> bool:
    """Whether ``name`` is a valid name; with ``expression``, also one that an expression
    can use (not a Python keyword such as ``if`` or ``lambda``)."""
    if not isinstance(name, str) or not name.isidentifier():
        return False
    if not name.isascii() and unicodedata.normalize("NFKC", name) != name:
        return False
    return not (expression and keyword.iskeyword(name))


def is_word_character(ch: str) -> bool:
    """Whether the character ``ch`` may stand inside a name (in its NFKC form)."""
    return ("_" + ch).isidentifier() and unicodedata.normalize("NFKC", ch) == ch


def suggestion(name: str) -> str:
    """A valid name close to ``name``: its NFKC form with every other character an ``_``,
    an ``_`` put before a leading digit or after a keyword."""
    text = unicodedata.normalize("NFKC", name)
    fixed = "".join(ch if ("_" + ch).isidentifier() else "_" for ch in text) or "_"
    if not fixed.isidentifier():
        fixed = "_" + fixed
    if keyword.iskeyword(fixed):
        fixed += "_"
    return unicodedata.normalize("NFKC", fixed)
