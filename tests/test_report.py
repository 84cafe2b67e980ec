"""The report and the analysis CLI: files written, deterministic PNGs, self-contained HTML, every claim
present; `extrapolate`, `fit-period`, `report` and `reproduce` through the CLI runner (exit code first)."""

import json
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from click.testing import CliRunner

from bifurcation.analysis import CLAIM_KEYS, slip_dataset
from bifurcation.cli import cli
from bifurcation.report import analyse, write_report
from bifurcation.report import figures as F

LAWS = ["piecewise-linear", "carlson-langer"]


@pytest.fixture(scope="module")
def sources():
    """Small stand-ins for the three paper workflows (store layout, computed in process)."""
    nu_f = np.unique(np.round(np.r_[np.linspace(0.02, 0.98, 49), np.linspace(0.45, 0.55, 21)], 6))
    critical = slip_dataset(LAWS, [0.2, 0.3, 0.4, 0.5], np.logspace(-3, -15, 49))
    fig2 = slip_dataset("piecewise-linear", nu_f, [1e-3, 1e-6, 1e-9])
    fig3 = slip_dataset("carlson-langer", nu_f, [1e-9, 1e-12])
    return [critical, fig2, fig3]


@pytest.fixture(scope="module")
def report(sources, tmp_path_factory):
    """The report, and the analysis it was written from."""
    data = analyse(sources)
    return data, write_report(sources, tmp_path_factory.mktemp("report1"), data=data)


def test_report_files(report):
    data, files = report
    assert files["markdown"].is_file() and files["html"].is_file()
    assert len(files["figures"]) == 5
    for png in files["figures"]:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        # a panel with nothing drawn (frame and ticks only) is 9.1–9.6 kB at these sizes and dpi; the
        # report's figures are 50–150 kB
        assert png.stat().st_size > 10_000
    md = files["markdown"].read_text(encoding="utf-8")
    for png in files["figures"]:
        assert f"]({png.name})" in md   # relative links
    for section in ("## Claims", "## Errata", "## Δ(ν → 0)", "## Recurrence time", "## Figures",
                    "## Provenance"):
        assert section in md
    # in-process stand-ins are not stores: nothing was computed behind the reader's back
    assert data.computed_in_process == []


def test_markdown_and_html_are_one_document(report):
    # both formats read back to the outline of the typed blocks the report was built from (_blocks)
    from _report_outline import from_blocks, from_html, from_markdown
    from bifurcation.report.render import _blocks

    data, files = report
    out = files["markdown"].parent
    expected = from_blocks(_blocks(data, [(png.name, "caption") for png in files["figures"]]), out)
    assert expected.count(("h", 2)) == 6 and sum(k[0] == "table" for k in expected) == 5
    assert sum(k[0] == "figure" for k in expected) == 5
    assert from_markdown(files["markdown"].read_text(encoding="utf-8"), out) == expected
    assert from_html(files["html"].read_text(encoding="utf-8")) == expected


@pytest.mark.slow   # 5 s: a second analysis and drawing (fast: see the docstring)
def test_pngs_are_deterministic(sources, report, tmp_path):
    """A second report from its own ``analyse`` run has the same bytes (determinism of analysis and drawing).
    Fast cover: test_rs_chain_report.py (same store, same bytes, through the same ``figures.save``) and
    test_report_digits.py (this analysis gives the committed report's digits)."""
    _, first = report
    second = write_report(sources, tmp_path, data=analyse(sources))
    for a, b in zip(first["figures"], second["figures"]):
        assert a.read_bytes() == b.read_bytes(), a.name
    assert first["markdown"].read_text() == second["markdown"].read_text()


def test_png_has_no_date_or_software(report):
    png = report[1]["figures"][0].read_bytes()
    assert b"Software" not in png and b"matplotlib" not in png.lower() and b"tIME" not in png


def test_html_is_self_contained(report):
    page = report[1]["html"].read_text(encoding="utf-8")
    srcs = re.findall(r'src="([^"]*)"', page)
    assert len(srcs) == 5 and all(s.startswith("data:image/png;base64,") for s in srcs)
    assert "<link" not in page and "<script" not in page and "http://" not in page and "https://" not in page
    assert 'url(' not in page


def test_html_has_no_raw_tex(report):
    """Exponents and subscripts are <sup>/<sub> in the page (no network, no script), never raw TeX."""
    page = report[1]["html"].read_text(encoding="utf-8")
    text = re.sub(r'src="[^"]*"', "", page)
    assert "<sup>" in text and "<sub>" in text
    for raw in ("^{", "_{", "^(", "_(", "^−", "^-"):
        assert raw not in text, raw
    # the Markdown keeps the plain-text form a Markdown reader shows as typed
    assert "e^{πα/ω}" in report[1]["markdown"].read_text(encoding="utf-8")


@pytest.mark.parametrize("text, html", [
    ("e^{πα/ω}", "e<sup>πα/ω</sup>"),
    ("K ν^−(α−ω)² + …", "K ν<sup>−(α−ω)²</sup> + …"),
    ("ν^(1−r)", "ν<sup>1−r</sup>"),
    ("Σ_(k≤2) a_k ε^k", "Σ<sub>k≤2</sub> a<sub>k</sub> ε<sup>k</sup>"),
    ("U̇_max at ν_f = 1/2", "U̇<sub>max</sub> at ν<sub>f</sub> = 1/2"),
    ("nu_f slip_duration a<b & c", "nu_f slip_duration a&lt;b &amp; c"),   # names and escaping
    ("(1 + ω/α)^{(1 + α/ω)/2}", "(1 + ω/α)<sup>(1 + α/ω)/2</sup>"),
    ("x^{unbalanced", "x^{unbalanced"),
])
def test_inline_math(text, html):
    from bifurcation.report._math import inline_html

    assert inline_html(text) == html


def test_claims_table_in_report(report):
    data, files = report
    assert tuple(c.key for c in data.claims) == CLAIM_KEYS
    md = files["markdown"].read_text(encoding="utf-8")
    page = files["html"].read_text(encoding="utf-8")
    for claim in data.claims:
        assert claim.where in md and claim.verdict in md
    for item in ("Eq. (8)", "Eq. (9)", "Eq. (10)", "Eq. (13)", "Eq. (16)", "Eq. (17)", "Eq. (18)", "Fig. 2",
                 "Fig. 3", "Δ = 0.17", "T = Δ/ν + t1"):
        assert item in md, item
        assert item.replace("&", "&amp;") in page, item
    assert "refuted" in md and "incomplete" in md


def test_figures_use_no_pyplot(tmp_path):
    # in a fresh interpreter: another test (or plugin) may have imported pyplot into this one
    code = ("import sys; from bifurcation.report import figures as F; "
            "F.save(F.figure_fig2({}, [0.1], [1.9], [0.1, 0.5], [1.9, 1.6]), 'fig.png'); "
            "print('matplotlib.pyplot' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=tmp_path)
    assert out.stdout.strip() == "False"


def test_figure_axes_are_labelled(report):
    fig = F.figure_period(report[0].period_fits)
    assert fig.canvas.__class__.__name__ == "FigureCanvasAgg"
    assert all(ax.get_ylabel() for ax in fig.axes)                       # labelled axes, units in brackets
    assert all("[" in ax.get_ylabel() or "error" in ax.get_ylabel() for ax in fig.axes)
    assert sum("ν  [V0]" in ax.get_xlabel() for ax in fig.axes) == 2     # x shared down each column


# -- CLI ------------------------------------------------------------------------------------------------------
_TINY = {
    "tiny-fig2.toml": """
        [study]
        name = "tiny-fig2"
        [engine]
        laws = ["piecewise-linear"]
        [grid.nu]
        values = [1e-6, 1e-9]
        [grid.nu_f]
        ranges = [{ start = 0.02, stop = 0.98, num = 25 }]
        """,
    "tiny-fig3.toml": """
        [study]
        name = "tiny-fig3"
        [engine]
        laws = ["carlson-langer"]
        [grid.nu]
        values = [1e-9]
        [grid.nu_f]
        values = [0.4]
        ranges = [{ start = 0.02, stop = 0.98, num = 25 }]
        """,
    "tiny-critical.toml": """
        [study]
        name = "tiny-critical"
        [engine]
        laws = ["piecewise-linear", "carlson-langer"]
        [grid.nu]
        log = { start = 1e-3, stop = 1e-15, per_decade = 4 }
        [grid.nu_f]
        values = [0.2, 0.3, 0.4, 0.5]
        """,
}


@pytest.fixture(scope="module")
def reproduced(tmp_path_factory):
    """`bifurcation reproduce` end to end (embedded cluster, one worker) on tiny paper-like workflows."""
    from bifurcation.cli import _analysis

    root = tmp_path_factory.mktemp("reproduce")
    wf = root / "workflows"
    wf.mkdir()
    for name, text in _TINY.items():
        (wf / name).write_text(textwrap.dedent(text))
    mp = pytest.MonkeyPatch()
    mp.setattr(_analysis, "PAPER_WORKFLOWS", tuple(_TINY))
    mp.setattr(_analysis, "_workflow_dir", lambda: wf)
    mp.chdir(root)
    try:
        result = CliRunner().invoke(cli, ["reproduce", "--workers", "1"])
    finally:
        mp.undo()
    return root, result


@pytest.fixture(scope="module")
def tiny_stores(tmp_path_factory):
    """The tiny critical-point store of `reproduce` above, written in process (no cluster): what the
    analysis commands read. Returns the directory holding ``results/``."""
    from bifurcation.run.tiles import compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.workflow import parse_workflow

    root = tmp_path_factory.mktemp("stores")
    w = parse_workflow(textwrap.dedent(_TINY["tiny-critical.toml"]))
    path = root / "results" / "tiny-critical.zarr"
    run_id = create_store(path, w)["run_id"]
    for tile in iter_tiles(w):
        write_tile(path, tile, compute_tile(tile), run_id)
    return root


@pytest.mark.slow   # 15 s (a cluster, three workflows, the report); test_cli_examples runs reproduce fast
def test_reproduce_writes_stores_and_report(reproduced):
    root, result = reproduced
    assert result.exit_code == 0, result.output
    for name in ("tiny-fig2", "tiny-fig3", "tiny-critical"):
        assert (root / "results" / f"{name}.zarr").is_dir()
    out = root / "results" / "local" / "paper"   # not the committed results/paper (.gitignore)
    assert (out / "REPORT.md").is_file() and (out / "report.html").is_file()
    assert len(list(out.glob("*.png"))) == 5
    assert "wrote results/local/paper/REPORT.md" in result.output


def test_cli_extrapolate_json(tiny_stores):
    root = tiny_stores
    store = root / "results" / "tiny-critical.zarr"
    r = CliRunner().invoke(cli, ["extrapolate", "--store", str(store), "--law", "carlson-langer",
                                 "--nu-f", "0.5", "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    for key in ("delta0_extrapolated", "uncertainty", "delta0_direct", "paper_value"):
        assert key in out
    assert out["paper_value"] == 0.17
    assert abs(out["delta0_extrapolated"] - out["delta0_direct"]) <= out["uncertainty"] <= 5e-3
    r = CliRunner().invoke(cli, ["extrapolate", "--store", str(store), "--law", "carlson-langer",
                                 "--nu-f", "0.3", "--json"])
    assert r.exit_code == 0 and json.loads(r.output)["paper_value"] is None   # the paper gives none there


def test_cli_fit_period_json(tiny_stores):
    root = tiny_stores
    r = CliRunner().invoke(cli, ["fit-period", "--store", str(root / "results"), "--law", "piecewise-linear",
                                 "--nu-f", "0.4", "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    for key in ("log_coefficient", "log_coefficient_expected", "C0", "K", "residual_max", "terms"):
        assert key in out
    assert out["log_coefficient"] == pytest.approx(out["log_coefficient_expected"], rel=0.01)


def test_cli_fit_period_text_output(tiny_stores):
    root = tiny_stores
    r = CliRunner().invoke(cli, ["fit-period", "--store", str(root / "results" / "tiny-critical.zarr"),
                                 "--law", "carlson-langer", "--nu-f", "0.4"])
    assert r.exit_code == 0, r.output
    assert "log_coefficient_expected 0.5000000000" in r.output and "resonance" in r.output


@pytest.mark.parametrize("args, message", [
    (["fit-period", "--law", "carlson-langer", "--nu-f", "0.5"], "--nu-f=0.5: is not below 1/2"),
    (["extrapolate", "--law", "carlson-langer", "--nu-f", "0.33"],
     "--nu-f=0.33: is not a label of this store (nearest: 0.3, 0.4; 0.2 … 0.5, 4 labels)"),
    (["fit-period", "--law", "carlson-langer", "--nu-f", "0.30001"], "--nu-f=0.30001: is not a label"),
    (["extrapolate", "--law", "1/(1+x/2)^2", "--nu-f", "0.3"], "--law='1/(1+x/2)^2': is in no store given"),
    (["extrapolate", "--law", "carlson-langer", "--nu-f", "abc"], "'abc' is not a number"),
])
def test_cli_bad_input_is_one_line_exit_2(tiny_stores, args, message):
    root = tiny_stores
    store = str(root / "results" / "tiny-critical.zarr")
    r = CliRunner().invoke(cli, [*args, "--store", store])
    assert r.exit_code == 2, r.output
    assert message in r.output and len(r.output.strip().splitlines()) == 1


def test_cli_missing_store_exit_2(tmp_path):
    r = CliRunner().invoke(cli, ["report", "--store", str(tmp_path / "nope"), "--out", str(tmp_path / "o")])
    assert r.exit_code == 2
    assert "does not exist" in r.output
