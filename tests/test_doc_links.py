"""README.md and docs/*.md: every relative link resolves (the file, and its #anchor to a heading there), and
README's quick start stays the two commands CI runs (issue 21: README short, the detail moved to docs/)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
_LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
_FENCE = re.compile(r"^```.*?^```", re.M | re.S)


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped (letters of any script, digits, '_', '-'
    and spaces kept), spaces to '-'."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(page: Path) -> set[str]:
    seen: dict[str, int] = {}
    anchors = set()
    for line in _FENCE.sub("", page.read_text(encoding="utf-8")).splitlines():
        if m := re.match(r"#{1,6} (.+)", line):
            slug = _slug(m.group(1))
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            anchors.add(slug if n == 0 else f"{slug}-{n}")
    return anchors


def _links(page: Path) -> list[str]:
    return _LINK.findall(_FENCE.sub("", page.read_text(encoding="utf-8")))


def test_slug_follows_github():
    assert _slug("Burridge–Knopoff chains (`bifurcation bench --suite chain`)") == \
        "burridgeknopoff-chains-bifurcation-bench---suite-chain"
    assert _slug("The ν → 0 limit, directly") == "the-ν--0-limit-directly"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(REPO).as_posix())
def test_relative_links_resolve(page):
    bad = []
    for target in _links(page):
        if re.match(r"[a-z]+:", target):      # http(s):, mailto: — not checked offline
            continue
        path, _, anchor = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        if not dest.exists():
            bad.append(f"{target}: no file {dest.relative_to(REPO) if dest.is_relative_to(REPO) else dest}")
        elif anchor and dest.suffix == ".md" and anchor not in _anchors(dest):
            bad.append(f"{target}: no heading with anchor #{anchor} in {dest.name}")
    assert bad == [], f"{page.name}: " + "; ".join(bad)


def test_quick_start_is_the_two_commands_ci_runs():
    """.ci/run runs README's second command; a new user copies both from the top of README."""
    lines = (REPO / "README.md").read_text(encoding="utf-8").splitlines()
    start = lines.index("## Quick start (Python ≥ 3.11)")
    block = lines[start + 2:start + 9]
    assert block == [
        "```bash",
        "# 1. install and run the main job: reproduce the paper on an embedded local Dask cluster → results/local/paper/",
        "python -m pip install -e . && bifurcation reproduce",
        "",
        "# 2. install and run the tests (the full suite, as CI runs it; the fast part alone: see Tests below)",
        'python -m pip install -e ".[test]" && python -m pytest -q',
        "```",
    ]
    ci = (REPO / ".ci" / "run").read_text()
    assert 'python -m pip install -q -e ".[test]"' in ci and "python -m pytest -q" in ci


def test_readme_is_read_in_ten_minutes():
    """Issue 21: README is what a new user reads first; measurements, history and reference go to docs/."""
    n = len((REPO / "README.md").read_text(encoding="utf-8").splitlines())
    assert n <= 320, f"README.md has {n} lines; move detail into docs/ (docs/benchmarks.md, docs/testing.md, ...)"
