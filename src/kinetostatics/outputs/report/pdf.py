"""The report as a paginated A4 PDF through fpdf2 (pure Python; ``pip install
'kinetostatics[pdf]'``).

Why fpdf2: it lays out text, tables that break across pages (their heading row
repeated) and images at a size in mm, embeds TrueType fonts as subsets with their
Unicode map (so the text can be searched and extracted), and needs no browser or
system library.  The fonts are matplotlib's own DejaVu Sans (Greek, subscripts, math
signs), with a CJK font as the first font for ``lang="zh"`` (the one :func:`..lang.cjk_font`
finds; with the ``zh`` extra mplfonts' TrueType SimHei, whose text fpdf2 maps so that the
PDF's Chinese text extracts cleanly).

Tables arrive split into column groups of at most 12 columns (``results.GROUP``); each
is set at 7 pt, narrowed to 6 pt or its cells wrapped only if it still does not fit the
page.  Drawings and polygons (``_Image.true_scale``) are placed at their true size so
that μ_l, μ_F, μ_v, μ_a hold on paper; one wider than the page is reduced and its
caption says by how much.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from ..fonts import cjk_fallback, cjk_font
from ..lang import tr
from ..plotting.style import A4_TEXT_MM
from .blocks import ReportError, _Heading, _Image, _List, _Para, _Table

MARGIN = 14.0  # mm
LINE = 4.4  # mm between the lines of the body text (9 pt)
TOP = MARGIN + 1.0  # below this, the top of a page: nothing is moved to the next one
CAPTION = 10.0  # mm kept below an image for its caption
SHRINK = 0.75  # a curve may be reduced this far to fit the rest of a page
PAD = 0.6  # mm inside a table's cells
HEAD_FILL = (232, 239, 248)  # a table's heading row
_HEADING = {1: 15.0, 2: 12.5, 3: 11.0, 4: 11.0, 5: 11.0, 6: 11.0}  # pt


def pdf_module():
    """fpdf2's ``FPDF`` class, or a clear error saying what to install."""
    try:
        from fpdf import FPDF
    except ImportError:
        raise ReportError(
            "a PDF report needs fpdf2: pip install 'kinetostatics[pdf]' (or pip install fpdf2)"
        ) from None
    return FPDF


def _fonts(pdf, lang: str, han: bool = False) -> str:
    """Register the fonts; returns the main one.  Chinese: the CJK font, DejaVu Sans for
    the glyphs it lacks.  English: DejaVu Sans, and the CJK font (when there is one) for
    Chinese characters in the text (``han``: a name the user gave)."""
    import matplotlib

    ttf = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
    pdf.add_font("dejavu", "", str(ttf / "DejaVuSans.ttf"))
    pdf.add_font("dejavu", "B", str(ttf / "DejaVuSans-Bold.ttf"))
    pdf.add_font("dejavu", "I", str(ttf / "DejaVuSans-Oblique.ttf"))
    if lang != "zh" and han:  # names in Chinese (曲柄) from a CJK font, when there is one
        if (found := cjk_fallback()) is None:
            return "dejavu"  # without a CJK font the names show as boxes
        pdf.add_font("cjk", "", found[1])
        pdf.set_fallback_fonts(["cjk"], exact_match=False)
    if lang != "zh":
        return "dejavu"
    # once: its bold and italic would be the same file parsed again (~0.15 s each), and
    # write_pdf's _Doc sets it for the bold and italic text
    pdf.add_font("cjk", "", cjk_font()[1])
    pdf.set_fallback_fonts(["dejavu", "cjk"], exact_match=False)  # "cjk": the footer's
    return "cjk"


def _han(blocks, title: str) -> bool:
    """Whether the title or a block has Chinese characters."""
    texts = [title]
    for b in blocks:
        if isinstance(b, _Table):
            texts += [b.caption, *map(str, b.header), *(str(c) for r in b.rows for c in r)]
        elif isinstance(b, _List):
            texts += b.items
        else:
            texts.append(getattr(b, "text", "") or getattr(b, "caption", ""))
    return any(re.search(f"[{_CJK}]", t) for t in texts)


def _plain(text: str) -> str:
    return text.replace("`", "")


def write_pdf(blocks, path: Path, title: str, lang: str = "en") -> Path:
    """Write the blocks as an A4 portrait PDF; returns ``path``."""
    FPDF = pdf_module()

    class _Doc(FPDF):
        def _render_styled_text_line(self, *args, **kwargs):
            # fpdf2 (2.8.1 to 2.8.9 at least) draws a glyph the main font lacks with the
            # fallback font and, when a line ends with such a glyph, leaves the PDF's text
            # font at the fallback font while believing the main one is still set: the
            # next text would be shown with the wrong font's resource (garbage, empty
            # boxes).  Have it set the font again before the next text.
            done = super()._render_styled_text_line(*args, **kwargs)
            size = self.font_size_pt
            self.set_font_size(size + 1.0)
            self.set_font_size(size)
            return done

        def footer(self):
            # in DejaVu Sans, the Chinese from the CJK font: fpdf2 2.8.1 replaces the
            # alias {nb} (the number of pages) in the font it loaded first only
            self.set_y(-10)
            self.set_font("dejavu", "", 7)
            self.set_text_color(110)
            page = tr("page {n}/{nb}", lang, n=self.page_no(), nb="{nb}")
            self.cell(0, 4, f"{title} — {page}", align="C")
            self.set_text_color(0)

        def set_font(self, family=None, style="", size=0):
            # the CJK font has one face (a regular one: _fonts registers it once) that its
            # bold and italic text is set in; the glyphs it lacks still come from DejaVu
            # Sans's bold and oblique faces (get_fallback_font)
            style = getattr(style, "style", style)  # a TextEmphasis too
            self._asked = "".join(sorted(c for c in style.upper() if c in "BI"))
            if (family or self.font_family).lower() == "cjk":
                style = ""
            super().set_font(family, style, size)

        def get_fallback_font(self, char, style=""):
            if self.font_family == "cjk":
                style = self._asked
            return super().get_fallback_font(char, style)

        def get_string_width(self, s, normalized=False, markdown=False):
            # a report measures the same strings many times (its tables' columns, their
            # heights before and after a page break): each measured once per style
            if normalized or markdown:
                return super().get_string_width(s, normalized, markdown)
            key = (self.font_family, self.font_style, self._asked, self.font_size_pt, s)
            if (w := self._width_cache.get(key)) is None:
                w = self._width_cache[key] = super().get_string_width(s)
            return w

    pdf = _Doc(orientation="P", unit="mm", format="A4")
    pdf._width_cache, pdf._asked = {}, ""
    font = _fonts(pdf, lang, han=lang != "zh" and _han(blocks, title))
    pdf.set_title(title)
    pdf.set_creator("kinetostatics")
    pdf.set_margins(MARGIN, MARGIN, MARGIN)
    pdf.set_auto_page_break(True, MARGIN)
    pdf.add_page()
    for i, b in enumerate(blocks):
        if isinstance(b, _Heading):
            y = pdf.get_y()
            if y > TOP and y + _need(pdf, blocks, i, font, y) > pdf.h - MARGIN:
                pdf.add_page()  # a heading never ends a page: it goes with its block
            size = _HEADING[b.level]
            pdf.ln(3 if b.level > 1 and pdf.get_y() > TOP else 0)
            pdf.set_font(font, "B", size)
            _text(pdf, b.text, size * 0.5, lang)
            pdf.ln(1.5)
        elif isinstance(b, _Para):
            pdf.set_font(font, "", 9)
            _text(pdf, b.text, LINE, lang)
            pdf.ln(1.5)
        elif isinstance(b, _List):
            for item in b.items:
                pdf.set_x(MARGIN + 2)
                pdf.set_font("dejavu", "", 9)  # a CJK font may have no U+2022
                pdf.cell(4, LINE, "•")
                pdf.set_font(font, "", 9)
                _text(pdf, item, LINE, lang)
            pdf.ln(1.5)
        elif isinstance(b, _Table):
            _table(pdf, font, b, lang)
        elif isinstance(b, _Image):
            _image(pdf, font, b, lang)
    path = Path(path)
    pdf.output(str(path))  # write_report writes it whole (base.files.write_file)
    return path


def _columns(pdf, font: str, t: _Table) -> tuple[float, list[float]]:
    """The font size and column widths (mm) of a table: 7 pt, narrowed to 6 pt only if it
    does not fit the page, then its cells wrapped."""
    epw = pdf.w - 2 * MARGIN
    size = 7.0
    widths = []
    for size in (7.0, 6.5, 6.0):
        pdf.set_font(font, "", size)
        widths = []
        for c in range(len(t.header)):
            cells = [str(r[c]) for r in t.rows if c < len(r)]
            body = max((pdf.get_string_width(x) for x in cells), default=0.0)
            pdf.set_font(font, "B", size)
            head = max((pdf.get_string_width(w) for w in str(t.header[c]).split()), default=0.0)
            pdf.set_font(font, "", size)
            widths.append(min(max(body, head, 4.0) + 2.4, 0.45 * epw))
        if sum(widths) <= epw:
            break
    total = sum(widths)
    if total > epw:  # long free text: share the page, cells wrap
        widths = [w * epw / total for w in widths]
    return size, widths


def _table_heights(pdf, font: str, t: _Table) -> tuple[tuple, float, list[float]]:
    """A table's :func:`_columns`, about how tall (mm) its caption with the space after it
    and its heading row are, and each of its rows: as many lines as its fullest cell
    takes."""
    size, widths = _columns(pdf, font, t)
    top = 0.0
    if t.caption:
        pdf.set_font(font, "I", 8)
        lines = math.ceil(pdf.get_string_width(_plain(t.caption)) / (pdf.w - 2 * MARGIN - 3))
        top += 3.8 * max(lines, 1) + 0.8
    rows = []
    for k, row in enumerate([t.header, *t.rows]):
        pdf.set_font(font, "B" if k == 0 else "", size)
        cells = zip(row, widths, strict=False)
        lines = max(
            (math.ceil(pdf.get_string_width(_plain(str(c))) / max(w - 1.6, 1.0)) for c, w in cells),
            default=1,
        )
        rows.append(size * 0.5 * max(lines, 1) + 1.2)
    return (size, widths), top + rows[0], rows[1:]


def _table_start(pdf, font: str, t: _Table, y: float) -> tuple[float, int, tuple]:
    """How a table starts at the height ``y``: the height (mm) of its part on this page
    and the number of its rows there.  All of it if it fits; else its caption, heading
    row and the rows that fit, at least 3 and leaving at least 2 for the next page (a
    table longer than a page: as many as fit); else ``(inf, 0)``: it starts on the next
    page.  Then its :func:`_columns`, measured for this."""
    columns, top, rows = _table_heights(pdf, font, t)
    room = pdf.h - MARGIN - y
    height, fit = top, 0
    while fit < len(rows) and height + rows[fit] <= room:
        height, fit = height + rows[fit], fit + 1
    if fit < len(rows) and top + sum(rows) <= pdf.h - 2 * MARGIN:
        while fit > 0 and len(rows) - fit < 2:  # no row or two alone on the next page
            fit -= 1
            height -= rows[fit]
    return (height, fit, columns) if fit >= min(3, len(rows)) else (math.inf, 0, columns)


def _table(pdf, font: str, t: _Table, lang: str) -> None:
    from fpdf.fonts import FontFace

    height, here, (size, widths) = _table_start(pdf, font, t, pdf.get_y())
    if pdf.get_y() > TOP and math.isinf(height):
        pdf.add_page()
        here = len(t.rows)  # from the top of a page, fpdf2 breaks it where it must
    if t.caption:
        pdf.set_font(font, "I", 8)
        _text(pdf, t.caption, 3.8, lang)
        pdf.ln(0.8)
    align = ["LEFT"] + ["RIGHT"] * (len(t.header) - 1)
    if any(len(str(r[c])) > 30 for r in t.rows for c in range(1, len(r))):
        align = ["LEFT"] * len(t.header)
    parts = [t.rows[:here], t.rows[here:]] if 0 < here < len(t.rows) else [t.rows]
    rows = [[_plain(str(c)) for c in r] for r in t.rows]
    scale = min(sum(widths), pdf.epw) / sum(widths)  # fpdf2's table: widths in proportion
    widths = [w * scale for w in widths]
    pdf.set_font(font, "", size)
    if all(_one_line(pdf, c, w) for r in rows for c, w in zip(r, widths)):
        _grid(pdf, font, size, [[str(h) for h in t.header], *rows], (widths, align), here)
        pdf.ln(3)
        return
    page = pdf.page
    for k, part in enumerate(parts):
        if k and pdf.page == page:
            pdf.add_page()  # the rest on the next page, under the heading row again
        with pdf.table(
            width=sum(widths),
            col_widths=widths,
            align="LEFT",
            text_align=align,
            line_height=size * 0.5,
            # bold in the heading row's style: fpdf2 would refuse a bold headings_style
            # for the CJK font, which has no bold face registered (_fonts)
            headings_style=FontFace(fill_color=HEAD_FILL),
            repeat_headings=1,
            padding=PAD,
            borders_layout="ALL",
        ) as table:
            table.row([str(h) for h in t.header], style=FontFace(emphasis="BOLD"))
            for r in part:
                table.row([_plain(str(c)) for c in r])
    pdf.ln(3)


def _grid(pdf, font: str, size: float, cells, columns, here: int) -> None:
    """A table whose body cells each fit on one line, drawn as fpdf2's ``table()`` draws
    it (the same boxes, fill, padding and text positions; its heading row again at the
    top of each page it runs on to) but each body cell as one rectangle and one text:
    fpdf2 lays out every cell of a ``table()`` twice through ``multi_cell`` (its height,
    then its text), ~70 % of writing a report's PDF.  ``here``: the rows on this page
    before the rest goes on the next one (all of them: as they fit).  ``cells``: the
    heading row, then the rows; ``columns``: their widths (mm) and alignments."""
    (header, *rows), (widths, align) = cells, columns
    line = size * 0.5
    xs = [MARGIN + sum(widths[:j]) for j in range(len(widths))]

    # the heading row's cells in lines, as fpdf2 breaks them (once for every page it is on)
    pdf.set_font(font, "B", size)
    broken = [
        [h] if _one_line(pdf, h, w) else _broken(pdf, h, w, line) for h, w in zip(header, widths)
    ]
    head = max((len(b) for b in broken), default=1) * line + 2 * PAD

    def heading() -> None:
        pdf.set_font(font, "B", size)
        y = pdf.get_y()
        pdf.set_fill_color(*HEAD_FILL)
        for x, w, lines, a in zip(xs, widths, broken, align):
            pdf.rect(x, y, w, head, style="DF")
            top = y + (head - 2 * PAD - len(lines) * line) / 2
            for k, text in enumerate(lines):  # each where multi_cell would set it
                if text:
                    _cell_text(pdf, (x, top + k * line, w, line), text, a)
        pdf.set_xy(MARGIN, y + head)
        pdf.set_fill_color(255)
        pdf.set_font(font, "", size)

    heading()
    page = pdf.page
    tall = line + 2 * PAD
    for k, row in enumerate(rows):
        y = pdf.get_y()
        if (k == here > 0 and pdf.page == page) or y + tall > pdf.page_break_trigger:
            pdf.add_page()
            heading()
            y = pdf.get_y()
        for x, w, text, a in zip(xs, widths, row, align):
            pdf.rect(x, y, w, tall)
            if text:
                _cell_text(pdf, (x, y, w, line), text, a)
        pdf.set_xy(MARGIN, y + tall)


def _one_line(pdf, text: str, w: float) -> bool:
    """Whether ``text`` fits a cell ``w`` mm wide on one line in the current font (with
    0.01 mm to spare, so that fpdf2 would not break it either)."""
    return "\n" not in text and pdf.get_string_width(text) <= w - 2 * PAD - 0.01


def _broken(pdf, text: str, w: float, line: float) -> list[str]:
    """``text``'s lines in a cell ``w`` mm wide, as fpdf2 breaks them."""
    return pdf.multi_cell(w, line, text, padding=PAD, dry_run=True, output="LINES")


def _cell_text(pdf, box, text: str, align: str) -> None:
    """A line of text (one that fits) in a table cell whose top-left corner, width and
    line height (mm) are ``box``, where fpdf2's ``multi_cell`` puts it: in the main font
    as one PDF text; with a glyph from the fallback font through ``multi_cell``."""
    x, y, w, line = box
    cmap = getattr(pdf.current_font, "cmap", None)
    if cmap is None or any(ord(ch) not in cmap for ch in text):
        pdf.set_xy(x, y)
        pdf.multi_cell(w, line, text, align=align[0], padding=PAD, new_x="RIGHT", new_y="TOP")
        return
    dx = PAD if align == "LEFT" else w - PAD - pdf.get_string_width(text)
    pdf.text(x + dx, y + PAD + 0.5 * line + 0.3 * pdf.font_size, text)  # fpdf2's baseline


def _placed(pdf, im: _Image) -> tuple[float, float, float]:
    """Width, height (mm) and scale of an image placed at the current height: at 100 %
    (at most the page's width and height); a curve (not to scale) that does not fit the
    rest of the page but would at ``SHRINK`` or more is reduced to fit there, instead of
    leaving that part of the page empty."""
    epw = pdf.w - 2 * MARGIN
    w, h = im.width_mm or epw, im.height_mm or epw * 0.6
    scale = min(1.0, epw / w, A4_TEXT_MM[1] / h)  # the room polygons are made to fit
    room = pdf.h - MARGIN - CAPTION - pdf.get_y()
    if not im.true_scale and room < h * scale and room >= SHRINK * h * scale:
        scale = room / h
    return w * scale, h * scale, scale


def _image(pdf, font: str, im: _Image, lang: str) -> None:
    epw = pdf.w - 2 * MARGIN
    w, h, scale = _placed(pdf, im)
    if pdf.get_y() + h + CAPTION > pdf.h - MARGIN:
        pdf.add_page()
        w, h, scale = _placed(pdf, im)
    pdf.image(str(im.path), x=MARGIN + (epw - w) / 2, y=pdf.get_y(), w=w, h=h)
    pdf.set_y(pdf.get_y() + h + 1)
    caption = im.caption
    if im.true_scale:
        caption += " " + (
            tr("(printed at 100 %: the scales hold on paper)", lang)
            if scale == 1.0
            else tr(
                "(reduced to {p} %: divide the scales by {s})",
                lang,
                p=f"{100 * scale:.0f}",
                s=f"{scale:.3g}",
            )
        )
    pdf.set_font(font, "I", 8)
    _text(pdf, caption, 3.8, lang)
    pdf.ln(3)


def _need(pdf, blocks, i: int, font: str, y: float) -> float:
    """The height (mm) a heading needs below ``y`` on its page: itself and the start of
    the block after it (two lines of text, a table's part on this page, an image whole);
    ``inf`` if that block would start on the next page."""
    b = blocks[i]
    if isinstance(b, _Heading):
        own = _HEADING[b.level] * 0.5 + 4.5
        return own + (_need(pdf, blocks, i + 1, font, y + own) if i + 1 < len(blocks) else 0.0)
    if isinstance(b, (_Para, _List)):
        return 2 * LINE + 1.5
    if isinstance(b, _Table):
        return _table_start(pdf, font, b, y)[0]
    if isinstance(b, _Image):
        return _placed(pdf, b)[1] + CAPTION
    return 0.0


# -- Chinese lines ---------------------------------------------------------------------
# fpdf2 breaks lines at spaces only and justifies them by widening the spaces: a Chinese
# sentence (no spaces) came out as "由            kinetostatics" and a run of characters
# on the next line.  Chinese text is broken here instead, between any two Chinese
# characters and at spaces, never inside a Latin word nor before a closing mark or after
# an opening one, and set flush left.
_CJK = "\u2e80-\u9fff\uf900-\ufaff\ufe30-\ufe4f\uff00-\uffef\u3000-\u303f"
_TOKEN = re.compile(f"[{_CJK}]|[^\\s{_CJK}]+|\\s+")
_NO_START = set("，。、；：！？）》」』】〕…%,.;:!?)]}°′″")  # never first on a line
_NO_END = set("（《「『【〔([{")  # never last on a line


def _lines(pdf, text: str, width: float) -> list[str]:
    """``text`` in lines of at most ``width`` mm in the current font."""
    tokens: list[str] = []
    for t in _TOKEN.findall(text):
        if tokens and not t.isspace() and (t[0] in _NO_START or tokens[-1][-1] in _NO_END):
            tokens[-1] += t
        elif pdf.get_string_width(t) > width:  # longer than a line: character by character
            tokens += list(t)
        else:
            tokens.append(t)
    lines, line, used = [], "", 0.0
    for t in tokens:
        w = pdf.get_string_width(t)
        if line and not t.isspace() and used + w > width:
            lines.append(line.rstrip())
            line, used = "", 0.0
        if line or not t.isspace():
            line, used = line + t, used + w
    return lines + [line.rstrip()]


def _text(pdf, text: str, height: float, lang: str) -> None:
    """A paragraph from the current position to the right margin, lines ``height`` mm
    apart: English justified, Chinese broken by :func:`_lines` and set flush left."""
    text = _plain(text).replace("\r", "")  # as multi_cell reads it
    width = pdf.w - pdf.r_margin - pdf.get_x() - 2 * pdf.c_margin
    if lang != "zh":
        if text and "\n" not in text and pdf.get_string_width(text) <= width - 0.01:
            lines = [text]  # one line (0.01 mm to spare, so that fpdf2 would not break it)
        else:
            pdf.multi_cell(0, height, text, new_x="LMARGIN", new_y="NEXT")
            return
    else:
        lines = _lines(pdf, text, width - 0.5)  # round-off room
        if not all(lines) or any("\n" in line for line in lines):
            text = "\n".join(lines)
            pdf.multi_cell(0, height, text, align="L", new_x="LMARGIN", new_y="NEXT")
            return
    # lines that need no breaking, each a cell where multi_cell would set it (flush left:
    # it justifies no last line), without its line breaking, which measures the line
    # again for each character added (English one-line texts, Chinese lines)
    for k, line in enumerate(lines, 1):
        pdf.cell(0, height, line, new_x="LMARGIN" if k == len(lines) else "LEFT", new_y="NEXT")
