"""The rate-and-state chain's section of ``bifurcation report --store`` (bifurcation/models/rs_chain/store_report.py):
its figures, its fit table, and that every number in its text is the one recomputed here from the catalog.

The store: N = 8, aging, k = 0.1, η = 1e-3, ℓ = 1 and 3, 300 events per run, computed in-process tile by
tile (as tests/test_rs_chain.py does; ~2 CPU s). ℓ = 1 gives events of 1–8 blocks over two decades of
potency; ℓ = 3 gives system-spanning events of one size (the not-fitted row).
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest

WORKFLOW = textwrap.dedent("""
    [study]
    name = "rs-chain-report-test"
    [model]
    name = "rs-chain"
    [engine]
    laws = ["aging"]
    [grid.n]
    values = [8]
    [grid.k]
    values = [0.1]
    [grid.ell]
    values = [1.0, 3.0]
    [grid.eta]
    values = [1e-3]
    [grid.events]
    values = [300]
    [tiles]
    catalog = 100
    """)


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    from bifurcation.run.tiles import compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.workflow import parse_workflow

    workflow = parse_workflow(WORKFLOW)
    path = tmp_path_factory.mktemp("rsreport") / "rs.zarr"
    run_id = create_store(path, workflow)["run_id"]
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile), run_id)
    return path


@pytest.fixture(scope="module")
def report(store, tmp_path_factory):
    from bifurcation.report.study import write_store_report

    out = tmp_path_factory.mktemp("rsreport_out")
    return out, write_store_report(store, out)


def _table(text: str, head: str) -> list[list[str]]:
    """The rows of the Markdown table whose head starts with the columns ``head`` ("a | b")."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"| {head} |"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip("|").split(" | ")])
    return rows


def _catalog(store, ell):
    from bifurcation.store.catalog import read_catalog

    return read_catalog(store, law="aging", n=8, ell=ell)


def test_the_report_has_its_figures_and_the_fit_table(report):
    out, res = report
    names = [p.name for p in res["figures"]]
    assert names == ["store0_rs_chain_sizes.png", "store0_rs_chain_space_time.png", "store0_rs_chain_balance.png"]
    for p in res["figures"]:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000, p
    text = res["markdown"].read_text()
    for name in names:
        assert f"]({name})" in text
    assert text.count("data:image/png;base64,") == 0 and res["html"].read_text().count("data:image/png;base64,") == 3
    assert len(_table(text, "run | events kept")) == 2          # both runs fitted or said why not


def test_the_numbers_in_the_text_are_those_of_the_catalog(store, report):
    from bifurcation.models.chain.clauset import clauset_fit
    from bifurcation.store import open_store

    text = report[1]["markdown"].read_text()
    runs = {r[0]: r for r in _table(text, "ell | status")}
    fits = {r[0]: r for r in _table(text, "run | events kept")}
    ds = open_store(store)
    for ell in (1.0, 3.0):
        cat = _catalog(store, ell)
        p, nb = np.asarray(cat["potency"]), np.asarray(cat["n_blocks"])
        assert p.size == 300
        row = runs[f"{ell}"]
        assert row[1:6] == ["complete", "300", f"{p.mean():.6g}", str(nb.max()), f"{np.mean(nb == 8):.3f}"]
        balance = float(ds["balance_max"].sel(state_law="aging", n=8, ell=ell).values.squeeze())
        assert row[6] == f"{balance:.1e}"
        kept = p[30:]                               # the first 10 % of 300 events: the transient
        fit_row = fits[f"ell = {ell}"]
        assert fit_row[1] == "270"
        if ell == 3.0:
            # characteristic events: all system-spanning, sizes within a few per cent: no tail to fit
            span = math.log10(kept.max() / kept.min())
            assert span < 0.1 and fit_row[8] == f"not fitted: sizes span {span:.2g} decades (< 1): no tail to fit"
            continue
        # the same fit, recomputed from the catalog with the settings the text states
        assert "10 data values per decade" in text and "100 parametric-bootstrap" in text and "200 moving-block" in text
        f = clauset_fit(kept, bootstrap=100, block_bootstrap=200, seed=1, resolution=10)
        assert fit_row[2:8] == [str(f.n_tail), f"{f.xmin:.4g}",
                                f"{f.alpha:.3f} ± {f.alpha_block_err:.3f} (i.i.d. {f.alpha_err:.3f})",
                                f"{f.alpha - 1:.3f}", f"{1.5 * (f.alpha - 1):.3f}", f"{f.ks:.4f}"]
        assert fit_row[8].startswith(f"power law plausible (p = {f.p_value:.2f})") or fit_row[8].startswith(
            f"power law ruled out (p = {f.p_value:.2f}")
        # α independently of powerlaw: the continuous MLE at the reported x_min, CSN Eq. (3.1)
        tail = kept[kept >= f.xmin]
        alpha = 1 + tail.size / np.sum(np.log(tail / f.xmin))
        assert tail.size == f.n_tail and abs(alpha - f.alpha) < 1e-12   # closed form both: rounding only
        # and its KS distance: the two-sided sup |S_n − F| of the tail, F(P) = 1 − (P/x_min)^(1−α), the
        # distance CSN Sec. 3.3 minimise over x_min (clauset.py). powerlaw's Distribution.KS compares F with
        # the data's CDF at the tail's points only, one side of each step of S_n, so its D is the
        # two-sided sup or up to 1/m less (equal on this catalog before the 2026-11-26 engine change, 1/m
        # less after it: a different catalog, the same two conventions)
        t, m = np.sort(tail), tail.size
        cdf = 1 - (t / f.xmin) ** (1 - alpha)
        ks = max(np.max(np.arange(1, m + 1) / m - cdf), np.max(cdf - np.arange(m) / m))
        assert ks - 1 / m - 1e-12 <= f.ks <= ks + 1e-12 and fit_row[7] == f"{f.ks:.4f}"
        # a sample with a tail to fit: two decades of potency, events of 1 to 8 blocks
        assert kept.max() / kept.min() > 10 and nb.min() == 1 and nb.max() == 8
    worst = float(np.nanmax(ds["balance_max"].values))
    assert f"the 2 runs with events is {worst:.1e}; 0 run(s) exceed the flag 1e-08" in text


def test_the_same_store_gives_the_same_bytes(store, report, tmp_path):
    from bifurcation.report.study import write_store_report

    out, first = report
    again = write_store_report(store, tmp_path)
    assert [p.name for p in again["figures"]] == [p.name for p in first["figures"]]
    for a, b in zip(first["figures"], again["figures"]):
        assert a.read_bytes() == b.read_bytes(), a.name
    assert again["markdown"].read_text() == first["markdown"].read_text()


def test_without_an_output_directory_the_section_draws_nothing(store):
    from bifurcation.models import get_model
    from bifurcation.models.rs_chain.store_report import blocks
    from bifurcation.analysis import load_stores
    from bifurcation.report.document import Figure, Table, flatten

    [ds] = load_stores(store)          # as the report reads it: with its path, for the catalog
    figures: list = []
    leaves = flatten(blocks(ds, get_model("rs-chain"), None, figures, "s"))
    assert figures == [] and not any(isinstance(b, Figure) for b in leaves)
    assert sum(isinstance(b, Table) for b in leaves) == 2      # the runs and the fits


def test_a_short_catalog_is_not_fitted_and_says_why():
    from bifurcation.models.rs_chain.store_report import MIN_FIT, size_fit

    s = size_fit(np.geomspace(0.01, 10.0, 40))
    assert s.fit is None and s.dropped == 4 and s.reason == f"36 events after the transient (< {MIN_FIT})"


def test_a_tail_shorter_than_a_decade_gets_no_power_law_reading():
    # results/rs-chain/REPORT.md's run: CSN's p = 0.53 on the largest 90 of 90000 potencies, x_min = 316.6,
    # largest 1839.9: the tail spans log10(1839.9/316.6) = 0.76 decade (all of them 242-256-block events),
    # too short for a scale-free reading whatever p says
    from types import SimpleNamespace

    from bifurcation.models.rs_chain.store_report import SizeFit, _fit_row

    def fit(xmin):
        return SimpleNamespace(verdict=lambda: "power law plausible (p = 0.53)", alpha=3.503, n_tail=90, xmin=xmin,
                               alpha_error=0.263, alpha_err=0.264, b_potency=2.503, b_magnitude=3.755, ks=0.0632)

    sizes = np.concatenate([np.full(89910, 10.0), np.linspace(316.6, 1839.9, 90)])
    row = _fit_row("the run", SizeFit(10000, sizes, fit(316.6)))
    assert row[8] == ("no power-law reading: the tail (90 of 90000 sizes) spans 0.76 decade (< 1); CSN's test: "
                      "power law plausible (p = 0.53)")
    assert _fit_row("the run", SizeFit(10000, sizes, fit(18.0)))[8] == "power law plausible (p = 0.53)"   # 2.0 decades


def test_report_says_on_stderr_what_it_is_doing(store, tmp_path, monkeypatch):
    """`bifurcation report` on the rs-chain study's store printed nothing for ~150 s (its Clauset fit of 9·10^4
    sizes; issue 21, walk 4): each stage is a line on stderr, and a stage that lasts (the fit, slowed here by
    0.5 s) gets 'still running' lines. The report itself is the one written without progress."""
    import time

    from click.testing import CliRunner

    from bifurcation.cli import _analysis, cli
    from bifurcation.models.rs_chain import store_report

    fit = store_report.size_fit

    def slow_fit(potency):
        time.sleep(0.5)
        return fit(potency)

    monkeypatch.setattr(_analysis, "STILL_SECONDS", 0.15)
    monkeypatch.setattr(_analysis, "QUIET_SECONDS", 0.0)   # (5 s: a short report, or an error, prints no stage)
    monkeypatch.setattr(store_report, "size_fit", slow_fit)
    result = CliRunner().invoke(cli, ["report", "--store", str(store), "--out", str(tmp_path / "r")])
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    assert lines and all(l.startswith("bifurcation: report: ") and l.endswith(" s]") for l in lines), lines
    assert "store 1 of 1" in lines[0] and "model rs-chain" in lines[0]
    fits = [i for i, l in enumerate(lines) if ": fitting 300 event sizes (Clauset" in l and "still" not in l]
    assert len(fits) == 2, lines          # ℓ = 1 and ℓ = 3
    assert lines[fits[0] + 1].startswith("bifurcation: report: still running: ell = 1.0: fitting"), lines
    # the repeats are short: the stage without its parenthesised detail, said once on its first line
    assert lines[fits[0] + 1].split(" [")[0] == "bifurcation: report: still running: ell = 1.0: fitting 300 event sizes"
    assert lines[-1].startswith("bifurcation: report: writing REPORT.md") and result.stdout.startswith("wrote ")
