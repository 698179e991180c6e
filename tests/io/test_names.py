"""The student's own names (issue 37, item 6): names in any script (曲柄, 导杆, 切削力) for
links, joints, points, loads, drivers and parameters, everywhere a name is used, and the
files written with them valid UTF-8 whatever the locale.

The truth is an identity: the shaper with Chinese names is the shipped shaper renamed,
so every result column of the one is the same number as the renamed column of the other.
"""

import csv
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base.expressions import ExpressionError, evaluate
from kinetostatics.base.names import SCHEMA_PATTERN
from kinetostatics.batch.objectives import Expression
from kinetostatics.cli import main
from kinetostatics.errors import ModelError

ROOT = Path(__file__).resolve().parents[2]
SHAPER = ROOT / "mechanisms" / "shaper.yaml"

# the shaper's own names -> a student's Chinese names (links, joints, driver, load, points,
# parameters); `link` is also a key (loads.cutting.link), renamed only where it is a name
RENAME = {
    "frame": "机架",
    "crank": "曲柄",
    "block": "滑块",
    "lever": "导杆",
    "link": "连杆",
    "ram": "刨头",
    "slot": "导槽",
    "guide": "导轨",
    "motor": "电机",
    "cutting": "切削力",
    "tool": "刀尖",
    "ram_guide": "导路点",
    "L_O2A": "曲柄长",
    "G6": "刨头重",
}


def chinese_text(positions: int | None = None) -> str:
    """The shipped shaper with RENAME applied to its names (not to its keys)."""
    text = SHAPER.read_text(encoding="utf-8")
    text = re.sub(r"(?m)^name: .*$", "name: 牛头刨床", text)
    for old, new in RENAME.items():
        # a name: not part of a longer name; `link` also a key (`link: ram` in a load)
        pattern = rf"(?<![\w.]){re.escape(old)}(?![\w])"
        if old == "link":
            pattern = r"(?m)(?<![\w.])link(?=[,\]]|:[ \t]*(?:#.*)?$)"
        text, n = re.subn(pattern, new, text)
        assert n, old
    if positions:
        text, n = re.subn(r"positions: 360", f"positions: {positions}", text)
        assert n == 1
    return text


def renamed(column: str) -> str:
    """The column's name in the Chinese file (a group's columns join its links by _)."""
    member, _, rest = column.partition(".")
    member = (
        "_".join(RENAME.get(p, p) for p in member.split("_"))
        if member not in RENAME
        else RENAME[member]
    )
    return ".".join([member] + [RENAME.get(p, p) for p in rest.split(".")] if rest else [member])


def test_chinese_names_give_the_same_numbers_as_ascii_names():
    ascii_result = ks.analyze(ks.load(SHAPER))
    model = ks.loads(chinese_text(), file="牛头刨床.yaml")
    assert model.name == "牛头刨床"
    assert {lk.name for lk in model.links} == {"机架", "曲柄", "滑块", "导杆", "连杆", "刨头"}
    result = ks.analyze(model)
    assert set(result.columns) == {renamed(c) for c in ascii_result.columns}
    assert "导杆.omega" in result.columns and "导轨.Fx" in result.columns
    assert "刨头.刀尖.vx" in result.columns and "电机.torque" in result.columns
    by_unit: dict[str, float] = {}
    for c in ascii_result.columns:
        v = np.abs(np.asarray(ascii_result[c], dtype=float))
        if np.any(np.isfinite(v)):
            u = ascii_result.units[c]
            by_unit[u] = max(by_unit.get(u, 0.0), float(np.nanmax(v)))
    for c in ascii_result.columns:
        a = np.asarray(ascii_result[c], dtype=float)
        b = np.asarray(result[renamed(c)], dtype=float)
        assert np.array_equal(np.isnan(a), np.isnan(b)), c
        scale = 1e-12 * max(by_unit.get(ascii_result.units[c], 0.0), 1e-300)
        assert np.nanmax(np.abs(a - b), initial=0.0) <= scale, c


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("main-motor", "{joint: O2, motion: {speed: 60}}", "e.g. 'main_motor'"),
        ("2电机", "{joint: O2, motion: {speed: 60}}", "e.g. '_2电机'"),
        ("电 机", "{joint: O2, motion: {speed: 60}}", "e.g. '电_机'"),
        ("ﬁ", "{joint: O2, motion: {speed: 60}}", "e.g. 'fi'"),  # NFKC: the parser's 'fi'
    ],
)
def test_a_name_that_is_not_a_name_is_one_line_with_a_valid_one(key, value, message):
    text = SHAPER.read_text(encoding="utf-8").replace(
        "  motor: {joint: O2, motion: {speed: 60}}", f"  {key}: {value}"
    )
    with pytest.raises(ModelError) as err:
        ks.loads(text, file="shaper.yaml")
    lines = str(err.value).splitlines()
    assert len(lines) == 1 and f"drivers.{key}" in lines[0] and message in lines[0], lines


def test_a_parameter_may_not_be_a_keyword_but_a_link_may():
    text = SHAPER.read_text(encoding="utf-8").replace("  G4: 200", "  lambda: 200")
    with pytest.raises(ModelError, match=r"parameters.lambda: .*Python keyword.*'lambda_'"):
        ks.loads(text, file="shaper.yaml")
    text = re.sub(r"(?<![\w.])ram(?![\w])", "if", SHAPER.read_text(encoding="utf-8"))
    assert "if.omega" in ks.analyze(ks.loads(text)).columns  # a column, not an expression


def test_expressions_take_names_in_any_script_and_nothing_else_beyond_ascii():
    assert evaluate("2*曲柄长 + 导杆长", {"曲柄长": 3.0, "导杆长": 4.0}) == 10.0
    for text, ch in (("100*ℯ", "ℯ"), ("a×b", "×"), ("１+2", "１"), ("a\u0301", "\u0301")):
        with pytest.raises(ExpressionError, match=f"U\\+{ord(ch):04X}"):
            evaluate(text, {"a": 1.0, "b": 2.0, "e": 3.0})
    e = Expression("刨头.stroke*2 + 曲柄长")
    assert set(e.names.values()) == {"刨头.stroke", "曲柄长"}
    assert e.value({"刨头.stroke": 0.25, "曲柄长": 1.0}) == 1.5


def test_the_schema_pattern_takes_the_loaders_names():
    pattern = re.compile(SCHEMA_PATTERN)
    assert SCHEMA_PATTERN.isascii()  # escapes that ECMA-262 and Python's re read alike
    for name in ("曲柄", "O2", "_x", "F_切削", "导杆4"):
        assert pattern.search(name), name
    for name in ("main-motor", "2A", "a.b", "a b", "曲柄 ", "", "x+y", "ram(1)"):
        assert not pattern.search(name), name
    jsonschema = pytest.importorskip("jsonschema")
    import yaml

    schema = json.loads(
        (ROOT / "src/kinetostatics/io/mechanism.schema.json").read_text(encoding="utf-8")
    )
    validator = jsonschema.Draft202012Validator(schema)
    assert not list(validator.iter_errors(yaml.safe_load(chinese_text())))
    broken = yaml.safe_load(chinese_text().replace("  导槽:", "  导 槽:"))
    assert [e.message for e in validator.iter_errors(broken)] == [
        "'导 槽' does not match " + repr(SCHEMA_PATTERN)
    ]


ASCII_LOCALE = {"LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0", "PYTHONCOERCECLOCALE": "0"}


def test_run_writes_utf8_under_an_ascii_locale(tmp_path):
    """A terminal or locale without Chinese: the files are still UTF-8 with the names,
    the output escapes what the terminal cannot show, and nothing stops."""
    path = tmp_path / "牛头刨床.yaml"
    path.write_text(chinese_text(positions=36), encoding="utf-8")
    env = {**os.environ, **ASCII_LOCALE, "PYTHONPATH": str(ROOT / "src")}
    for verb in (["check"], ["run", "--out", str(tmp_path / "out")]):
        done = subprocess.run(
            [sys.executable, "-m", "kinetostatics.cli", verb[0], str(path), *verb[1:]],
            env=env,
            capture_output=True,
        )
        assert done.returncode == 0, done.stderr.decode(errors="replace")
        assert b"\\u725b\\u5934\\u5228\\u5e8a" in done.stdout  # 牛头刨床, escaped
    lines = (tmp_path / "out" / "results.csv").read_text(encoding="utf-8").splitlines()
    assert "导杆.omega" in next(csv.reader([lines[1]]))
    summary = (tmp_path / "out" / "summary.json").read_text(encoding="utf-8")
    assert json.loads(summary)["name"] == "牛头刨床" and "牛头刨床" in summary  # not \u escapes


def test_batch_sweeps_a_chinese_parameter_and_best_reads_it_back(tmp_path, capsys):
    path = tmp_path / "牛头刨床.yaml"
    path.write_text(chinese_text(positions=36), encoding="utf-8")
    out = tmp_path / "batch"
    assert main(["batch", str(path), "--out", str(out), "--set", "曲柄长=100,110", "--serial"]) == 0
    with open(out / "summary.csv", encoding="utf-8", newline="") as fh:
        rows = [r for r in csv.reader(fh) if not r[0].startswith("#")]
    header, body = rows[0], rows[1:]
    assert "曲柄长" in header and "导轨.stroke" in header and len(body) == 2
    # the ram's stroke H = 2·L_O3B·L_O2A/L_O2O3 (docs: the shaper's closed form)
    strokes = sorted(float(r[header.index("导轨.stroke")]) for r in body)
    assert strokes == pytest.approx([2 * 0.540 * a / 0.380 for a in (0.100, 0.110)], rel=1e-9)
    capsys.readouterr()
    assert main(["best", str(out), "--best", "max 导轨.stroke"]) == 0
    assert "110" in capsys.readouterr().out


# -- item 7: the textbook's link numbers (number:) ---------------------------------------
# the shaper's guide numbers its links so (mechanisms/shaper.yaml's number: keys)
GUIDE = {"frame": 1, "crank": 2, "block": 3, "lever": 4, "link": 5, "ram": 6}


def _shaper(text: str | None = None, **numbers: int | None) -> ks.Model:
    """The shaper with each link's number: line set to ``numbers`` (None: removed)."""
    text = text or SHAPER.read_text(encoding="utf-8")
    for link, n in numbers.items():
        pattern = rf"(?m)^(  {link}:[^\n]*\n)    number: \d+\n"
        text, k = re.subn(pattern, rf"\g<1>    number: {n}\n" if n else r"\g<1>", text)
        assert k == 1, link
    return ks.loads(text, file="shaper.yaml")


def test_the_links_carry_the_numbers_of_the_file():
    from kinetostatics.outputs.labels import link_numbers
    from kinetostatics.structure.system import system_of

    assert link_numbers(system_of(ks.load(SHAPER))) == GUIDE
    none = _shaper(**dict.fromkeys(GUIDE))  # no number: the model's order, the frame last
    assert link_numbers(system_of(none)) == {
        "crank": 1,
        "block": 2,
        "lever": 3,
        "link": 4,
        "ram": 5,
        "frame": 6,
    }
    some = _shaper(**{k: None for k in GUIDE if k != "lever"})  # the others: numbers not given
    assert link_numbers(system_of(some)) == {
        "crank": 1,
        "block": 2,
        "lever": 4,
        "link": 3,
        "ram": 5,
        "frame": 6,
    }


@pytest.mark.parametrize(
    "number, message",
    [
        ("2", "links.block.number: number 2 is already the number of link 'crank'"),
        ("2.5", "links.block.number: a link's number must be a whole number from 1 to 99, got 2.5"),
        ("0", "links.block.number: a link's number must be a whole number from 1 to 99, got 0"),
        ("-3", "links.block.number: a link's number must be a whole number from 1 to 99, got -3"),
        ("100", "a whole number from 1 to 99, got 100"),
        ("three", "links.block.number: undefined parameter 'three'"),
    ],
)
def test_a_wrong_number_is_one_line_naming_its_key(tmp_path, capsys, number, message):
    text = SHAPER.read_text(encoding="utf-8").replace("    number: 3\n", f"    number: {number}\n")
    path = tmp_path / "shaper.yaml"
    path.write_text(text, encoding="utf-8")
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and "Traceback" not in err[0], err


def test_the_pictures_and_the_report_name_reactions_by_the_numbers():
    """F_Rij is the force of link i on link j, with the guide's numbers: the crank 2 on the
    block 3 at A is F_R23, the lever 4 on the link 5 at B F_R45."""
    from kinetostatics.outputs.plotting.draw import _loads_at

    result = ks.analyze(ks.load(SHAPER))
    labels = {a.label for a in _loads_at(result, 0)}
    assert {"F_R12", "F_R23", "F_R43", "F_R14", "F_R45", "F_R56", "F_R16"} <= labels
    assert {"F_I4", "M_I4", "G4", "F_I6", "G6"} <= labels  # lever 4, ram 6
    from kinetostatics.outputs.report.data import _data_blocks

    tables = {
        t.header[0]: t
        for t in _data_blocks(result.system.model, result.system)
        if hasattr(t, "header")
    }
    joints = {r[0]: r[3] for r in tables["joint"].rows}
    assert joints == {
        "O2": "F_R12",
        "A": "F_R23",
        "slot": "F_R43",
        "O3": "F_R14",
        "B": "F_R45",
        "C": "F_R56",
        "guide": "F_R16",
    }
    links = [(r[0], int(r[1])) for r in tables["link"].rows]
    assert links == sorted(GUIDE.items(), key=lambda kv: kv[1])  # in the numbers' order


def test_two_digit_numbers_are_separated():
    from kinetostatics.outputs.labels import pair

    assert pair(2, 3) == "23" and pair(10, 11) == "10,11" and pair(1, 12) == "1,12"


# -- item 8: the quantities in Chinese with the member's name or number -------------------
def _tables(md: str) -> list[list[list[str]]]:
    """The Markdown tables of a report with a 'CSV row' column: rows of cells."""
    from tests.outputs.test_report import _md_tables

    return [t for t in _md_tables(md) if len(t[0]) > 1 and t[0][1] == "CSV row"]


DOTTED_COLUMN = re.compile(r"[^\W\d]\w*\.[^\W\d|]")  # lever.omega, crank.A.x, O2.|F|


@pytest.fixture(scope="module")
def chinese_reports(tmp_path_factory):
    """The Chinese report (Markdown, HTML) of the Chinese shaper (names and the guide's
    numbers); the PDF test adds the English one."""
    folder = tmp_path_factory.mktemp("cn")
    path = folder / "牛头刨床.yaml"
    path.write_text(chinese_text(positions=72), encoding="utf-8")
    out = {lang: folder / lang for lang in ("zh", "en")}
    args = ["report", str(path), "--out", str(out["zh"]), "--dpi", "30", "--lang", "zh"]
    assert main([*args, "--format", "md", "html"]) == 0
    return path, out


def test_the_chinese_tables_name_quantity_member_and_symbol(chinese_reports):
    from kinetostatics.outputs.plotting import analyze_for_pictures, course_positions
    from kinetostatics.outputs.report.results import report_tables

    path, out = chinese_reports
    zh = _tables((out["zh"] / "report.md").read_text(encoding="utf-8"))
    heads = [h for t in zh for h in t[0][2:]]
    assert len(zh) > 5
    assert not [h for h in heads if DOTTED_COLUMN.search(h)], heads  # no `导杆.omega`
    assert not [h for h in heads if re.search(r"[A-Za-z]{4,}", h)], heads  # no English word
    # the guide's numbers: the lever 4 (导杆), the link 5 (连杆); B joins them, 4 on 5
    for head in ("构件4 ", " ω₄ (rad/s)", " α₄ (rad/s²)", " θ₄ (°)", "B ", " F_R45x (N)"):
        assert any(head in h for h in heads), head
    assert any(h.startswith("构件4 ") and h.endswith(" ω₄ (rad/s)") for h in heads)
    frame_on_ram = [h for h in heads if h.startswith("导轨 ") and h.endswith(" F_R16y (N)")]
    assert frame_on_ram  # the frame 1 on the ram 6
    # the same numbers as the English tables, whose heads are the CSV's columns
    result = analyze_for_pictures(ks.load(path))
    rows = course_positions(result)
    tables = {lang: report_tables(result, rows, lang) for lang in ("zh", "en")}
    assert [t.header for t in tables["zh"]] == [t[0] for t in zh]
    for t_zh, t_en in zip(tables["zh"], tables["en"]):
        assert t_zh.rows == t_en.rows and len(t_zh.header) == len(t_en.header)
        assert any(DOTTED_COLUMN.search(h) for h in t_en.header[3:])


def test_the_report_shows_the_names_as_written(chinese_reports):
    _, out = chinese_reports
    md = (out["zh"] / "report.md").read_text(encoding="utf-8")
    assert md.splitlines()[0].endswith("牛头刨床")  # the title: the file's name:
    html = (out["zh"] / "report.html").read_text(encoding="utf-8")
    assert "<title>" in html and "牛头刨床" in html.split("</title>")[0]
    for name in ("曲柄", "导杆", "导槽", "导轨", "电机", "切削力", "曲柄长"):
        assert name in md, name
    joints = dict(
        (r[0].strip(), r[3].strip())
        for r in (line.strip("|").split("|") for line in md.splitlines() if "→" in line)
        if len(r) == 6
    )
    assert joints["导槽"] == "F_R43" and joints["导轨"] == "F_R16" and joints["A"] == "F_R23"


def test_column_labels_in_both_languages():
    from kinetostatics.outputs.labels import column_label

    result = ks.analyze(ks.loads(chinese_text(positions=12)))
    system = result.system
    assert column_label(system, "导杆.omega", "en") == "link 4 angular velocity ω₄"
    assert column_label(system, "导杆.B.vx", "en") == "point B velocity v_Bx"
    assert column_label(system, "B.Fx_friction", "en") == "B reaction (with friction) F_R45x"
    assert column_label(system, "导槽.N", "en") == "导槽 normal force N43"
    assert column_label(system, "电机.torque", "en") == "电机 driving torque M_b"
    zh = column_label(system, "导杆.omega", "zh")
    assert zh.startswith("构件4 ") and zh.endswith(" ω₄") and not re.search("[A-Za-z]{2}", zh)
    assert column_label(system, "导杆_刨头.cond", "zh") == "导杆_刨头.cond"  # not a quantity
    # without number: the link's own name, the subscript its number in the pictures
    plain = ks.analyze(ks.loads(re.sub(r"(?m)^    number: \d+\n", "", chinese_text(12))))
    label = column_label(plain.system, "导杆.omega", "zh")
    assert label.startswith("导杆 ") and label.endswith(" ω₃")


def test_the_chinese_pictures_say_the_quantities():
    import kinetostatics.outputs.plotting as pl

    result = pl.analyze_for_pictures(ks.loads(chinese_text(positions=72)))

    def texts(fig):
        return [t.get_text() for t in fig.findobj(lambda o: hasattr(o, "get_text"))]

    fig = pl.plot_result(result, "导杆.omega", "导轨.Fx", lang="zh")
    legend = [t for ax in fig.axes if ax.get_legend() for t in texts(ax.get_legend())]
    assert any(t.startswith("构件4 ") and t.endswith(" ω₄") for t in legend), legend
    assert any(t.startswith("导轨 ") and t.endswith(" F_R16x") for t in legend), legend
    title = " ".join(texts(pl.motion_diagram(result, lang="zh")))
    assert "牛头刨床" in title and not DOTTED_COLUMN.search(title), title
    row = pl.row_at(result, label="7")
    for kind in ("velocity", "acceleration"):  # 刀尖 is no mathtext: its font has no 刀
        words = texts(pl.polygon_figure(result, kind, row=row, lang="zh"))
        maths = [m for w in words for m in w.split("$")[1::2]]  # the $…$ parts
        assert maths and not [m for m in maths if re.search(r"[\u4e00-\u9fff]", m)], maths


# -- done when: a Chinese file with the textbook's numbers through every command -----------
def test_a_chinese_file_runs_through_every_command(tmp_path, capsys):
    path = tmp_path / "牛头刨床.yaml"
    path.write_text(chinese_text(positions=36), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["check", str(path)]) == 0
    assert "RPR" in capsys.readouterr().out
    assert main(["run", str(path), "--out", str(out / "run")]) == 0
    header = (out / "run" / "results.csv").read_text(encoding="utf-8").splitlines()[1]
    assert "导杆.omega" in header and "导槽.Fx" in header and "电机.torque" in header
    for lang in ("zh", "en"):
        args = ["plot", str(path), "--out", str(out / f"plot_{lang}"), "--lang", lang]
        assert main([*args, "--what", "drawing", "reactions", "--forces", "--dpi", "30"]) == 0
        assert {p.name for p in (out / f"plot_{lang}").iterdir()} == {
            "drawing.png",
            "reactions.png",
        }
    batch = out / "batch"
    assert main(["batch", str(path), "--out", str(batch), "--set", "曲柄长=100,110"]) == 0
    assert "导轨.stroke" in (batch / "summary.csv").read_text(encoding="utf-8")
    assert main(["export", str(path), "--format", "svg", "--out", str(out / "牛头刨床.svg")]) == 0
    assert (out / "牛头刨床.svg").stat().st_size > 0
    ezdxf = pytest.importorskip("ezdxf")
    dxf = out / "牛头刨床.dxf"
    assert main(["export", str(path), "--format", "dxf", "--out", str(dxf)]) == 0
    texts = " ".join(e.dxf.text for e in ezdxf.readfile(dxf).modelspace().query("TEXT"))
    assert "O2" in texts


@pytest.mark.slow
def test_the_pdf_reports_of_a_chinese_file_carry_its_names_and_numbers(chinese_reports):
    """The PDF in both languages (slow: fonts and pictures): the names, the numbers and
    the reactions F_Rij as the Markdown has them."""
    pypdf = pytest.importorskip("pypdf")
    path, out = chinese_reports
    for lang in ("zh", "en"):
        pdf = out[lang].parent / f"pdf_{lang}"
        args = ["report", str(path), "--out", str(pdf), "--dpi", "60", "--lang", lang]
        assert main([*args, "--format", "pdf"]) == 0
        text = " ".join(p.extract_text() for p in pypdf.PdfReader(str(pdf / "report.pdf")).pages)
        text = re.sub(r"\s+", " ", text)
        for word in ("牛头刨床", "曲柄", "导杆", "导轨", "F_R45", "F_R16"):
            assert word in text, (lang, word)
        if lang == "zh":
            assert "构件4" in text and "ω₄" in text
    for lang in ("zh", "en"):
        args = ["plot", str(path), "--out", str(out[lang].parent / f"plots_{lang}"), "--lang", lang]
        assert main([*args, "--dpi", "40"]) == 0
