"""The CSN fits of the chain report's own catalogs (issue 17: the MFD and near-1/2 sections read by
Clauset–Shalizi–Newman, not by a KS distance against 1.36/√n): results/chain/csn.json is recomputed from the
committed raw catalogs (near_half.npz, catalogs.npz). Fast: the keys (hashes of the data fitted) and two small
fits recomputed in full; slow: every fit."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bifurcation.models.chain._study_csn import CSN_SETTINGS, CsnCache, _key, csn_cell, csn_word, fit_dict

OUT = Path(__file__).resolve().parents[1] / "results" / "chain"


def _samples() -> list:
    """(label, multi-block sizes) of every committed catalog the report fits, in the report's way."""
    out = []
    z = np.load(OUT / "near_half.npz")
    for i, m in enumerate(json.loads(str(z["meta"]))):
        p, nb = z[f"potency_{i}"], z[f"n_blocks_{i}"]
        cp, cs = z[f"c_potency_{i}"], z[f"c_size_{i}"]
        tag = f"ν = {m['nu']:g}, ν_f = {m['nu_f']:g}, N = {m['n']}"
        if p.size >= 20:     # fewer events (or patches) have no statistics row (_study_mfd._row)
            out.append((tag + " events", p[nb >= 2]))
        if cp.size >= 20:
            out.append((tag + " patches", cp[cs >= 2]))
    z = np.load(OUT / "catalogs.npz")
    for i, m in enumerate(json.loads(str(z["meta"]))):
        p, nb = z[f"potency_{i}"], z[f"n_blocks_{i}"]
        out.append((f"[catalog] N = {m['n']}, ν_f = {m['nu_f']:g}", p[nb >= 2]))
    return [(t, v[v > 0]) for t, v in out if (v > 0).sum() >= 20]


def _same(got: dict, ref: dict) -> None:
    # the same numbers: the fit is deterministic (seeded bootstrap), so only rounding of a KS comparison
    # could move p on another CPU; here (the CPU that wrote csn.json) the bootstrap count must agree exactly
    assert got["n"] == ref["n"] and got["n_tail"] == ref["n_tail"] and got["bootstrap"] == ref["bootstrap"]
    assert got["p"] == ref["p"]
    for k in ("xmin", "alpha", "alpha_err", "alpha_block_err", "ks", "largest", "decades"):
        assert got[k] == pytest.approx(ref[k], rel=1e-9, abs=1e-12), k
    for alt, (r, p) in ref["ratios"].items():
        assert got["ratios"][alt][0] == pytest.approx(r, rel=1e-6, abs=1e-9)
        assert got["ratios"][alt][1] == pytest.approx(p, rel=1e-6, abs=1e-12)


def test_every_committed_fit_belongs_to_a_committed_catalog_and_every_catalog_has_its_fit():
    """csn.json holds exactly the fits of the committed catalogs' multi-block sizes (keys are hashes of the
    data and the settings): no stale fit, none missing, so --from-data never computes or reuses one."""
    fits = json.loads((OUT / "csn.json").read_text())
    keys = {_key(v, CSN_SETTINGS): (t, v) for t, v in _samples()}
    assert set(keys) == set(fits), "csn.json and the raw catalogs disagree"
    for k, (t, v) in keys.items():
        assert fits[k]["n"] == v.size and fits[k]["largest"] == float(v.max()), t
        assert fits[k]["bootstrap"] == CSN_SETTINGS["bootstrap"], t


def test_two_committed_fits_recomputed():
    """The two smallest samples refitted from the raw catalogs (B = 100 each, a few CPU seconds)."""
    fits = json.loads((OUT / "csn.json").read_text())
    for t, v in sorted(_samples(), key=lambda s: s[1].size)[:2]:
        _same(fit_dict(v), fits[_key(v, CSN_SETTINGS)])


@pytest.mark.slow
def test_every_committed_fit_recomputed():
    """Every CSN fit of the report recomputed (~5 CPU minutes on this machine)."""
    fits = json.loads((OUT / "csn.json").read_text())
    for t, v in _samples():
        _same(fit_dict(v), fits[_key(v, CSN_SETTINGS)])


def test_the_cache_refits_changed_data_and_drops_stale_fits(tmp_path):
    rng = np.random.default_rng(3)
    x = (1 - rng.random(300)) ** (-1 / 1.5)            # Pareto, α = 2.5, x_min = 1
    few = dict(CSN_SETTINGS, bootstrap=5, block_bootstrap=5)
    c = CsnCache(tmp_path)
    a = c.fit(x, few)
    c.save()
    assert c.fit(x[:10], few) is None                    # too few values: no fit, nothing stored
    c2 = CsnCache(tmp_path)
    assert c2.fit(x, few) == a and not c2.changed        # read back, not refitted
    b = c2.fit(x * 1.0000001, few)                       # other data: a fit of its own
    assert c2.changed and b["xmin"] != a["xmin"]
    c3 = CsnCache(tmp_path)
    c3.fit(x * 1.0000001, few)                           # the first sample no longer used: dropped on save
    c3.save()
    assert len(json.loads((tmp_path / "csn.json").read_text())) == 1


def test_the_words_follow_the_printed_rule():
    base = {"n": 500, "n_tail": 200, "xmin": 1.0, "alpha": 2.0, "alpha_err": 0.07, "alpha_block_err": 0.1,
            "ks": 0.03, "bootstrap": 100, "largest": 100.0, "decades": 2.0,
            "ratios": {"truncated_power_law": [-2.0, 0.01], "lognormal": [0.5, 0.6], "exponential": [5.0, 1e-6]}}
    assert csn_word(dict(base, p=0.0)) == "ruled out"       # 0 of 100: ≤ 0.030 at 95 %
    assert csn_word(dict(base, p=0.08)) == "undecided"      # 8 of 100: ≤ 0.14 at 95 %
    assert csn_word(dict(base, p=0.5)) == "plausible"
    assert csn_word(dict(base, p=0.0, bootstrap=10)) == "undecided"   # 0 of 10 bounds p only by 0.26
    assert csn_word(dict(base, p=0.5, decades=0.9)) == "no scaling range"
    cell = csn_cell(dict(base, p=0.0))
    assert "0 of 100, ≤ 0.03" in cell and "**ruled out**" in cell and "favoured: TPL" in cell
    assert math.isclose(float(cell.split("α = ")[1].split(" ±")[0]), 2.0)


def test_the_speed_headline_is_the_compiled_bench_run():
    """REPORT.md's speed table quotes results/chain/bench_compiled.txt (the compiled engine against the numba
    RK4 baselines, the interpreted RK4 as the second column): every rate and ratio of the table read back from
    that file's lines, per N."""
    import re

    text = (OUT / "bench_compiled.txt").read_text()
    report = (OUT / "REPORT.md").read_text()
    speed = report[report.index("## Speed"):report.index("### The exact (heyoka) engine")]
    rows = {int(r.split("|")[1]): [c.strip() for c in r.split("|")[2:-1]]
            for r in speed.splitlines() if re.match(r"\| \d+ \|", r)}
    blocks = re.split(r"\n  ν = ", text.split("\n# The sections below")[0])[1:]
    assert sorted(rows) == [64, 256, 1024, 4096] and len(blocks) == 4
    for b in blocks:
        n = int(re.search(r"N = +(\d+):", b).group(1))
        rate, size = re.search(r"compiled +(\d+) events/s .*mean size ([\d.]+)", b).groups()
        verify = re.search(r"largest relative difference ([\d.e+-]+)", b).group(1)
        ratio = {(kind, dt): x for kind, dt, x in re.findall(r"numba RK4 (active|plain) +dt = ([\d.]+) .*?compiled/RK4 = ([\d.]+)x", b)}
        interp = re.findall(r"dt = ([\d.]+): \d+ events/s, compiled/RK4 = ([\d.]+)x", b)
        row = rows[n]
        assert row[0] == rate and row[1] == size and row[2] == verify
        assert row[3] == f"**{ratio['active', '0.2']}×** / **{ratio['active', '0.1']}×**"
        assert row[4] == f"{ratio['plain', '0.2']}× / {ratio['plain', '0.1']}×"
        assert row[5] == " / ".join(f"{x}×" for _, x in interp)
