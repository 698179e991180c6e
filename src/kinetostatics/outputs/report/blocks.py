"""The report as a list of blocks (headings, paragraphs, lists, tables, images),
rendered to Markdown (images in files) and to self-contained HTML (images embedded,
printable on A4: drawings at their true size); ``pdf.py`` renders the same blocks."""

from __future__ import annotations

import base64
import html
from dataclasses import dataclass
from pathlib import Path

from ...errors import KinetostaticsError


class ReportError(KinetostaticsError, ValueError):
    """A report cannot be written as asked."""


@dataclass
class _Heading:
    level: int
    text: str


@dataclass
class _Para:
    text: str


@dataclass
class _Table:
    header: list[str]
    rows: list[list[str]]
    caption: str = ""


@dataclass
class _Image:
    path: Path  # inside the output folder
    caption: str
    width_mm: float = 0.0  # the figure's size on paper at 100 %
    height_mm: float = 0.0
    true_scale: bool = False  # a drawing or polygon to a stated scale


@dataclass
class _List:
    items: list[str]


# characters of a text that Markdown could read as markup beyond code spans and emphasis:
# raw HTML (tags, comments) and entities, written as character references (markup-neutral
# in and out of code spans, so however a text's backticks pair up it never holds a tag);
# links and images, their brackets escaped (a backslash too, so that none escapes
# another's escape); line breaks, which could start a block of their own.
_MD_TEXT = str.maketrans(
    {
        "&": "&amp;",
        "<": "&lt;",
        ">": "&gt;",
        "\\": "\\\\",
        "[": "\\[",
        "]": "\\]",
        "\n": " ",
        "\r": " ",
        "\u2028": " ",
        "\u2029": " ",
    }
)


def md_text(text: object) -> str:
    """``text`` safe in a Markdown report: every text of the report (a mechanism's
    ``name:``, the names of its links, joints and drivers, the program's own sentences)
    goes through here on its way into ``report.md`` (the HTML report escapes with
    ``html.escape``); its `code` spans stay code spans.

    >>> print(md_text("<script>x</script> [a](javascript:b)"))
    &lt;script&gt;x&lt;/script&gt; \\[a\\](javascript:b)
    """
    return str(text).translate(_MD_TEXT)


def _md_cell(s: object) -> str:
    return md_text(s).replace("|", "\\|")


def _to_markdown(blocks, out: Path) -> str:
    lines: list[str] = []
    for b in blocks:
        if isinstance(b, _Heading):
            lines += ["#" * b.level + " " + md_text(b.text), ""]
        elif isinstance(b, _Para):
            lines += [md_text(b.text), ""]
        elif isinstance(b, _List):
            lines += [f"- {md_text(item)}" for item in b.items] + [""]
        elif isinstance(b, _Table):
            if b.caption:
                lines += [f"*{md_text(b.caption)}*", ""]
            lines.append("| " + " | ".join(_md_cell(h) for h in b.header) + " |")
            lines.append("|" + "|".join("---" for _ in b.header) + "|")
            for r in b.rows:
                lines.append("| " + " | ".join(_md_cell(c) for c in r) + " |")
            lines.append("")
        elif isinstance(b, _Image):
            rel = b.path.relative_to(out).as_posix()
            caption = md_text(b.caption)
            lines += [f"![{caption}]({rel})", "", f"*{caption}*", ""]
    return "\n".join(lines).rstrip() + "\n"


_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,Arial,sans-serif;max-width:1100px;
margin:2em auto;padding:0 1em;color:#1d1d1d;line-height:1.45}
h1{border-bottom:2px solid #1f5fa8;padding-bottom:.2em}
h2{border-bottom:1px solid #ccc;padding-bottom:.15em;margin-top:1.8em}
table{border-collapse:collapse;font-size:.82em;margin:.6em 0 1.2em}
th,td{border:1px solid #d0d0d0;padding:.2em .45em;text-align:right;white-space:nowrap}
th{background:#eef3fa}
td:first-child,th:first-child{text-align:left}
figure{margin:1em 0}
figure img{max-width:100%;height:auto;border:1px solid #eee}
figcaption,.caption{font-size:.85em;color:#444;font-style:italic}
code{background:#f3f3f3;padding:0 .2em}
@page{size:A4;margin:14mm}
@media print{body{max-width:none;margin:0;padding:0;font-size:9pt}
table{font-size:7pt;page-break-inside:auto}tr{page-break-inside:avoid}
thead{display:table-header-group}figure{page-break-inside:avoid}
figure img{max-width:none;border:none}h2{page-break-after:avoid}}
"""


def _to_html(blocks, title: str, lang: str = "en") -> str:
    parts = [
        "<!DOCTYPE html>",
        f'<html lang="{"zh-CN" if lang == "zh" else "en"}"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title>",
        f"<style>{_CSS}</style></head><body>",
    ]
    for b in blocks:
        if isinstance(b, _Heading):
            parts.append(f"<h{b.level}>{html.escape(b.text)}</h{b.level}>")
        elif isinstance(b, _Para):
            parts.append(f"<p>{_inline(b.text)}</p>")
        elif isinstance(b, _List):
            parts.append("<ul>" + "".join(f"<li>{_inline(i)}</li>" for i in b.items) + "</ul>")
        elif isinstance(b, _Table):
            if b.caption:
                parts.append(f'<p class="caption">{html.escape(b.caption)}</p>')
            head = "".join(f"<th>{html.escape(h)}</th>" for h in b.header)
            body = "".join(
                "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>"
                for r in b.rows
            )
            parts.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
        elif isinstance(b, _Image):
            data = base64.b64encode(b.path.read_bytes()).decode("ascii")
            size = f' style="width:{b.width_mm:.2f}mm"' if b.width_mm else ""
            parts.append(
                f'<figure><img alt="{html.escape(b.caption)}"{size} '
                f'src="data:image/png;base64,{data}">'
                f"<figcaption>{html.escape(b.caption)}</figcaption></figure>"
            )
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def _inline(text: str) -> str:
    """Escape, then turn `code` spans into <code>."""
    out, code = [], False
    for piece in text.split("`"):
        out.append(f"<code>{html.escape(piece)}</code>" if code else html.escape(piece))
        code = not code
    return "".join(out)
