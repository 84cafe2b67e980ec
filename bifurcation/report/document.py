"""A report as a tree of small typed blocks (STYLE.md §14), which one renderer turns into Markdown and HTML.

``Section(title, blocks, level)`` holds its blocks (a store's section holds one ``Section`` per law);
the leaves are ``Heading``, ``Paragraph``, ``Items`` (a bullet list), ``Table`` and ``Figure``. The
renderer (``to_markdown``, ``to_html``) reads ``flatten(blocks)``: a section is its heading, then its
blocks. Text may hold the inline math of ``report._math`` ($...$, x_i, ...).

Every report is built of these blocks: the paper's (``report.render``), the one of any store
(``report.study``), the rate-state study's (``models.rate_state.report``), the chain study's
(``models.chain.study``) and the models' store sections; anything else is refused (``flatten``: a
TypeError naming the block).
"""

from __future__ import annotations

import base64
import html
import re
from dataclasses import dataclass, field
from pathlib import Path

from ._math import inline_html

__all__ = ["Block", "Figure", "Heading", "Items", "Paragraph", "Section", "Table", "flatten", "to_html",
           "to_markdown"]


@dataclass(frozen=True)
class Heading:
    text: str
    level: int = 2      # 1: the report's title, 2: a section, 3: a subsection

    def __post_init__(self) -> None:
        if self.level not in (1, 2, 3):
            raise ValueError(f"Heading level {self.level}: use 1, 2 or 3")


@dataclass(frozen=True)
class Paragraph:
    text: str


@dataclass(frozen=True)
class Items:
    """A bullet list."""

    items: tuple[str, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "items", tuple(self.items))


@dataclass(frozen=True)
class Table:
    """A table of text cells: ``head`` names the columns, each row has one cell per column."""

    head: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "head", tuple(self.head))
        object.__setattr__(self, "rows", tuple(tuple(r) for r in self.rows))
        bad = [i for i, r in enumerate(self.rows) if len(r) != len(self.head)]
        if bad:
            raise ValueError(f"Table row {bad[0]} has {len(self.rows[bad[0]])} cells for {len(self.head)} columns")


@dataclass(frozen=True)
class Figure:
    """An image file written beside the report (its name relative to the report) and its caption (none if
    empty); ``alt``, its text for readers who cannot see it, is the file's name in words unless given."""

    file: str
    caption: str = ""
    alt: str = ""

    def __post_init__(self) -> None:
        if not self.alt:
            object.__setattr__(self, "alt", self.file.rsplit(".", 1)[0].replace("_", " "))


@dataclass(frozen=True)
class Section:
    """A heading and the blocks under it (sections nest: a level-2 section holds level-3 ones)."""

    title: str
    blocks: tuple = field(default_factory=tuple)
    level: int = 2

    def __post_init__(self) -> None:
        object.__setattr__(self, "blocks", tuple(self.blocks))


Block = Heading | Paragraph | Items | Table | Figure | Section

def flatten(blocks) -> list:
    """The leaves of ``blocks`` in reading order: a ``Section`` becomes its ``Heading`` then its blocks."""
    out = []
    for block in blocks:
        if isinstance(block, Section):
            out.append(Heading(block.title, block.level))
            out.extend(flatten(block.blocks))
        elif isinstance(block, (Heading, Paragraph, Items, Table, Figure)):
            out.append(block)
        else:
            raise TypeError(f"not a report block: {block!r}")
    return out


# -- the renderer ---------------------------------------------------------------------------------------
#: what Markdown reads as raw HTML in a cell (a tag's start, an entity): a label "prz <fast>" vanished as a tag
_MD_HTML = re.compile(r"<(?=[A-Za-z/!?])|&(?=#[0-9]+;|#[xX][0-9a-fA-F]+;|[A-Za-z][A-Za-z0-9]*;)")


def _md_cell(text: str) -> str:
    text = str(text).replace("|", "\\|").replace("\r\n", " ").replace("\n", " ").replace("\r", " ")
    return _MD_HTML.sub(lambda m: "&lt;" if m.group() == "<" else "&amp;", text)


def to_markdown(blocks) -> str:
    """``blocks`` as Markdown: one blank line between blocks."""
    out = []
    for block in flatten(blocks):
        if isinstance(block, Heading):
            out.append(f"{'#' * block.level} {block.text}\n")
        elif isinstance(block, Paragraph):
            out.append(f"{block.text}\n")
        elif isinstance(block, Items):
            out.append("\n".join(f"- {item}" for item in block.items) + "\n")
        elif isinstance(block, Table):
            lines = ["| " + " | ".join(_md_cell(h) for h in block.head) + " |",
                     "|" + "|".join("---" for _ in block.head) + "|"]
            lines += ["| " + " | ".join(_md_cell(c) for c in r) + " |" for r in block.rows]
            out.append("\n".join(lines) + "\n")
        elif isinstance(block, Figure):
            out.append(f"![{block.alt}]({block.file})\n" + (f"\n*{block.caption}*\n" if block.caption else ""))
    return "\n".join(out)


_CSS = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.45;"
        "color:#222}"
        "table{border-collapse:collapse;font-size:0.85em;margin:0.6em 0}"
        "td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:top}th{background:#f2f2f2}"
        "figure{margin:1.2em 0}img{max-width:100%}figcaption{font-size:0.9em;color:#444}"
        ".card{border:1px solid #ddd;border-radius:4px;padding:0.5em 0.9em;margin:0.7em 0}"
        ".card h3{font-size:1em;margin:0.1em 0 0.4em}.card dl{margin:0;display:grid;"
        "grid-template-columns:10em 1fr;gap:0.25em 0.8em;font-size:0.92em}.card dt{color:#555}"
        ".card dd{margin:0}.tag{font-size:0.8em;border-radius:3px;padding:1px 6px;margin-left:0.6em;"
        "background:#eee}")

#: The inline Markdown the reports write: `code`, **bold**, [text](relative link or http(s) address).
_INLINE = re.compile(r"`([^`]+)`|\*\*(.+?)\*\*|\[([^\]]+)\]\(([^)\s]+)\)")


def _inline(text) -> str:
    """``text`` as HTML: the reports' inline Markdown as its elements, the rest through ``inline_html``
    (escaped, exponents and subscripts). A link to anything but a relative path or http(s) stays text."""
    text, out, at = str(text), [], 0
    for match in _INLINE.finditer(text):
        out.append(inline_html(text[at:match.start()]))
        code, bold, label, href = match.groups()
        if code is not None:
            out.append(f"<code>{html.escape(code)}</code>")
        elif bold is not None:
            out.append(f"<strong>{_inline(bold)}</strong>")
        elif ":" in href.split("/", 1)[0] and not href.startswith(("http://", "https://")):
            out.append(inline_html(match.group(0)))   # javascript:, data:, ...: not a link
        else:
            out.append(f'<a href="{html.escape(href)}">{_inline(label)}</a>')
        at = match.end()
    out.append(inline_html(text[at:]))
    return "".join(out)


#: A table whose cells average more characters than this reads better as one card per row.
_CARD_CELL_CHARS = 45


def _table_html(head, rows) -> str:
    m = _inline
    cells = [str(c) for r in rows for c in r]
    if len(head) < 4 or not cells or sum(map(len, cells)) / len(cells) < _CARD_CELL_CHARS:
        return ("<table><tr>" + "".join(f"<th>{m(h)}</th>" for h in head) + "</tr>"
                + "".join("<tr>" + "".join(f"<td>{m(c)}</td>" for c in r) + "</tr>" for r in rows)
                + "</table>")
    # one card per row: the first column as its title, a verdict-like last column as a tag
    tagged = head[-1].lower() in ("verdict", "cause")
    out = []
    for r in rows:
        title = f"<h3>{m(r[0])}" + (f'<span class="tag">{m(r[-1])}</span>' if tagged else "") + "</h3>"
        body = head[1:-1] if tagged else head[1:]
        items = "".join(f"<dt>{m(h)}</dt><dd>{m(c)}</dd>" for h, c in zip(body, r[1:]))
        out.append(f'<div class="card">{title}<dl>{items}</dl></div>')
    return "".join(out)


def to_html(blocks, figure_dir) -> str:
    """``blocks`` as one self-contained HTML page: its title is the first heading, each figure is read from
    ``figure_dir`` and embedded (base64), so the page needs no file beside it."""
    e, m = html.escape, _inline
    blocks = flatten(blocks)
    title = next(b.text for b in blocks if isinstance(b, Heading))
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>{e(title)}</title><style>{_CSS}</style></head><body>"]
    for block in blocks:
        if isinstance(block, Heading):
            parts.append(f"<h{block.level}>{m(block.text)}</h{block.level}>")
        elif isinstance(block, Paragraph):
            parts.append(f"<p>{m(block.text)}</p>")
        elif isinstance(block, Items):
            parts.append("<ul>" + "".join(f"<li>{m(i)}</li>" for i in block.items) + "</ul>")
        elif isinstance(block, Table):
            parts.append(_table_html(block.head, block.rows))
        elif isinstance(block, Figure):
            data = base64.b64encode((Path(figure_dir) / block.file).read_bytes()).decode("ascii")
            caption = f"<figcaption>{m(block.caption)}</figcaption>" if block.caption else ""
            parts.append(f'<figure><img alt="{e(block.alt)}" src="data:image/png;base64,{data}">{caption}</figure>')
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
