"""Each formula parsed, and each text measured, once per process: one mathtext parser
and one table of text sizes for the pictures' renderers.

matplotlib's Agg renderer makes a mathtext parser of its own, whose cache of parsed
formulas (50) is keyed on the parser: a formula measured while a sheet is laid out
(:func:`.style._fit_sheet`, :func:`.style._grow_to_fit`, :func:`.style._inside_axes`) was
parsed again by the renderer of each new size of the sheet, by the one that draws it and
again in the next picture.  Parsing is pyparsing's work, milliseconds a formula: the
polygons' lists of vectors, the polar diagrams' labels and the curves' axis labels.
:func:`share` gives an Agg renderer the process's one parser, which keeps 1,024 parsed
formulas (their laid-out glyphs: a few kB each).  Likewise matplotlib keeps the sizes of
the texts it measured per renderer: a picture's texts were measured by its layout's
pass and again by the renderer of its final size that draws it, and the tick labels
met again in every picture.  :func:`share` has the renderer measure through the
process's table of sizes (8,192 kept: width, height and descent of a text).

What a parse or a measure gives depends on its input (the text, the dpi, the font
properties, antialiasing, hinting) and on matplotlib's settings of the moment
(``mathtext.default``, the math fonts, the families behind ``sans-serif`` …), which
matplotlib's own caches do not look at.  These are keyed on both (every ``mathtext.*``,
``font.*`` and ``text.*`` setting), so they give what a fresh parse or measure gives,
pixel for pixel.  They are the caches the pictures keep for the process
(docs/architecture.md, "What is computed once").
"""

from __future__ import annotations

import functools
import weakref

SIZE = 1024  # formulas kept
SIZES = 8192  # texts' sizes kept
_SIZES: dict = {}  # (text, font properties, ismath, dpi, settings) -> (width, height, descent)
_PARSERS: dict = {}  # the process's parser by output ("path", "agg"), made on first use
_SETTINGS = ("mathtext.", "font.", "text.")  # the settings a parse reads
_KEYS: list = []  # their names, sorted (matplotlib's settings are a fixed set): found once


def _settings() -> tuple:
    import matplotlib

    rc = matplotlib.rcParams
    if not _KEYS:
        _KEYS.extend(k for k in sorted(rc) if k.startswith(_SETTINGS))
    return tuple((k, repr(rc[k])) for k in _KEYS)


def shared_parser(output: str):
    """The process's mathtext parser for ``output`` ("path": Agg's), or None when this
    matplotlib's parser is not the one this module knows."""
    if output not in _PARSERS:
        from matplotlib.mathtext import MathTextParser

        parse = getattr(MathTextParser._parse_cached, "__wrapped__", None)
        _PARSERS[output] = _parser_class(MathTextParser, parse)(output) if _known(parse) else None
    return _PARSERS[output]


def _known(parse) -> bool:
    """Whether ``parse`` is matplotlib's uncached parse as this module calls it (3.10 and
    later); another matplotlib keeps its own parsers."""
    import inspect

    try:
        from matplotlib.ft2font import LoadFlags  # noqa: F401
    except ImportError:
        return False
    names = ["self", "s", "dpi", "prop", "antialiased", "load_glyph_flags"]
    return callable(parse) and list(inspect.signature(parse).parameters) == names


def _parser_class(base, parse):
    import matplotlib
    from matplotlib.ft2font import LoadFlags

    class Parser(base):
        def parse(self, s, dpi=72, prop=None, *, antialiased=None):
            # matplotlib's MathTextParser.parse, with the settings in the cache's key
            prop = prop.copy() if prop is not None else None
            if antialiased is None:
                antialiased = matplotlib.rcParams["text.antialiased"]
            if self._output_type == "vector":
                flags = LoadFlags.NO_HINTING
            else:
                from matplotlib.backends import backend_agg

                flags = backend_agg.get_hinting_flag()
            return self._parsed(s, dpi, prop, antialiased, flags, _settings())

        @functools.lru_cache(SIZE)  # noqa: B019  (the process's one parser: never freed)
        def _parsed(self, s, dpi, prop, antialiased, flags, settings):
            return parse(self, s, dpi, prop, antialiased, flags)

    return Parser


def share(renderer) -> None:
    """Give an Agg ``renderer`` the process's parser for the output its own parser makes
    (any other renderer is left alone)."""
    from matplotlib.backends.backend_agg import RendererAgg

    kind = getattr(getattr(renderer, "mathtext_parser", None), "_output_type", None)
    if isinstance(renderer, RendererAgg) and kind in ("vector", "raster"):
        parser = shared_parser("path" if kind == "vector" else "agg")
        if parser is not None:
            renderer.mathtext_parser = parser
        settings = _settings()  # the same while the renderer lays out or draws a picture
        # a weak reference: the renderer (its pixels) freed as soon as it is dropped
        measure = functools.partial(_measure, weakref.ref(renderer), settings)
        renderer.get_text_width_height_descent = measure


def _measure(ref, settings, s, prop, ismath):
    """What the renderer's ``get_text_width_height_descent(s, prop, ismath)`` gives,
    measured once per process under ``settings``."""
    renderer = ref()
    own = type(renderer).get_text_width_height_descent
    if ismath == "TeX":
        return own(renderer, s, prop, ismath)
    key = (s, prop.copy(), ismath, renderer.dpi, settings)
    if (size := _SIZES.get(key)) is None:
        if len(_SIZES) >= SIZES:
            _SIZES.clear()
        size = _SIZES[key] = own(renderer, s, prop, ismath)
    return size
