"""The languages of the report and the pictures: English (the default) and Chinese
(``--lang zh``).  Every translated text is in :data:`ZH`, keyed by its English text;
:func:`tr` looks one up (a text without an entry stays English, and is recorded in
:data:`MISSING` so that a test can list it).  Chinese glyphs need a CJK font:
:func:`cjk_font` finds one through matplotlib's font manager (or the file named by the
environment variable ``KINETOSTATICS_CJK_FONT``) and raises a clear error when the
system has none.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import KinetostaticsError

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


# -- fonts -------------------------------------------------------------------------------
# Families known to hold the CJK unified ideographs, most common first (Linux, Windows,
# macOS); any other installed font whose name says CJK/SC/CN also serves.
_CJK_FAMILIES = (
    "Noto Sans CJK SC",
    "Noto Sans SC",
    "Noto Serif CJK SC",
    "Source Han Sans SC",
    "Source Han Sans CN",
    "WenQuanYi Micro Hei",
    "WenQuanYi Zen Hei",
    "Droid Sans Fallback",
    "AR PL UMing CN",
    "AR PL UKai CN",
    "Microsoft YaHei",
    "SimHei",
    "SimSun",
    "PingFang SC",
    "Hiragino Sans GB",
    "Heiti SC",
    "STHeiti",
    "Arial Unicode MS",
)
_HINT = (
    "no font with Chinese glyphs found for --lang zh. Install one, e.g. "
    "'apt-get install fonts-noto-cjk' or 'apt-get install fonts-wqy-microhei' (Debian, "
    "Ubuntu), 'dnf install google-noto-sans-cjk-fonts' (Fedora); or name a .ttf/.otf/.ttc "
    "file with the environment variable KINETOSTATICS_CJK_FONT. (matplotlib may cache the "
    "font list: after installing, delete ~/.cache/matplotlib if the font is still not found.)"
)


def _has_han(path: str) -> bool:
    """Whether the font file maps 中 (U+4E2D) and 力 (U+529B)."""
    try:
        from fontTools.ttLib import TTCollection, TTFont

        fonts = TTCollection(path).fonts if path.lower().endswith(".ttc") else [TTFont(path)]
        cmap = fonts[0].getBestCmap() or {}
        return 0x4E2D in cmap and 0x529B in cmap
    except Exception:  # unreadable or not a font: not this one
        return False


_FOUND: dict[str, tuple[str, str]] = {}


def cjk_font() -> tuple[str, str]:
    """``(family, path)`` of a font with Chinese glyphs, registered with matplotlib.

    Raises :class:`LanguageError` (saying what to install) when there is none."""
    if "font" in _FOUND:
        return _FOUND["font"]
    from matplotlib import font_manager as fm

    env = os.environ.get("KINETOSTATICS_CJK_FONT")
    if env:
        if not Path(env).is_file() or not _has_han(env):
            raise LanguageError(
                f"KINETOSTATICS_CJK_FONT={env}: not a font file with Chinese glyphs"
            )
        fm.fontManager.addfont(env)
        family = fm.FontProperties(fname=env).get_name()
        _FOUND["font"] = (family, env)
        return _FOUND["font"]
    entries = {f.name: f.fname for f in fm.fontManager.ttflist}
    names = [n for n in _CJK_FAMILIES if n in entries]
    names += sorted(
        n
        for n in entries
        if n not in names and any(w in n for w in ("CJK", " SC", " CN", "Hei", "Song", "Kai"))
    )
    for name in names:
        if _has_han(entries[name]):
            _FOUND["font"] = (name, entries[name])
            return _FOUND["font"]
    raise LanguageError(_HINT)


def rc_fonts(lang: str) -> dict:
    """matplotlib rc settings for ``lang``: the CJK family first for Chinese."""
    if lang != "zh":
        return {}
    family, _ = cjk_font()
    return {"font.family": [family, "DejaVu Sans"]}  # named: kept by every Text at creation


# -- the Chinese texts ---------------------------------------------------------------------
ZH: dict[str, str] = {}
