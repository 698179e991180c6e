"""What the PDF shows is what the Markdown report says (issue 37, the rendering defects):
every heading, paragraph and list item of ``report.md`` is in the PDF's extracted text,
in English and in Chinese, for every shipped mechanism and every template of ``init``,
whatever glyph the CJK font lacks (a bullet, ², μ, ≤, –, · drawn from the fallback font
must not garble the text after them); no picture or PDF draws a glyph its font does not
have (``tests/conftest.py`` fails any test that does)."""

import html
import io
import re
from pathlib import Path

import pytest

from kinetostatics.cli import main
from kinetostatics.io.templates import NAMES as TEMPLATES
from tests.helpers import ROOT, motion_driven

pypdf = pytest.importorskip("pypdf")
pytest.importorskip("fpdf")

MOTION = motion_driven()  # the files the report handles
FAST = {("slider_crank", "zh")}  # the lists and ² of the Chinese report, in the default run


def _squash(text: str) -> str:
    return re.sub(r"\s+", "", text)


# a page's footer ("title — page 2/13", "title — 第 2 页，共 13 页"), drawn where the page
# breaks: inside the text of a paragraph that runs on to the next page
FOOTER = re.compile(r"^.* — (page \d+/\d+|第 \d+ 页，共 \d+ 页)$", re.MULTILINE)


def _pdf_text(path: Path, footers: bool = False) -> str:
    """The PDF's text, page after page, without the pages' footers unless asked."""
    reader = pypdf.PdfReader(str(path))
    text = "\n".join(page.extract_text() for page in reader.pages)
    return text if footers else FOOTER.sub("", text)


def _md_texts(md: str) -> list[str]:
    """The headings, paragraphs, list items and captions of a Markdown report, its markup
    taken off: ``#``, ``- ``, ``*emphasis*``, backticks, backslash escapes, entities."""
    texts = []
    for line in md.splitlines():
        line = line.strip()
        if not line or line.startswith(("|", "![")):
            continue
        line = re.sub(r"^#+ |^- ", "", line)
        if len(line) > 1 and line[0] == line[-1] == "*":
            line = line[1:-1]
        line = re.sub(r"\\(.)", r"\1", line.replace("`", ""))
        texts.append(html.unescape(line))
    return texts


def _has_cjk_font() -> bool:
    from kinetostatics.outputs import fonts, lang

    try:
        fonts.cjk_font()
    except lang.LanguageError:
        return False
    return True


def test_text_after_a_glyph_from_the_fallback_font_is_intact(tmp_path):
    """Bullets and lines ending with a glyph SimHei lacks (fpdf2 draws it from DejaVu
    Sans), followed by Chinese text: each item comes out of the PDF as written."""
    if not _has_cjk_font():
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    from kinetostatics.outputs.report.blocks import _Heading, _List, _Para
    from kinetostatics.outputs.report.pdf import write_pdf

    items = [
        "自由度：1",
        "加速度 m/s²",
        "μ_a = 0.04 (m/s²)/mm ≤ 5 – a·b，ω₃ 与 α₃",
        "转动惯量 kg·m²",
        "第三段 中文 " * 14 + "²",
        "之后的中文",
    ]
    blocks = [_Heading(1, "标题"), _List(items), _Para("段落 m/s²"), _Para("再一段中文")]
    path = write_pdf(blocks, tmp_path / "t.pdf", "t", "zh")
    flat = _squash(_pdf_text(path))
    for text in ["标题", "•" + items[0], *items, "段落 m/s²", "再一段中文"]:
        assert _squash(text) in flat, text
    footer = _squash(_pdf_text(path, footers=True))
    assert footer.endswith("t—第1页，共1页")  # the footer, in Chinese word order


def _cases():
    for name in MOTION:
        for lang in ("en", "zh"):
            slow = () if (name, lang) in FAST else pytest.mark.slow
            yield pytest.param(name, lang, marks=slow, id=f"{name}-{lang}")


def _assert_on_paper(path: Path, lang: str, tmp_path: Path) -> None:
    """The report of ``path`` in ``lang``, Markdown and PDF: every heading, paragraph and
    list item of the Markdown is in the PDF's text (the glyph check is conftest.py's)."""
    if lang == "zh" and not _has_cjk_font():
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    out = tmp_path / "out"
    args = ["report", str(path), "--out", str(out)]
    code = main([*args, "--dpi", "40", "--format", "md", "pdf", "--lang", lang])
    assert code == 0
    md = (out / "report.md").read_text(encoding="utf-8")
    flat = _squash(_pdf_text(out / "report.pdf"))
    texts = _md_texts(md)
    assert len(texts) > 30
    missing = [t for t in texts if _squash(t) not in flat]
    assert not missing, missing[:3]


@pytest.mark.parametrize("name, lang", list(_cases()))
def test_every_paragraph_and_list_item_is_on_paper(name, lang, tmp_path):
    _assert_on_paper(ROOT / "mechanisms" / f"{name}.yaml", lang, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("lang", ["en", "zh"])
@pytest.mark.parametrize("name", TEMPLATES)
def test_every_template_is_on_paper(name, lang, tmp_path):
    """The same for the file ``kinetostatics init`` writes from each template (row I)."""
    path = tmp_path / f"{name}.yaml"
    assert main(["init", name, "--out", str(path)]) == 0
    _assert_on_paper(path, lang, tmp_path)


def _picture(path: Path) -> Path:
    from PIL import Image

    Image.new("RGB", (60, 60), "white").save(path)
    return path


def _pages(path: Path) -> list[str]:
    return [_squash(p.extract_text()) for p in pypdf.PdfReader(str(path)).pages]


def test_chinese_lines_are_full_and_flush_left(tmp_path):
    """fpdf2 broke a Chinese paragraph at its spaces only: "由 kinetostatics" alone on a
    justified first line, widened to the margin. Broken between characters instead, the
    first line goes on past it; no line starts with a closing mark."""
    if not _has_cjk_font():
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    from kinetostatics.outputs.report.blocks import _Para
    from kinetostatics.outputs.report.pdf import write_pdf

    text = (
        "由 kinetostatics 进行动态静力分析（精确的位置、速度与加速度；达朗贝尔惯性力；"
        "牛顿–欧拉法求运动副反力；摩擦按近似解与一致解）。约定：x 向右，y 向上，"
        "角度与力矩以逆时针为正；运动副反力 F_ij 为构件 i 对构件 j 的作用力。" * 3
    )
    path = write_pdf([_Para(text)], tmp_path / "t.pdf", "t", "zh")
    lines = [ln for ln in pypdf.PdfReader(str(path)).pages[0].extract_text().splitlines()]
    assert "进行动态静力分析" in lines[0], lines[:2]
    assert len(lines) >= 4 and not any(ln.lstrip()[:1] in "，。、；：）" for ln in lines)
    assert _squash(text) in _squash("".join(lines))


def test_a_heading_goes_to_the_next_page_with_its_picture(tmp_path):
    from kinetostatics.outputs.report.blocks import _Heading, _Image, _Para
    from kinetostatics.outputs.report.pdf import write_pdf

    png = _picture(tmp_path / "p.png")
    filler = [_Para(f"Paragraph {k}. " + "Some words of text. " * 20) for k in range(9)]
    blocks = [
        *filler,
        _Heading(2, "7. Polygons"),
        _Image(png, "A drawing to scale.", 150.0, 150.0, true_scale=True),
    ]
    pages = _pages(write_pdf(blocks, tmp_path / "t.pdf", "t"))
    assert len(pages) == 2
    assert "7.Polygons" in pages[1] and "Adrawingtoscale." in pages[1], pages[0][-80:]


def test_a_curve_is_reduced_to_fit_the_rest_of_a_page(tmp_path):
    """A curve (not to scale) that fits the rest of the page at 75 % or more is placed
    there, not on the next page; a drawing to scale never is."""
    from kinetostatics.outputs.report.blocks import _Image, _Para
    from kinetostatics.outputs.report.pdf import write_pdf

    png = _picture(tmp_path / "p.png")
    filler = [_Para(f"Paragraph {k}. " + "Some words of text. " * 20) for k in range(6)]
    for true_scale, n_pages in ((False, 1), (True, 2)):
        blocks = [*filler, _Image(png, "A curve.", 165.0, 160.0, true_scale=true_scale)]
        path = write_pdf(blocks, tmp_path / f"{true_scale}.pdf", "t")
        pages = _pages(path)
        assert len(pages) == n_pages, true_scale
        assert "Paragraph5" in pages[0] and "Acurve." in pages[-1]


def test_a_chinese_name_in_an_english_report(tmp_path):
    """The English pictures and PDF fall back to the CJK font for a name written in
    Chinese (no empty box: the glyph check of conftest.py)."""
    if not _has_cjk_font():
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    text = (ROOT / "mechanisms" / "slider_crank.yaml").read_text(encoding="utf-8")
    path = tmp_path / "crank.yaml"
    path.write_text(re.sub(r"(?m)^name: .*$", "name: 曲柄滑块机构", text), encoding="utf-8")
    out = tmp_path / "out"
    args = ["report", str(path), "--out", str(out), "--dpi", "40", "--format", "md", "pdf"]
    assert main([*args, "--polygons", "2"]) == 0
    pages = _pages(out / "report.pdf")
    assert "曲柄滑块机构" in pages[0]
    assert all(p.endswith(f"page{k + 1}/{len(pages)}") for k, p in enumerate(pages))


def test_no_word_about_a_bold_face_the_cjk_font_does_not_have(caplog):
    """The point labels are bold; the CJK font has no bold face and its regular one
    stands in, without matplotlib's warning on every drawing (English and Chinese)."""
    if not _has_cjk_font():
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    import kinetostatics as ks
    from kinetostatics.outputs import plotting as pl

    result = ks.analyze(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"))
    for lang in ("en", "zh"):
        pl.draw_mechanism(result, row=0, lang=lang).savefig(io.BytesIO(), format="png")
    assert not [r for r in caplog.records if "font weight" in r.getMessage()]


def test_a_table_never_leaves_a_row_or_two_alone(tmp_path):
    """Wherever a 14-row table starts, a page holds none of its rows or at least 3, and
    the page after at least 2 (a table that fits is never split)."""
    from kinetostatics.outputs.report.blocks import _Para, _Table
    from kinetostatics.outputs.report.pdf import write_pdf

    rows = [[f"row{k:02d}", f"{k * 1.5:.4g}", "kg·m²"] for k in range(1, 15)]
    table = _Table(["quantity", "value", "unit"], rows, "Flywheel: result")
    seen = set()
    for n in range(28, 40):
        filler = [_Para(f"Line {k}.") for k in range(n)]
        pages = _pages(write_pdf([*filler, table], tmp_path / f"{n}.pdf", "t"))
        counts = [sum(f"row{k:02d}" in p for k in range(1, 15)) for p in pages]
        assert sum(counts) == 14, counts
        on = [c for c in counts if c]
        assert on[0] >= 3 and on[-1] >= 2, (n, counts)
        seen.add(len(on))
    assert seen == {1, 2}  # split, and moved or fitted whole, both met


def test_a_table_over_pages_keeps_every_cell_and_its_heading_row(tmp_path):
    """A table whose cells each fit one line (drawn a text per cell, not by fpdf2's
    table()) and runs over three pages: every cell on paper once, in order, and the
    heading row at the top of each page it is on; a table with a cell to wrap (drawn by
    fpdf2's table()) keeps its text too."""
    from kinetostatics.outputs.report.blocks import _Table
    from kinetostatics.outputs.report.pdf import write_pdf

    rows = [[f"r{k:03d}", f"{k * 0.125:.4g}", f"{-k * 7:.4g}"] for k in range(1, 151)]
    table = _Table(["row name", "value (mm)", "force (N)"], rows, "A long table")
    long_text = "a cell long enough to wrap " * 12
    wrapped = _Table(["item", "note"], [["x1", long_text], ["x2", "short"]], "A wrapped table")
    pages = _pages(write_pdf([table, wrapped], tmp_path / "t.pdf", "t"))
    on = [[k for k in range(1, 151) if f"r{k:03d}" in p] for p in pages]
    assert [k for page in on for k in page] == list(range(1, 151))  # each once, in order
    spans = [p for p, ks in zip(pages, on) if ks]
    assert len(spans) == 3, [len(ks) for ks in on]
    assert all("rowname" in p and "value(mm)" in p for p in spans)  # the heading row again
    assert "0.125" in pages[0] and "-1050" in spans[-1]
    assert _squash(long_text) in "".join(pages) and "short" in pages[-1]
