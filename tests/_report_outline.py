"""Shared by the report tests (imported as ``_report_outline``): the outline of a report — its headings,
paragraphs, lists, tables and figures in reading order — read back from the Markdown and from the HTML
with none of the renderer's code, so a test can check that the two formats of one document say the same
thing and match the typed blocks it was built from.

An outline is a list of tuples: ``("h", level)``, ``("p",)``, ``("ul", items)``, ``("table", columns,
rows)``, ``("figure", sha256 of the PNG, has caption)``. Text is not compared: the HTML writes inline
math as markup (ν_f → ν<sub>f</sub>).
"""

from __future__ import annotations

import base64
import hashlib
import re
from html.parser import HTMLParser
from pathlib import Path

__all__ = ["from_blocks", "from_html", "from_markdown"]


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:16]


def from_blocks(blocks, figure_dir) -> list:
    """The outline the typed ``blocks`` should render to (figures read from ``figure_dir``)."""
    from bifurcation.report.document import Figure, Heading, Items, Paragraph, Table, flatten

    out = []
    for b in flatten(blocks):
        if isinstance(b, Heading):
            out.append(("h", b.level))
        elif isinstance(b, Paragraph):
            out.append(("p",))
        elif isinstance(b, Items):
            out.append(("ul", len(b.items)))
        elif isinstance(b, Table):
            out.append(("table", len(b.head), len(b.rows)))
        elif isinstance(b, Figure):
            out.append(("figure", _sha((Path(figure_dir) / b.file).read_bytes()), bool(b.caption)))
    return out


_CELL = re.compile(r"(?<!\\)\|")


def _cells(line: str) -> int:
    """Cells of a Markdown table row, an escaped ``\\|`` inside a cell not counting as a border."""
    return len(_CELL.split(line.strip())) - 2


def from_markdown(text: str, figure_dir) -> list:
    """The outline of a Markdown report whose blocks are separated by blank lines. A table row with
    another number of cells than its header is an error (GitHub would not draw the table)."""
    chunks = [c for c in text.split("\n\n") if c.strip()]
    out, i = [], 0
    while i < len(chunks):
        chunk = chunks[i].strip("\n")
        lines = chunk.split("\n")
        if m := re.match(r"(#{1,6}) ", chunk):
            out.append(("h", len(m.group(1))))
        elif chunk.startswith("| ") and len(lines) > 1 and re.fullmatch(r"\|(---\|)+", lines[1]):
            columns = lines[1].count("---")
            bad = [line for line in lines if _cells(line) != columns and line != lines[1]]
            assert not bad, f"a table row with other than {columns} cells: {bad[0]!r}"
            out.append(("table", columns, len(lines) - 2))
        elif chunk.startswith("- "):
            out.append(("ul", len(lines)))
        elif m := re.fullmatch(r"!\[[^\]]*\]\(([^)]+)\)", chunk):
            caption = i + 1 < len(chunks) and re.fullmatch(r"\*[^\n]+\*", chunks[i + 1].strip("\n")) is not None
            out.append(("figure", _sha((Path(figure_dir) / m.group(1)).read_bytes()), caption))
            i += caption
        else:
            out.append(("p",))
        i += 1
    return out


class _Outline(HTMLParser):
    def __init__(self):
        super().__init__()
        self.out: list = []
        self.stack: list[str] = []
        self.cards: list[int] = []      # columns of each card of the run of cards being read (one table)
        self.rows = self.columns = self.items = 0
        self.caption = False
        self.figure = ""

    def _end_cards(self):
        if self.cards:
            self.out.append(("table", self.cards[0], len(self.cards)))
            self.cards = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        in_card = "card" in self.stack
        if tag == "div" and attrs.get("class") == "card":
            self.cards.append(1)        # its title cell; each <dt> and the tag add one
            self.stack.append("card")
            return
        if in_card:
            if tag == "dt" or (tag == "span" and attrs.get("class") == "tag"):
                self.cards[-1] += 1
        elif tag in ("h1", "h2", "h3", "p", "ul", "table", "figure"):
            self._end_cards()
            if tag[0] == "h":
                self.out.append(("h", int(tag[1])))
            elif tag == "p" and "body" in self.stack:
                self.out.append(("p",))
            self.rows = self.columns = self.items = 0
            self.caption, self.figure = False, ""
        elif tag == "tr":
            self.rows += 1
        elif tag == "th":
            self.columns += 1
        elif tag == "li":
            self.items += 1
        elif tag == "img":
            head, _, data = attrs["src"].partition(",")
            assert head == "data:image/png;base64", head
            self.figure = _sha(base64.b64decode(data))
        elif tag == "figcaption":
            self.caption = True
        if tag in ("body", "ul", "table", "figure"):
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag == "div" and self.stack and self.stack[-1] == "card":
            self.stack.pop()
        elif tag in ("body", "ul", "table", "figure") and self.stack and self.stack[-1] == tag:
            self.stack.pop()
            if tag == "ul":
                self.out.append(("ul", self.items))
            elif tag == "table":
                self.out.append(("table", self.columns, self.rows - 1))   # the first row is the header
            elif tag == "figure":
                self.out.append(("figure", self.figure, self.caption))
            elif tag == "body":
                self._end_cards()


def from_html(text: str) -> list:
    """The outline of an HTML report (a table drawn as one card per row reads back as that table)."""
    parser = _Outline()
    parser.feed(text)
    parser.close()
    return parser.out
