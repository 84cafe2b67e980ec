"""`bifurcation report --store S` reports what S holds (issue 9): the user's laws, axes and figures."""

from __future__ import annotations

import textwrap

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.store import create_store, write_tile
from bifurcation.run.tiles import compute_tile, iter_tiles
from bifurcation.workflow import parse_workflow

USER = textwrap.dedent("""
    [study]
    name = "user-laws"
    [engine]
    laws = ["exp(-x)", "1/(1+x/2)^2"]
    [grid.nu]
    log = { start = 1e-3, stop = 1e-9, num = 13 }
    [grid.nu_f]
    values = [0.3, 0.45, 0.5, 0.55, 0.7]
    [tiles]
    nu_f = 5
    nu = 13
    """)


def _store(tmp_path, text):
    w = parse_workflow(text)
    path = tmp_path / f"{w.name}.zarr"
    run_id = create_store(path, w)["run_id"]
    for tile in iter_tiles(w):
        write_tile(path, tile, compute_tile(tile), run_id)
    return w, path


@pytest.fixture(scope="module")
def user_report(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("user")
    w, path = _store(tmp, USER)
    out = tmp / "report"
    result = CliRunner().invoke(cli, ["report", "--store", str(path), "--out", str(out)])
    return w, out, result


def test_report_names_the_users_laws_with_their_figures(user_report):
    w, out, result = user_report
    assert result.exit_code == 0, result.output
    md = (out / "REPORT.md").read_text()
    for law in w.laws:
        assert f"### Law {law}" in md and f"Φ(x) = {law}" in md
    assert "carlson-langer" not in md and "piecewise-linear" not in md   # not the paper's laws
    assert "The paper's claims" not in md
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert pngs == ["store0_law0_delta.png", "store0_law1_delta.png"]
    # the axes as the store holds them
    assert "| nu | ν | 1e-09 | 0.001 | 13 |" in md and "| nu_f | ν_f | 0.3 | 0.7 | 5 |" in md


def test_report_markdown_and_html_are_one_document(user_report):
    from _report_outline import from_html, from_markdown

    _, out, result = user_report
    assert result.exit_code == 0, result.output
    outline = from_markdown((out / "REPORT.md").read_text(), out)
    assert outline == from_html((out / "report.html").read_text())
    # title, the store's section with one subsection per law (each with its figure), the provenance
    assert [k for k in outline if k[0] == "h"] == [("h", 1), ("h", 2), ("h", 3), ("h", 3), ("h", 2)]
    assert sum(k[0] == "figure" for k in outline) == 2


def test_report_finds_the_transition_between_the_labels_either_side(user_report):
    _, out, _ = user_report
    md = (out / "REPORT.md").read_text()
    # at ν ≤ 1e-3 both laws are stick-slip at ν_f = 0.5 and creep at 0.55 (docs/physics.md: creep above
    # 1/2 once U̇ stays below ν_f); the store's labels either side are named
    assert "0.5 (stick-slip) → 0.55 (creep)" in md


def test_report_says_when_the_grid_is_too_short_to_extrapolate(user_report):
    _, out, _ = user_report
    md = (out / "REPORT.md").read_text()
    # 13 points along ν with 7 at ν ≤ 1e-6 is fewer than MIN_SERIES: no extrapolation, and it says so
    assert "No ν → 0 extrapolation" in md


LONG = textwrap.dedent("""
    [study]
    name = "long-series"
    [engine]
    laws = ["carlson-langer"]
    [grid.nu]
    log = { start = 1e-6, stop = 1e-15, per_decade = 2 }
    [grid.nu_f]
    values = [0.3, 0.48, 0.5]
    """)


def test_report_extrapolates_where_the_grid_allows_it(tmp_path):
    """19 points along ν at ν ≤ 1e-6 (≥ MIN_SERIES): the extrapolation and the recurrence-time fit are
    made, with their figures; at ν_f = 0.48 (r = 0.5625 ≥ 1/2) the report says they do not apply."""
    _, path = _store(tmp_path, LONG)
    out = tmp_path / "r"
    result = CliRunner().invoke(cli, ["report", "--store", str(path), "--out", str(out)])
    assert result.exit_code == 0, result.output
    md = (out / "REPORT.md").read_text()
    table = md[md.index("| ν_f | regime |"):md.index("Recurrence time T − Δ0/ν")]   # the extrapolations
    rows = {line.split(" | ")[0].lstrip("| "): line for line in table.splitlines() if line.startswith("| 0.")}
    # the direct limits these rows are compared with: Carlson–Langer Δ0(0.3) = 1.0884904195 and
    # Δ0(1/2) = 0.15072944 (README, results/paper/REPORT.md); "yes" = within the stated uncertainty
    assert "| stick-slip | 19 | 1.08849" in rows["0.3"] and rows["0.3"].endswith("| yes |")
    assert "| critical | 19 | 0.1507" in rows["0.5"] and rows["0.5"].endswith("| yes |")
    assert "0.48" not in rows   # no number where the method does not apply ...
    assert "do not apply at ν_f = 0.48: there r = (α − ω)² ≥ 1/2" in md   # ... a sentence instead
    fits = md[md.index("Recurrence time T − Δ0/ν"):]
    assert "| 0.3 | 0.3333" in fits and "| 0.48 |" not in fits   # ln coefficient near α − ω = 1/3
    figures = sorted(p.name for p in out.glob("*.png"))
    assert figures == ["store0_law0_critical.png", "store0_law0_delta.png", "store0_law0_period.png"]


@pytest.mark.slow   # 8 s; the claims table itself is tested fast in test_report.py
def test_report_of_a_store_with_the_paper_laws_has_the_claims(tmp_path):
    text = USER.replace('["exp(-x)", "1/(1+x/2)^2"]', '["piecewise-linear", "carlson-langer"]').replace(
        'name = "user-laws"', 'name = "paper-laws"').replace("num = 13", "num = 4").replace("nu = 13", "nu = 4")
    _, path = _store(tmp_path, text)
    out = tmp_path / "r"
    result = CliRunner().invoke(cli, ["report", "--store", str(path), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "The paper's claims" in (out / "REPORT.md").read_text()
