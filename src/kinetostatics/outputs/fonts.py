"""The fonts of the report and the pictures.  Chinese glyphs need a CJK font:
:func:`cjk_font` takes the file named by the environment variable
``KINETOSTATICS_CJK_FONT``, else a system font found through matplotlib's font manager,
else a font of the optional package ``mplfonts`` (``pip install 'kinetostatics[zh]'``),
and raises a clear error naming both when there is none.
"""

from __future__ import annotations

import functools
import logging
import os
import re
from pathlib import Path

from .lang import LanguageError

# -- fonts -------------------------------------------------------------------------------
# Where a font with Chinese glyphs is looked for, in this order: the file named by the
# environment variable KINETOSTATICS_CJK_FONT; the fonts installed on the system (through
# matplotlib's font manager; the families below first, most common first: Linux, Windows,
# macOS; then any other whose name says CJK/SC/CN); the fonts shipped by the optional
# package ``mplfonts`` (``pip install 'kinetostatics[zh]'``), located without importing it
# (its ``init`` would rewrite matplotlib's configuration).
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
# mplfonts' files, TrueType first: fpdf2 embeds a TrueType (glyf) font with a text map
# that PDF readers extract; a CFF .otf comes out with a NUL before every character.
_MPLFONTS_FILES = (
    "SimHei.ttf",
    "NotoSansCJKsc-Regular.otf",
    "SourceHanSerifSC-Regular.otf",
    "NotoSerifCJKsc-Regular.otf",
)
_ENV = "KINETOSTATICS_CJK_FONT"
_HINT = (
    "no font with Chinese glyphs found for --lang zh. Install one: "
    "pip install 'kinetostatics[zh]' (the fonts of the package mplfonts), or a system font "
    "('apt-get install fonts-noto-cjk' on Debian/Ubuntu, 'dnf install "
    "google-noto-sans-cjk-fonts' on Fedora); or name a .ttf/.otf/.ttc file with the "
    "environment variable KINETOSTATICS_CJK_FONT. (matplotlib may cache the font list: after "
    "installing a system font, delete ~/.cache/matplotlib if it is still not found.)"
)


def _has_han(path: str) -> bool:
    """Whether the font file (the first font of a collection) maps 中 (U+4E2D) and 力
    (U+529B).  Through FreeType (matplotlib's FT2Font), which reads only what it is asked:
    fontTools' whole character map of a CJK font cost ~60 ms of every picture's and
    report's start, its import included."""
    try:
        from matplotlib.ft2font import FT2Font

        font = FT2Font(path)
        return font.get_char_index(0x4E2D) != 0 and font.get_char_index(0x529B) != 0
    except Exception:  # unreadable or not a font: not this one
        return False


def _system_font() -> str | None:
    """The file of an installed font with Chinese glyphs that matplotlib knows, or None."""
    from matplotlib import font_manager as fm

    entries = {f.name: f.fname for f in fm.fontManager.ttflist}
    names = [n for n in _CJK_FAMILIES if n in entries]
    names += sorted(
        n
        for n in entries
        if n not in names and any(w in n for w in ("CJK", " SC", " CN", "Hei", "Song", "Kai"))
    )
    return next((entries[n] for n in names if _has_han(entries[n])), None)


def _mplfonts_font() -> str | None:
    """A font file shipped by the package ``mplfonts`` (the ``zh`` extra), or None.  The
    package is found, not imported."""
    import importlib.util

    try:
        spec = importlib.util.find_spec("mplfonts")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    for folder in spec.submodule_search_locations:
        for name in _MPLFONTS_FILES:
            path = Path(folder) / "fonts" / name
            if path.is_file() and _has_han(str(path)):
                return str(path)
    return None


class _RegularForBold(logging.Filter):
    """Drops matplotlib's warning that the CJK family has no bold face (a point label is
    bold; its Chinese characters are drawn regular), said on every drawing otherwise."""

    def __init__(self, family: str):
        super().__init__()
        self.family = family

    def filter(self, record: logging.LogRecord) -> bool:
        return not (
            str(record.msg).startswith("findfont: Failed to find font weight")
            and len(record.args or ()) == 3
            and record.args[1] == self.family  # type: ignore[index]
        )


_FOUND: dict[str | None, tuple[str, str]] = {}  # by the value of KINETOSTATICS_CJK_FONT


def cjk_font() -> tuple[str, str]:
    """``(family, path)`` of a font with Chinese glyphs, registered with matplotlib's font
    manager: KINETOSTATICS_CJK_FONT, else a system font, else one of ``mplfonts``.

    Raises :class:`LanguageError` (saying what to install) when there is none."""
    from matplotlib import font_manager as fm

    env = os.environ.get(_ENV) or None
    if env in _FOUND:
        return _FOUND[env]
    if env:
        if not Path(env).is_file() or not _has_han(env):
            raise LanguageError(f"{_ENV}={env}: not a font file with Chinese glyphs")
        path = env
    else:
        path = _system_font() or _mplfonts_font()
        if path is None:
            raise LanguageError(_HINT)
    if path not in {f.fname for f in fm.fontManager.ttflist}:
        fm.fontManager.addfont(path)
    family = fm.FontProperties(fname=path).get_name()
    logging.getLogger("matplotlib.font_manager").addFilter(_RegularForBold(family))
    _FOUND[env] = (family, path)
    return _FOUND[env]


def cjk_fallback() -> tuple[str, str] | None:
    """The CJK font for the names in Chinese (曲柄) of an English picture or PDF, as a
    fallback after DejaVu Sans; None when there is none (the English texts need none)."""
    try:
        return cjk_font()
    except LanguageError:
        return None


def rc_fonts(lang: str) -> dict:
    """matplotlib rc settings for ``lang``: a chain of fonts that matplotlib (≥ 3.6) falls
    back along glyph by glyph.  For Chinese the CJK family, then DejaVu Sans for every
    glyph it lacks (², ≤, subscripts …); for English the default sans-serif, then a CJK
    family when there is one (for the Chinese names a user may give).  The plain text of
    a mathtext label is drawn from one font alone: :func:`math_fallback` mends it."""
    if lang != "zh":
        found = cjk_fallback()
        return {"font.family": ["sans-serif", found[0]]} if found else {}
    family, _ = cjk_font()
    return {"font.family": [family, "DejaVu Sans"]}  # named: kept by every Text at creation


@functools.cache
def _font_file(path: str):
    from matplotlib.ft2font import FT2Font

    return FT2Font(path)


@functools.lru_cache(maxsize=4096)
def _lacks(path: str, ch: str) -> bool:
    """Whether the font file ``path`` has no glyph for ``ch``."""
    return _font_file(path).get_char_index(ord(ch)) == 0


def math_fallback(text: str, paths: list[str]) -> tuple[int, str]:
    r"""How to draw ``text``, a mathtext label (``$…$`` in it), whose plain parts
    matplotlib draws from one font file alone: which of the font files ``paths`` (the
    chain of the label's families) has most of the plain parts' characters, and the text
    with each character that file lacks set as a formula ``$\mathrm{c}$`` (drawn from
    the math fonts, DejaVu Sans by default).  ``(0, text)`` for a text without formulas.

    >>> import matplotlib
    >>> dejavu = matplotlib.get_data_path() + "/fonts/ttf/DejaVuSans.ttf"
    >>> math_fallback(r"$\mu_a$ = 0.04 (m/s²)/mm", [dejavu])  # DejaVu has ²
    (0, '$\\mu_a$ = 0.04 (m/s²)/mm')
    >>> math_fallback(r"$\mu_a$ ≤ 1 中", [dejavu])  # but not 中
    (0, '$\\mu_a$ ≤ 1 $\\mathrm{中}$')
    >>> math_fallback("中 $5 (an odd dollar)", [dejavu])  # no formula: as it is
    (0, '中 $5 (an odd dollar)')
    """
    parts = re.split(r"(?<!\\)\$", text)
    if len(parts) < 3 or len(parts) % 2 == 0:
        return 0, text  # no formula: plain text, with the fallback along font.family
    plain = {c for part in parts[::2] for c in part if not c.isspace()}
    best = max(range(len(paths)), key=lambda i: (sum(not _lacks(paths[i], c) for c in plain), -i))
    for i in range(0, len(parts), 2):
        parts[i] = "".join(
            c if c.isspace() or ord(c) < 128 or not _lacks(paths[best], c) else f"$\\mathrm{{{c}}}$"
            for c in parts[i]
        )
    return best, "$".join(parts)
