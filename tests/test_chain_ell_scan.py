"""The chain report's ℓ scan (issue 17, item 5; bifurcation/models/chain/_study_ell.py): which runs it makes,
the workflow's checks, the location of a known step, the checkpoint (a stopped scan resumes with the runs still
missing) and one real sweep. The committed section itself is checked by tests/test_chain_study.py (REPORT.md
rendered from results/chain/ell_scan.json)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bifurcation.errors import InputError
from bifurcation.models.chain import _study_ell as E

REPO = Path(__file__).resolve().parents[1]


def _cfg(**scan) -> dict:
    s = {"ells": [1.0, 3.0, 10.0], "sizes": [4, 16], "seeds": 3, "ratios": [0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0],
         "continuum": [4.0], "cycles_per_step": 3, "transient_cycles": 3, "amplitude": 0.1,
         "max_events_per_step": 20000, "longest_event": 0.5}
    s.update(scan)
    return {"chain": {"law": "carlson-langer", "nu": 1e-3, "ends": "free", "ell": 1.0, "amplitude": 0.1},
            "ell_scan": s}


def test_the_scan_runs_every_ell_and_size_then_the_fixed_n_over_ell_pairs_once():
    cfg = _cfg()
    assert E.pairs(cfg) == [(1.0, 4), (1.0, 16), (3.0, 4), (3.0, 16), (10.0, 4), (10.0, 16), (3.0, 12), (10.0, 40)]
    jobs = E.ell_scan_jobs(cfg)
    assert len(jobs) == 8 * 3 and {j[1][3] for j in jobs} == {1, 2, 3}
    assert E.ell_scan_jobs({"chain": cfg["chain"]}) == []


def test_the_start_amplitude_over_ell_squared_gives_every_ell_the_same_start_stress_spread():
    """A start u_j = A r_j has spring stresses ~ℓ²A: at ℓ = 10 from A = 0.1 the spread is ~30 (far above the
    threshold 1; docs/chain.md, "ℓ scan"), from A = 0.1/ℓ² as at ℓ = 1 (same seed: within a factor 1.5)."""
    from bifurcation.models.chain._validate import check_initial

    def spread(ell, a):
        u = check_initial(16, ell, "free", None, a, 1)
        lap = np.diff(np.concatenate(([u[0]], u, [u[-1]])), 2)
        s = ell**2 * lap - u
        return float(s.max() - s.min())

    assert spread(10.0, 0.1) > 20
    ref = spread(1.0, 0.1)
    for ell in (3.0, 10.0):
        assert ref / 1.5 < spread(ell, 0.1 / ell**2) < 1.5 * ref


def _write(tmp_path, cfg, d_of_ratio, longest=0.01, seeds=None):
    """ell_scan.json with synthetic runs: D(ratio) up then down, seed noise 2 %."""
    rng = np.random.default_rng(0)
    ratios = np.asarray(cfg["ell_scan"]["ratios"])
    for ell, n in E.pairs(cfg):
        for seed in range(1, (seeds or cfg["ell_scan"]["seeds"]) + 1):
            d = d_of_ratio(ratios) * (1 + 0.02 * rng.standard_normal(ratios.size))
            E.record_run(tmp_path, cfg, {"ell": ell, "n": n, "seed": seed, "cpu": 1.0,
                                         "slip_per_block": list(d) + list(d[::-1]),
                                         "longest_event": [longest] * (2 * ratios.size), "events": [10] * (2 * ratios.size),
                                         "cycles": [3.0] * (2 * ratios.size), "slip_fraction": [0.1] * (2 * ratios.size),
                                         "status": ["complete"] * (2 * ratios.size)})


def test_a_step_of_d_between_two_ratios_is_located_between_them_at_every_ell(tmp_path):
    """D falls from 0.5 to 0.01 between ν_f/ν_f* = 1.25 and 1.5: ν_½/ν_f* must lie in that bracket, ν_½ = that
    ratio × ν_f*(ℓ), and the fit over N reads 'approaches ν_f*' only if ν_f* is within 2σ (here it is not: the
    step sits at 1.25–1.5 ν_f*, so ν_∞ is several σ above ν_f*, and the words say so)."""
    cfg = _cfg(sizes=[4, 16, 64])
    _write(tmp_path, cfg, lambda r: np.where(r <= 1.25, 0.5, 0.01))
    st = E.ell_scan_stats(tmp_path, cfg)
    assert len(st["rows"]) == 11 and st["runs"] == 33
    for r in st["rows"]:
        assert 1.25 < r["half"]["value"] < 1.5, r
        assert r["star"] == pytest.approx(0.5 / math.sqrt(1 + 2 * r["ell"] ** 2))
    for ell in (1.0, 3.0, 10.0):
        f = st["fits"][f"{ell:g}"]
        assert f["fit"]["points"] == 3
        assert 1.25 < f["fit"]["nu_inf"] / E.star(ell) < 1.5
        assert f["words"][0] != "approaches ν_f*"
    # the section renders with one row per (ℓ, N) and one fit row per ℓ
    from bifurcation.report.document import Table, flatten

    tables = [b for b in flatten(E.ell_scan_section(cfg, st)) if isinstance(b, Table)]
    assert len(tables[0].rows) == 11 and len(tables[1].rows) == 3


def test_steps_with_merged_slides_are_left_out(tmp_path):
    """An event longer than longest_event (0.5 loading cycles) in a step leaves D out there (NaN), as in [sweep]."""
    cfg = _cfg(ells=[3.0], sizes=[16], continuum=[])
    _write(tmp_path, cfg, lambda r: np.where(r <= 1.25, 0.5, 0.01), longest=0.6)
    (r,) = E.ell_scan_stats(tmp_path, cfg)["rows"]
    assert all(r["merged_up"]) and all(math.isnan(x) for x in r["d_up"])
    assert not math.isfinite(r["half"]["value"])


def test_a_stopped_scan_resumes_with_the_runs_still_missing(tmp_path):
    """Each run is kept in ell_scan.json as it finishes: the jobs left are the others; adding sizes or seeds keeps
    the kept runs, changing how a run is made (cycles_per_step) drops them."""
    cfg = _cfg(ells=[3.0], sizes=[4, 16], continuum=[])
    _write(tmp_path, cfg, lambda r: 0.5 - 0.1 * r, seeds=2)       # seeds 1, 2 of 3 done
    left = E.missing_jobs(tmp_path, cfg)
    assert sorted((j[1][1], j[1][2], j[1][3]) for j in left) == [(3.0, 4, 3), (3.0, 16, 3)]
    assert len(E.missing_jobs(tmp_path, _cfg(ells=[3.0], sizes=[4, 16, 64], continuum=[]))) == 2 + 3
    assert len(E.missing_jobs(tmp_path, _cfg(ells=[3.0], sizes=[4, 16], continuum=[], cycles_per_step=2))) == 6
    assert E.ell_scan_stats(tmp_path, cfg)["rows"] == []     # no (ℓ, N) has all its seeds: nothing located
    doc = json.loads((tmp_path / E.ELL_FILE).read_text())
    assert len(doc["runs"]) == 4 and "sizes" not in doc["settings"]


def test_one_real_sweep_of_the_scan():
    """One (ℓ, N, seed) of the scan on the engine: D per step up and down, the amplitude scaled by 1/ℓ²."""
    st = E.settings(_cfg(ratios=[0.5, 1.0, 2.0, 3.0], cycles_per_step=0.3, transient_cycles=0.3))
    r = E._ell_sweep((st, 3.0, 4, 1))
    assert len(r["slip_per_block"]) == 8 and r["n"] == 4 and r["ell"] == 3.0
    assert all(s == "complete" for s in r["status"])
    assert all(c >= 0.3 for c in r["cycles"])


@pytest.mark.parametrize("key, value, words", [
    ("ratios", [1.0, 0.5, 2.0, 3.0], "ell_scan.ratios"),
    ("ratios", [0.5, 1.0], "ell_scan.ratios"),
    ("ratios", [0.5, 1.0, 2.0, 1e9], "ell_scan.ratios"),
    ("continuum", [0.01], "ell_scan.continuum"),
    ("ells", [-1.0], "ell_scan.ells[0]"),
    ("seeds", 0, "ell_scan.seeds"),
])
def test_the_workflow_refuses_a_bad_ell_scan_naming_the_key(tmp_path, key, value, words):
    import tomllib

    from bifurcation.models.chain.study_workflow import load_report_workflow

    text = (REPO / "workflows" / "chain-report.toml").read_text()
    doc = tomllib.loads(text)
    assert "ell_scan" in doc
    i = text.index("\n[ell_scan]") + 1
    scan = dict(doc["ell_scan"], **{key: value})
    body = "\n".join(f"{k} = {json.dumps(v)}" for k, v in scan.items())
    (tmp_path / "w.toml").write_text(text[:i] + "[ell_scan]\n" + body + "\n")
    with pytest.raises(InputError) as exc:
        load_report_workflow(tmp_path / "w.toml")
    assert str(exc.value).startswith(words) or words in str(exc.value)


def test_ell_scan_only_is_refused_with_another_run_or_without_data(tmp_path):
    from click.testing import CliRunner

    from bifurcation.cli import cli

    wf = str(REPO / "workflows" / "chain-report.toml")
    r = CliRunner().invoke(cli, ["study", "chain", wf, "--out", str(tmp_path), "--ell-scan-only", "--from-data"])
    assert r.exit_code == 2 and "--ell-scan-only" in r.output and "Traceback" not in r.output
    r = CliRunner().invoke(cli, ["study", "chain", wf, "--out", str(tmp_path), "--ell-scan-only"])
    assert r.exit_code == 2 and "data.json" in r.output
    assert not any(tmp_path.iterdir())


def test_a_workflow_without_an_ell_scan_is_refused_by_ell_scan_only(tmp_path):
    import tomllib

    from click.testing import CliRunner

    from bifurcation.cli import cli

    text = (REPO / "workflows" / "chain-report.toml").read_text()
    (tmp_path / "w.toml").write_text(text[:text.index("\n[ell_scan]") + 1])
    assert "ell_scan" not in tomllib.loads((tmp_path / "w.toml").read_text())
    r = CliRunner().invoke(cli, ["study", "chain", str(tmp_path / "w.toml"), "--out", str(tmp_path / "o"),
                                 "--ell-scan-only"])
    assert r.exit_code == 2 and "has no [ell_scan] table" in r.output and len(r.output.strip().splitlines()) == 1


def test_a_stop_while_keeping_a_run_leaves_the_earlier_ell_scan_json_whole(tmp_path, monkeypatch):
    """record_run writes beside and renames (as data.json's _write_data): a stop inside the write keeps every run
    kept before it, and leaves no partial file."""
    cfg = _cfg(ells=[3.0], sizes=[4], continuum=[])
    _write(tmp_path, cfg, lambda r: 0.5 - 0.1 * r, seeds=2)
    before = (tmp_path / E.ELL_FILE).read_text()
    write_text = Path.write_text

    def half_then_stop(self, text, *args, **kwargs):
        write_text(self, text[: len(text) // 2], *args, **kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(Path, "write_text", half_then_stop)
    run = json.loads(before)["runs"][0]
    with pytest.raises(KeyboardInterrupt):
        E.record_run(tmp_path, cfg, dict(run, seed=3))
    monkeypatch.undo()
    assert (tmp_path / E.ELL_FILE).read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [E.ELL_FILE]
