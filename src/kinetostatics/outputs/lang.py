"""The languages of the report and the pictures: English (the default) and Chinese
(``--lang zh``).  Every translated text is in :data:`ZH`, keyed by its English text;
:func:`tr` looks one up (a text without an entry stays English, and is recorded in
:data:`MISSING` so that a test can list it).  The Chinese texts are in
:mod:`.zh`, the fonts that show them in :mod:`.fonts`.
"""

from __future__ import annotations

from ..errors import KinetostaticsError
from .zh import ZH

LANGS = ("en", "zh")
MISSING: set[str] = set()


class LanguageError(KinetostaticsError, ValueError):
    """A language cannot be used as asked (unknown code, no font for its glyphs)."""


def check_lang(lang: str) -> str:
    if lang not in LANGS:
        raise LanguageError(f"unknown language '{lang}' (have {', '.join(LANGS)})")
    return lang


def tr(text: str, lang: str = "en", **values) -> str:
    """``text`` in ``lang``, its ``{fields}`` filled from ``values``."""
    if lang == "zh":
        out = ZH.get(text)
        if out is None:
            MISSING.add(text)
            out = text
    else:
        out = text
    return out.format(**values) if values else out


def tr_unit(unit: str, lang: str = "en") -> str:
    """A unit as written in ``lang``: ``deg`` is ``°`` in Chinese; the SI symbols stay."""
    return "°" if lang == "zh" and unit == "deg" else unit
