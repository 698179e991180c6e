"""Each formula parsed once per process: one mathtext parser for the pictures' renderers.

matplotlib's Agg renderer makes a mathtext parser of its own, whose cache of parsed
formulas (50) is keyed on the parser: a formula measured while a sheet is laid out
(:func:`.style._fit_sheet`, :func:`.style._grow_to_fit`, :func:`.style._inside_axes`) was
parsed again by the renderer of each new size of the sheet, by the one that draws it and
again in the next picture.  Parsing is pyparsing's work, milliseconds a formula: the
polygons' lists of vectors, the polar diagrams' labels and the curves' axis labels.
:func:`share` gives an Agg renderer the process's one parser, which keeps 1,024 parsed
formulas (their laid-out glyphs: a few kB each).

What a parse gives depends on its input (the text, the dpi, the font properties,
antialiasing, hinting) and on matplotlib's settings of the moment (``mathtext.default``,
the math fonts, …), which matplotlib's own cache does not look at: a sheet is laid out
inside the pictures' style (:func:`.style._rc`) and saved after it.  This cache is keyed
on both (every ``mathtext.*``, ``font.*`` and ``text.*`` setting), so it gives what a
fresh parse gives, pixel for pixel.  It is the one cache the pictures keep for the
process (docs/architecture.md, "What is computed once").
"""

from __future__ import annotations

import functools

SIZE = 1024  # formulas kept
_PARSERS: dict = {}  # the process's parser by output ("path", "agg"), made on first use
_SETTINGS = ("mathtext.", "font.", "text.")  # the settings a parse reads


def _settings() -> tuple:
    import matplotlib

    rc = matplotlib.rcParams
    return tuple((k, repr(rc[k])) for k in sorted(rc) if k.startswith(_SETTINGS))


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
