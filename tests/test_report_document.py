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


def test_the_renderer_writes_the_same_markdown_for_typed_blocks_and_the_older_tuples():
    # the chain's store section still builds tuples: both forms must give one text, byte for byte
    tuples = [("h1", "Study report: 'x'"), ("p", "units: $\\nu$ in V0."), ("h2", "Store s"),
              ("table", ["law", "points"], [["carlson-langer", "3"]]), ("h3", "Law carlson-langer"),
              ("ul", ["one", "two"])]
    assert _markdown(_tree()) == _markdown(tuples)
    assert _markdown(_tree()) == ("# Study report: 'x'\n\nunits: $\\nu$ in V0.\n\n## Store s\n\n"
                                  "| law | points |\n|---|---|\n| carlson-langer | 3 |\n\n"
                                  "### Law carlson-langer\n\n- one\n- two\n")


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
