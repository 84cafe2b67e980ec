"""A report is a tree of typed blocks (report.document) that one renderer turns into Markdown and HTML."""

import pytest

from bifurcation.report.document import Figure, Heading, Items, Paragraph, Section, Table, flatten
from bifurcation.report.document import to_html as _html, to_markdown as _markdown


def _tree():
    return [Heading("Study report: 'x'", 1), Paragraph("units: $\\nu$ in V0."),
            Section("Store s", [Table(["law", "points"], [["carlson-langer", "3"]]),
                                Section("Law carlson-langer", [Items(["one", "two"])], level=3)])]


def test_a_section_reads_as_its_heading_then_its_blocks():
    leaves = flatten(_tree())
    assert [type(b).__name__ for b in leaves] == ["Heading", "Paragraph", "Heading", "Table", "Heading", "Items"]
    assert [(b.text, b.level) for b in leaves if isinstance(b, Heading)] == \
        [("Study report: 'x'", 1), ("Store s", 2), ("Law carlson-langer", 3)]


def test_the_renderer_writes_the_markdown_of_the_tree_and_refuses_what_is_not_a_block():
    assert _markdown(_tree()) == ("# Study report: 'x'\n\nunits: $\\nu$ in V0.\n\n## Store s\n\n"
                                  "| law | points |\n|---|---|\n| carlson-langer | 3 |\n\n"
                                  "### Law carlson-langer\n\n- one\n- two\n")
    # the older ("table", head, rows) tuples are gone: every report builds typed blocks
    with pytest.raises(TypeError, match="not a report block"):
        _markdown([("p", "text")])


def test_html_embeds_the_figure_and_takes_its_title_from_the_first_heading(tmp_path):
    (tmp_path / "f.png").write_bytes(b"\x89PNG")
    page = _html([Heading("T", 1), Figure("f.png", "a caption")], tmp_path)
    assert "<title>T</title>" in page and 'src="data:image/png;base64,iVBORw==' in page
    assert "<figcaption>a caption</figcaption>" in page


def test_blocks_check_themselves():
    with pytest.raises(ValueError, match="Table row 1 has 1 cells for 2 columns"):
        Table(["a", "b"], [["1", "2"], ["3"]])
    with pytest.raises(ValueError, match="Heading level 4: use 1, 2 or 3"):
        Heading("x", 4)
    with pytest.raises(TypeError, match="not a report block"):
        flatten(["a bare string"])


def _every_kind_of_block(tmp_path):
    """A document with each kind of block: nested sections, a narrow table and a wide one (drawn as cards
    in HTML, with a verdict tag), a cell holding '|', a list, a figure with and one without a caption."""
    from bifurcation.report import figures as F

    fig, axes = F._figure(2.0, 1.5)
    axes[0][0].plot([0, 1], [1, 0])
    F.save(fig, tmp_path / "a_figure.png")
    (tmp_path / "b.png").write_bytes((tmp_path / "a_figure.png").read_bytes() + b"\0")   # other bytes
    wide = "a cell long enough that the table reads better as one card per row, " * 2
    return [Heading("Report of every kind of block: ν_f and $x^2$", 1), Paragraph("two lines\nof one paragraph"),
            Items(["one", "two", "three"]),
            Section("Tables", [Table(["law", "max |T/T0 − 1|"], [["aging", "1e-13"], ["slip", "2e-13"]]),
                               Section("Cards", [Table(["claim", "paper", "measured", "verdict"],
                                                       [["Eq. 12", wide, wide, "confirmed"],
                                                        ["Eq. 19", wide, wide, "refuted"]])], level=3)]),
            Section("Figures", [Figure("a_figure.png", "Δ against ν_f"), Figure("b.png", alt="no caption")])]


def test_markdown_and_html_of_one_document_have_the_outline_of_its_blocks(tmp_path):
    from _report_outline import from_blocks, from_html, from_markdown

    blocks = _every_kind_of_block(tmp_path)
    expected = from_blocks(blocks, tmp_path)
    assert [k[0] for k in expected] == ["h", "p", "ul", "h", "table", "h", "table", "h", "figure", "figure"]
    assert from_markdown(_markdown(blocks), tmp_path) == expected
    assert from_html(_html(blocks, tmp_path)) == expected
    page = _html(blocks, tmp_path)
    assert page.count('<div class="card">') == 2 and '<span class="tag">refuted</span>' in page
    assert '<img alt="no caption"' in page and '<img alt="a figure"' in page


def test_a_cell_with_a_bar_stays_one_cell(tmp_path):
    # a raw '|' inside a cell gave the rate-state report header rows of 13 cells over 9 columns
    md = _markdown([Table(["x", "|T − 1|"], [["1", "|a|"]])])
    assert md == "| x | \\|T − 1\\| |\n|---|---|\n| 1 | \\|a\\| |\n"
    from _report_outline import from_markdown

    assert from_markdown(md, tmp_path) == [("table", 2, 1)]
    with pytest.raises(AssertionError, match="other than 2 cells"):
        from_markdown("| x | |T − 1| |\n|---|---|\n", tmp_path)


def test_html_renders_the_inline_markdown_the_reports_write_and_no_other_link(tmp_path):
    page = _html([Heading("T", 1), Paragraph("**bold ν_f**, `x_i < 2`, [data](data.json), [x](javascript:alert(1))"),
                  Table(["a", "b"], [["**yes**", "`q`"]])], tmp_path)
    assert "<strong>bold ν<sub>f</sub></strong>" in page and "<code>x_i &lt; 2</code>" in page
    assert '<a href="data.json">data</a>' in page
    assert "javascript" in page and 'href="javascript' not in page   # left as text, never a link
    assert "<td><strong>yes</strong></td><td><code>q</code></td>" in page and "**" not in page


def test_a_cell_holds_no_raw_html_and_no_line_break(tmp_path):
    # labels come from workflows: a branch "prz <fast>" rendered as an unknown tag (GitHub shows nothing of
    # it), "&amp;" as "&", a "\r" split the row; "σ < 1", "a & b" and "<1e-13" stay as they are
    md = _markdown([Table(["branch", "note"], [["prz <fast>", "&amp; x"], ["σ < 1, <1e-13", "a & b\r\nc"]])])
    assert md.splitlines()[2:] == ["| prz &lt;fast> | &amp;amp; x |", "| σ < 1, <1e-13 | a & b c |"]
    from _report_outline import from_markdown

    assert from_markdown(md, tmp_path) == [("table", 2, 2)]
