"""The chain report's preset section and verdict table (issue 17, item 6;
bifurcation/models/chain/_study_presets.py), from hand-made statistics: no runs, < 1 s."""

from __future__ import annotations

from pathlib import Path

import pytest

from bifurcation.models.chain._study_presets import PRESET_RULES, _peak, preset_section, verdict_table
from bifurcation.report.document import Table, flatten, to_markdown


def _run(preset, nu_f, fit=True, **kw):
    par = {"n": 800, "ell": 3.0, "nu": 1e-5, "nu_f": nu_f, "sigma": 0.01, "ends": "periodic"}
    x = {"preset": preset, "verified_preset": False, "overrides": {"nu": 1e-5}, "parameters": par, "why": "ν lowered",
         "claim": "", "events": 1000, "status": "complete", "cpu_run": 1.0, "cpu_stats": 1.0, "cpu": 2.0,
         "loading_cycles": 5.0, "transient_cycles": 1.0, "kept": 900,
         "verify": {"checked": 2, "largest": 1e-13, "mismatched": 0},
         "n_blocks": {"max": 800, "mean": 3.0, "spanning": 2, "large": 6, "one": 500},
         "distinct_potencies": 900, "potency_range": [1e-3, 900.0], "relative_spread": 1.0,
         "mfd": {"edges": [0.0, 0.1, 0.2], "counts": [5, 3]}, "peak": None,
         "excess": {"large": 6, "p_large": 100.0, "observed_above": 30, "expected": 5.0, "ratio": 6.0}}
    x["fit"] = ({"n": 900, "n_tail": 300, "xmin": 0.01, "alpha": 1.6, "alpha_err": 0.03, "alpha_block_err": 0.04,
                 "block": 10, "ks": 0.02, "p": 0.0, "bootstrap": 10, "b_P": 0.6, "b_M": 0.9, "words": "",
                 "ratios": {"exponential": [5.0, 1e-5], "lognormal": [-2.0, 0.04]}} if fit else None)
    x.update(kw)
    return x


def test_the_verdict_table_has_one_row_per_claim_and_prints_its_rules():
    data = {"presets": [_run("carlson-langer-1991", 0.2), _run("mori-kawamura-2006", 0.5),
                        _run("mori-kawamura-2006", 0.25)]}
    blocks = verdict_table({}, data, {"vas": "x", "vas_word": "**undecided**", "sak": "y"})
    (table,) = [b for b in flatten(blocks) if isinstance(b, Table)]
    assert len(table.head) == 5 and table.head[0] == "claim" and table.head[-1] == "verdict"
    assert len(table.rows) == 5
    # no published-ν catalog given: that column says so for the chain claims
    assert table.rows[1][2] == "not run" and table.rows[3][2] == "not run"
    for claim in ("Vasconcelos", "Carlson & Langer", "de Sousa Vieira", "Mori & Kawamura", "Sakaguchi"):
        assert sum(r[0].startswith(claim) for r in table.rows) == 1
    rows = [" | ".join(r) for r in table.rows]
    # unread papers and models not run are "not tested", whatever the numbers beside them
    assert "**not tested**" in rows[2] and "**not tested**" in rows[3] and "**not tested** on its model" in rows[4]
    # CL: p = 0 of 10 bootstrap samples bounds p only by 0.26 (95 %): undecided, not ruled out (the rule's
    # Clopper–Pearson bound); 6 ≥ N/2 events, 6× the prediction: an excess by the printed rule
    assert "power law undecided" in rows[1] and "**excess**" in rows[1] and "not a test of the paper" in rows[1]
    # a tail of less than one decade above x_min is not read as a power law
    short = _run("carlson-langer-1991", 0.2, potency_range=[1e-3, 0.05])
    text = to_markdown(verdict_table({}, {"presets": [short]}, {}))
    assert "no scaling range" in text and "power law ruled out" not in text
    assert "Rules: " + PRESET_RULES in text
    # MK reports both α, the larger ν_f (α = 1) first
    assert rows[3].index("α = 1 (") < rows[3].index("α = 2 (")
    # each run says what it holds: its events and their definition, and σ and the ends of the MK chain
    assert "900 of 1000 events kept after 1 loading cycle(s); an event lasts until every block is stuck" in rows[1]
    assert "σ = 0.01, periodic" in rows[3]
    # p with its count and 95 % bound: 0 of 10 samples bounds p by 0.26, so the word stays undecided
    assert "0 of 10, ≤ 0.26 at 95 %" in rows[3] and "power law undecided" in rows[3]


def test_a_repeated_single_event_is_not_fitted():
    x = _run("vasconcelos-1996", 0.5, fit=False, relative_spread=3e-14, potency_range=[0.198, 0.198])
    text = to_markdown(preset_section({"presets": [x]}))
    assert "no size distribution to fit" in text and "3.0e-14" in text


_BODY = [1000, 600, 400, 300, 200, 150, 100, 80, 60, 50]     # the mode, then a decade of decay


@pytest.mark.parametrize("tail,peak", [([40, 30, 20, 60, 90, 70, 20], 1.4),   # rises again: 90 vs 20 (> 3σ = 31)
                                       ([40, 30, 20, 15, 10, 5, 2], None),    # monotone
                                       ([40, 30, 20, 25, 30, 20, 10], None),  # 30 vs 20: within 3σ (21)
                                       ([90, 30, 20, 10, 10, 5, 2], None)])   # above the mode's decade only falls
def test_the_characteristic_peak_rule(tail, peak):
    counts = _BODY + tail
    edges = [i / 10 for i in range(len(counts) + 1)]
    got = _peak(edges, counts)
    assert (got is None) == (peak is None)
    if peak is not None:
        assert got["m"] == pytest.approx(peak) and got["m_low"] == pytest.approx(1.2)


def test_presets_only_needs_the_full_run_data(tmp_path):
    # --presets-only takes every other section from DIR/data.json: without it, one line and nothing run
    from bifurcation.models.chain.study import main

    wf = Path(__file__).resolve().parents[1] / "workflows" / "chain-report.toml"   # (checked whole first)
    with pytest.raises(SystemExit, match="--presets-only: .*data.json does not exist"):
        main([str(wf), "--out", str(tmp_path / "o"), "--presets-only"])
    assert not (tmp_path / "o").exists()


def _pub(nu_f, slides, large, observed, expected, p=0.0, largest=1e3):
    return {"preset": "mori-kawamura-2006", "nu_f": nu_f, "nu": 0.01, "v_threshold": 0.1, "kept": 5000,
            "n": 800, "ell": 3.0, "sigma": 0.01, "ends": "periodic",
            "status": "complete", "loading_cycles": 400.0, "cpu_per_event": 2e-3,
            "n_blocks": {"mean": 3.0, "large": large}, "duration": {"over_one_cycle": slides},
            "excess": ({"large": large, "p_large": 50.0, "observed": observed, "expected": expected} if large else
                       {"large": 0}),
            "fit": {"alpha": 1.5, "alpha_block_err": 0.01, "xmin": 0.1, "n_tail": 900, "b_P": 0.5, "b_M": 0.75,
                    "p": p, "bootstrap": 100, "largest": largest, "ratios": {"exponential": [4.0, 1e-4]}}}


def test_the_published_nu_column_reads_each_catalog_by_its_rule():
    data = {"presets": [_run("mori-kawamura-2006", 0.5)],
            "published_nu": [_pub(0.25, slides=7, large=9, observed=40, expected=2.0),
                             _pub(0.5, slides=0, large=0, observed=0, expected=0, p=0.4, largest=5.0)]}
    (table,) = [b for b in flatten(verdict_table({}, data, {})) if isinstance(b, Table)]
    cell = table.rows[3][2]
    # α = 1 (ν_f = 0.5) first: 1.7 decades above x_min is a scaling range only from 1 decade on: 5/0.1 = 50
    assert cell.index("α = 1 (") < cell.index("α = 2 (")
    one, two = cell.split("; α = 2 (")
    assert "power law plausible" in one and "B = 100" in one and "slides of ≥ 1 loading cycle" not in one
    assert "**slides of ≥ 1 loading cycle**" in two and "power law ruled out" in two and "**excess**" in two
    # what was run, and the event definition, in the cell itself; 0 of 100 bounds p by 0.03: ruled out
    assert "N = 800, ℓ = 3, ν = 0.01, σ = 0.01, periodic; an event lasts while some block is faster than V_th = 0.1" in two
    assert "0 of B = 100, ≤ 0.03 at 95 %" in two
    assert table.rows[1][2] == "not run"    # no carlson-langer-1991 record
    # the sizes paragraph: computed from the records (2 ms per event: 10^6 events ~0.56 CPU h, printed "1")
    text = to_markdown(verdict_table({}, data, {}))
    assert "Catalog sizes at the presets' own ν: 5000–5000 events per catalog" in text
    assert "is 2–2 CPU ms" in text and "would take 1–1 CPU hours each" in text
    assert "(0 of 2 fits with **no scaling range**)" in text


def test_published_nu_md_is_rendered_from_the_committed_catalog_records(tmp_path):
    """results/chain/PUBLISHED_NU.md is write_report's page of the committed subevents_*.json (every number
    on it recomputed from those records; regenerate with `python -m bifurcation.models.chain.subevent_study
    report results/chain`)."""
    import shutil

    from bifurcation.models.chain.subevent_study import write_report

    out = Path(__file__).resolve().parents[1] / "results" / "chain"
    for q in out.glob("subevents_*.json"):
        shutil.copy(q, tmp_path / q.name)
    page = write_report(tmp_path).read_text().replace(str(tmp_path), "results/chain")
    assert page == (out / "PUBLISHED_NU.md").read_text()


@pytest.mark.parametrize("line,message", [
    ('cpu = 0', "published_nu.cpu"),
    ('v_threshold = -1', "published_nu.v_threshold"),
    ('bootstrap = 1.5', "published_nu.bootstrap"),
    ('nu_f_typo = 1', "nu_f_typo")])
def test_the_published_nu_table_is_checked_before_anything_runs(tmp_path, line, message):
    from bifurcation.errors import InputError
    from bifurcation.models.chain.study_workflow import load_report_workflow

    wf = (Path(__file__).resolve().parents[1] / "workflows" / "chain-report.toml").read_text()
    head, tail = wf.split("[published_nu]", 1)
    bad = tmp_path / "w.toml"
    bad.write_text(head + "[published_nu]\n" + line + "\n" + "\n".join(
        x for x in tail.split("\n") if not x.startswith(line.split(" = ")[0] + " ")))
    with pytest.raises(InputError, match=message):
        load_report_workflow(bad)


def test_published_nu_jobs_carry_the_shared_settings_and_the_run():
    from bifurcation.models.chain.study_workflow import load_report_workflow
    from bifurcation.models.chain.subevent_study import _published_job, published_nu_jobs

    cfg = load_report_workflow(Path(__file__).resolve().parents[1] / "workflows" / "chain-report.toml")
    jobs = published_nu_jobs(cfg)
    assert [j[0] for j in jobs] == [_published_job] * len(cfg["published_nu"]["run"])
    shared, run = jobs[1][1]
    assert run == {"preset": "mori-kawamura-2006", "nu_f": 0.5} and shared["v_threshold"] == 0.1
    assert jobs[1][2] == cfg["published_nu"]["cpu"]


@pytest.mark.parametrize("flags,needle", [
    (["--from-data", "--published-nu-only"], "give one of --from-data, --presets-only, --catalogs-only"),
    (["--catalogs-only", "--presets-only"], "give one of --from-data, --presets-only, --catalogs-only"),
    (["--published-nu-only"], "does not exist: the report is re-rendered from it"),
    (["--catalogs-only"], "does not exist: the report is re-rendered from it")])
def test_the_partial_run_flags_refuse_before_running(tmp_path, flags, needle):
    """One line, exit 2, nothing written: two partial runs at once, or a partial run without DIR/data.json."""
    from click.testing import CliRunner

    from bifurcation.cli import cli

    wf = str(Path(__file__).resolve().parents[1] / "workflows" / "chain-report.toml")
    out = tmp_path / "o"
    r = CliRunner().invoke(cli, ["study", "chain", wf, "--out", str(out), *flags])
    assert r.exit_code == 2 and needle in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not any(out.iterdir()) if out.exists() else True


def test_the_literature_column_quotes_each_finding_in_its_claims_row():
    """Column 4 (literature.py): every finding read, with its source, place and words, in the row of its
    claim; a claim with none says so; CL's comparison is computed from the run, not written by hand."""
    from bifurcation.models.chain.literature import FINDINGS, SEARCHES

    data = {"presets": [_run("carlson-langer-1991", 0.2), _run("mori-kawamura-2006", 0.5)]}
    (table,) = [b for b in flatten(verdict_table({}, data, {})) if isinstance(b, Table)]
    assert table.head[3].startswith("published finding read")
    keys = ["vas", "cl", "dsvvn", "mk", "sak"]
    for f in FINDINGS:
        assert f.claim in keys and f.source and f.place
        cell = table.rows[keys.index(f.claim)][3]
        assert f"“{f.quote}”" in cell and f.source in cell
        # an account of another paper says it is one
        assert ("(secondary: its account of another paper)" in cell) or not f.secondary
    # MK's 1D α-dependence was not read anywhere: only its 2D models' abstracts, not compared; the claim is the
    # issue's summary
    assert "not compared: the first two are MK's two-dimensional models" in table.rows[3][3]
    assert "realized only by fine-tuning the model parameters" in table.rows[3][3]     # MK on their 1D models
    assert "issue 17's summary" in table.rows[3][3]
    # de Sousa Vieira–Vasconcelos–Nagel is read only through Vasconcelos 1996's account of it
    assert table.rows[2][3].startswith("Vasconcelos, PRL 76, 4865 (1996)") and "secondary" in table.rows[2][3]
    # the hand-made CL run: 6 events ≥ N/2 at 6× the prediction is an excess by the rule; p = 0 of 10 undecided
    assert "ours **excess** (30 events with P ≥ 100 against 5 predicted (6×))" in table.rows[1][3]
    assert "small events: ours power law undecided (b_P = 0.60)" in table.rows[1][3]
    # without a CL run there is nothing to set beside the CL findings
    (t2,) = [b for b in flatten(verdict_table({}, {"presets": []}, {})) if isinstance(b, Table)]
    assert t2.rows[1][3].endswith("beside ours: no run on the preset")
    # the record of searches that found nothing names its corpus and query
    assert SEARCHES and all(c in ("pages", "code", "docs", "issues", "find_string", "find_repos") and q and r
                            for c, q, r in SEARCHES)


def test_docs_list_every_search_that_found_nothing():
    """docs/chain.md, "Presets", lists the look-ups of literature.SEARCHES, so the next search starts elsewhere."""
    from bifurcation.models.chain.literature import SEARCHES

    doc = (Path(__file__).resolve().parents[1] / "docs" / "chain.md").read_text(encoding="utf-8")
    for corpus, query, outcome in SEARCHES:
        assert f"- {corpus}: \"{query}\" → {outcome}" in doc
