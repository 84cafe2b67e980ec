"""A report as a tree of small typed blocks (STYLE.md §14), which one renderer turns into Markdown and HTML.

``Section(title, blocks, level)`` holds its blocks (a store's section holds one ``Section`` per law);
the leaves are ``Heading``, ``Paragraph``, ``Items`` (a bullet list), ``Table`` and ``Figure``. The
renderer (``bifurcation.report.render``: ``_markdown``, ``_html``) reads ``flatten(blocks)``: a section
is its heading, then its blocks. Text may hold the inline math of ``report._math`` ($...$, x_i, ...).

The paper's report (``render._blocks``), the common part of ``report --store`` (``report.study``) and
the chain's store section still build the older tuples (``("table", head, rows)``); ``flatten`` reads
those too, so every report goes through the one renderer (rate-state's store section is typed).
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["Block", "Figure", "Heading", "Items", "Paragraph", "Section", "Table", "flatten"]


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
    """An image file written beside the report (its name relative to the report) and its caption."""

    file: str
    caption: str


@dataclass(frozen=True)
class Section:
    """A heading and the blocks under it (sections nest: a level-2 section holds level-3 ones)."""

    title: str
    blocks: tuple = field(default_factory=tuple)
    level: int = 2

    def __post_init__(self) -> None:
        object.__setattr__(self, "blocks", tuple(self.blocks))


Block = Heading | Paragraph | Items | Table | Figure | Section

_TUPLES = {"h1": lambda text: Heading(text, 1), "h2": lambda text: Heading(text, 2),
           "h3": lambda text: Heading(text, 3), "p": Paragraph, "ul": Items, "table": Table, "figure": Figure}


def flatten(blocks) -> list:
    """The leaves of ``blocks`` in reading order: a ``Section`` becomes its ``Heading`` then its blocks; an
    older tuple block (``("p", text)``, ``("table", head, rows)``, ...) becomes its typed block."""
    out = []
    for block in blocks:
        if isinstance(block, Section):
            out.append(Heading(block.title, block.level))
            out.extend(flatten(block.blocks))
        elif isinstance(block, tuple):
            kind, *rest = block
            out.append(_TUPLES[kind](*rest))
        elif isinstance(block, (Heading, Paragraph, Items, Table, Figure)):
            out.append(block)
        else:
            raise TypeError(f"not a report block: {block!r}")
    return out
