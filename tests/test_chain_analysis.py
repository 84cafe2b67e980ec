"""Chain statistics against samples with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bifurcation.models.chain.analysis import (b_value, finite_size_fit, hysteresis, magnitude_frequency,
                                               recurrence, spanning_excess, sweep_nu_f)


def test_b_value_recovers_a_known_gutenberg_richter_law():
    """Magnitudes drawn from the GR law with b = 1.2 above m_min = 0 (m − m_min exponential with mean
    log10(e)/b): the Aki–Utsu estimate is within 3σ (σ = b/√n, Aki 1965) of 1.2."""
    rng = np.random.default_rng(7)
    m = rng.exponential(math.log10(math.e) / 1.2, 20000)
    fit = b_value(10 ** m, m_min=0.0)
    assert abs(fit["b"] - 1.2) <= 3 * fit["sigma"]
    assert abs(fit["sigma"] - 1.2 / math.sqrt(20000)) < 1e-3


def test_magnitude_frequency_counts_and_potency_add_up():
    p = 10 ** np.random.default_rng(1).uniform(-2, 1, 500)
    mfd = magnitude_frequency(p, per_decade=10)
    assert mfd["counts"].sum() == 500
    assert math.isclose(mfd["potency"].sum(), p.sum(), rel_tol=1e-12)
    assert np.allclose(np.diff(mfd["edges"]), 0.1)


def test_spanning_excess_and_recurrence():
    rng = np.random.default_rng(2)
    m = rng.exponential(math.log10(math.e), 5000)
    p = np.concatenate((10 ** m, np.full(50, 10 ** 6)))      # 50 events far beyond GR (expected ~1e-2)
    nb = np.concatenate((np.ones(5000, int), np.full(50, 64)))
    fit = b_value(p, m_min=0.0, m_max=5.0)
    ex = spanning_excess(p, nb, 64, fit)
    assert ex["spanning"] == 50 and ex["excess"] > 1000
    t = np.arange(5050, dtype=float)
    rc = recurrence(t, nb == 64)
    assert rc["count"] == 50 and rc["cv"] == 0.0


def test_truncated_b_value_is_the_maximum_likelihood_of_a_truncated_exponential():
    """Magnitudes from GR with b = 1.0 truncated to [0, 1.5] (inverse-CDF sampling): Page's estimator is
    within 3σ of 1.0, Aki's untruncated formula is biased high far beyond its σ, and the Fisher σ
    matches the spread of the estimates over 200 independent samples of 2000 (to 15 %: the standard
    error of a standard deviation from 200 samples is 5 %)."""
    rng = np.random.default_rng(11)
    beta, width = math.log(10), 1.5

    def sample(k):
        u = rng.uniform(size=k)
        return -np.log1p(-u * (1 - math.exp(-beta * width))) / beta

    m = sample(20000)
    fit = b_value(10 ** m, m_min=0.0, m_max=width)
    assert abs(fit["b"] - 1.0) <= 3 * fit["sigma"]
    aki = b_value(10 ** m, m_min=0.0)
    assert aki["b"] - 1.0 > 10 * aki["sigma"]
    fits = [b_value(10 ** sample(2000), m_min=0.0, m_max=width) for _ in range(200)]
    spread = np.std([f["b"] for f in fits], ddof=1)
    assert abs(spread / np.mean([f["sigma"] for f in fits]) - 1) < 0.15


def test_b_value_refuses_samples_without_a_decreasing_tail():
    """Uniform magnitudes on [0, 1] have mean 1/2 = Δ/2: no decreasing exponential fits (NaN, not b ≈ 0)."""
    m = np.linspace(0, 1, 1001)
    assert math.isnan(b_value(10 ** m, m_min=0.0, m_max=1.0)["b"])
    assert math.isnan(b_value(np.ones(5), m_min=0.0)["b"])


def test_finite_size_fit_on_exact_and_noisy_power_laws():
    """Exact y = 2 N^-0.5: θ = 0.5 and A = 2 to rounding, χ² = 0, the constant fit rejected. Noisy data
    (5 % Gaussian errors, 400 draws): |θ̂ − 0.5| ≤ σ_θ in 68 ± 7 % of the draws (binomial 3σ at n = 400),
    and the closed-form σ_θ equals the least-squares one computed independently with numpy.polyfit."""
    sizes = np.array([4, 16, 64, 256])
    y = 2 * sizes**-0.5
    fit = finite_size_fit(sizes, y, 0.05 * y)
    assert abs(fit["theta"] - 0.5) < 1e-12 and abs(fit["amplitude"] - 2) < 1e-12 and fit["chi2_power"] < 1e-20
    assert fit["chi2_constant"] / fit["dof_constant"] > 100
    _, cov = np.polyfit(np.log(sizes), np.log(y), 1, w=np.full(4, 1 / 0.05), cov="unscaled")
    assert math.isclose(fit["theta_sigma"], math.sqrt(cov[0, 0]), rel_tol=1e-10)
    rng = np.random.default_rng(5)
    hits = 0
    for _ in range(400):
        f = finite_size_fit(sizes, y * (1 + 0.05 * rng.standard_normal(4)), 0.05 * y)
        hits += abs(f["theta"] - 0.5) <= f["theta_sigma"]
    assert abs(hits / 400 - 0.683) < 0.07
    flat = finite_size_fit(sizes, np.full(4, 0.3), np.full(4, 0.01))
    assert abs(flat["theta"]) < 1e-12 and flat["chi2_constant"] < 1e-20
    assert finite_size_fit([1, 4], [0.0, 0.1], [0.1, 0.1])["points"] == 1     # y = 0 cannot enter ln y


def test_hysteresis_jump_width_and_area_of_a_known_loop():
    """up = 1,1,0,0 and down = 1,1,1,0 on ν_f = 0,1,2,3: jump 1 between 1 and 2 (downwards), width 1
    at 2, area 1 (trapezoid weight of the inner point 1); σ from the standard errors."""
    se = np.full(4, 0.1)
    h = hysteresis([0, 1, 2, 3], [1, 1, 0, 0], [1, 1, 1, 0], se, se)
    assert h["jump"] == 1 and h["jump_sign"] == -1 and h["jump_at"] == [1.0, 2.0]
    assert h["width"] == 1 and h["width_at"] == 2 and h["area"] == 1
    assert math.isclose(h["jump_sigma"], 0.1 * math.sqrt(2)) and math.isclose(h["width_sigma"], 0.1 * math.sqrt(2))
    assert math.isclose(h["area_sigma"], math.sqrt(2 * 0.01 * (0.25 * 2 + 1 + 1)))
    # a step left out (NaN): a jump across the gap is not a neighbouring change and is not measured
    gap = hysteresis([0, 1, 2, 3], [1, np.nan, 0, 0], [1, np.nan, 1, 0], se, se)
    assert gap["jump"] == 0 and gap["jump_at"] == [2.0, 3.0] and gap["width"] == 1 and gap["area"] == 1
    assert math.isnan(hysteresis([0, 1], [np.nan, np.nan], [1, 1], se[:2], se[:2])["jump"])


def test_sweep_of_one_block_gives_the_single_block_delta():
    """N = 1: every event spans the chain and starts stuck at σ = 1, so D (slip per block per event) is
    the single block's Δ (bifurcation.slip) to rounding (1e-12: the mean of equal potencies), and
    Ψ = closure = 1 up to one event's slip over the step's loading (Δ/cycles ≤ 0.3 here, 0.1 measured)."""
    import bifurcation as bf

    nus = [0.2, 0.3, 0.2]
    out = sweep_nu_f("carlson-langer", n=1, ell=1.0, nu=1e-3, nu_f_values=nus, cycles_per_step=3.0)
    assert all(s == "complete" for s in out["status"]) and min(out["cycles"]) >= 3.0
    for nf, d in zip(nus, out["slip_per_block"]):
        assert abs(d / float(bf.slip("carlson-langer", nu=1e-3, nu_f=nf).delta) - 1) < 1e-12
    assert np.allclose(out["psi"], out["closure"]) and np.all(np.abs(np.array(out["psi"]) - 1) < 0.3)
    # one event lasts ~10 time units against a recurrence of ~Δ/ν ~ 1000: the block is mostly stuck
    assert all(0 < f < 0.05 for f in out["slip_fraction"]) and all(0 < e < 0.05 for e in out["longest_event"])


def test_sweep_steps_are_measured_in_loading_cycles():
    """N = 16: each step runs until the driver has advanced 2 units of slip per block (never less, and
    at most one event's recurrence more); the event cap stops a step early and says so in ``cycles``."""
    out = sweep_nu_f("carlson-langer", n=16, ell=1.0, nu=1e-3, nu_f_values=[0.25, 0.45], cycles_per_step=2.0)
    assert all(2.0 <= c < 3.0 for c in out["cycles"]) and min(out["events"]) > 10
    assert all(abs(c - 1) < 0.3 for c in out["closure"])
    capped = sweep_nu_f("carlson-langer", n=16, ell=1.0, nu=1e-3, nu_f_values=[0.25], cycles_per_step=2.0,
                        max_events_per_step=3)
    assert capped["events"] == [3] and capped["cycles"][0] < 2.0


@pytest.mark.slow   # 3 s; the chain's report section and its figure stay fast in test_chain_store.py
def test_report_runner_writes_study_figures_and_data(tmp_path):
    """A tiny workflow through the report runner: every section, the figures, data.json, and a Speed
    section of an existing REPORT.md carried over unchanged."""
    import json

    from bifurcation.models.chain.study import main

    out = tmp_path / "out"
    out.mkdir()
    (out / "REPORT.md").write_text("# old\n\n## Speed (bench)\n\nrates 1.5x\n\n## Verdict\nold verdict\n")
    wf = tmp_path / "tiny.toml"
    wf.write_text(f"""
[study]
name = "tiny"
out = "{out}"
workers = 2
[chain]
law = "carlson-langer"
ell = 1.0
nu = 1e-3
ends = "free"
amplitude = 0.1
[sweep]
sizes = [1, 4, 8, 16]
seeds = [1, 2, 2, 2]
nu_f = [0.2, 0.4]
nu_f_max = [0.4, 0.4, 0.4, 0.4]
cycles_per_step = [1, 1, 1, 1]
transient_cycles = 1
max_events_per_step = 500
[catalog]
sizes = [8]
events = [150]
nu_f = [0.2]
seed = 1
skip = 20
[threshold]
ells = [1.0]
nus = [1e-6]
level = 0.01
scan_nu = 1e-6
scan_points = 5
[near_half]
nus = [1e-3, 1e-4]
nu_f = [[0.45], [0.5]]
sizes = [[4, 8, 16], [8]]
cycles = [[20, 10, 5], [1]]
events = 400
transient_cycles = 1
longest_event = 2.0
cpu = 20
seed = 1
[sweep_small_nu]
nu = 1e-4
sizes = [1, 4]
seeds = [1, 2]
nu_f = [0.3, 0.5]
cycles_per_step = [1, 0.5]
transient_cycles = 0.5
[ell_scan]
ells = [1.0, 3.0]
sizes = [4]
seeds = 2
ratios = [0.5, 1.0, 1.5, 2.0]
cycles_per_step = 0.5
transient_cycles = 0.5
amplitude = 0.1
max_events_per_step = 500
""")
    main([str(wf)])
    text = (out / "REPORT.md").read_text()
    for head in ("## Lone-block threshold", "## Order parameter", "### Finite-size scaling", "## Magnitude–frequency",
                 "## Speed (bench)", "## Verdict table (issue 17)", "## Readings of the σ = 0, ℓ = 1 runs"):
        assert head in text
    assert "rates 1.5x" in text and "old verdict" not in text
    # the ℓ scan through the full run: its 4 sweeps kept in ell_scan.json, its section rendered from them
    scan = json.loads((out / "ell_scan.json").read_text())
    assert sorted((r["ell"], r["n"], r["seed"]) for r in scan["runs"]) == [(1.0, 4, 1), (1.0, 4, 2), (3.0, 4, 1), (3.0, 4, 2)]
    assert "### ℓ scan (1, 3) and the continuum limit" in text and (out / "fig_ell_scan.png").is_file()
    for fig in ("fig_order", "fig_fss", "fig_mfd", "fig_threshold"):
        assert (out / f"{fig}.png").stat().st_size > 1000
    data = json.loads((out / "data.json").read_text())
    assert [r["n"] for r in data["sweeps"]["table"]] == [1, 4, 8, 16]
    assert data["catalogs"][0]["events"] == 130
    assert data["sweeps"]["fss"]["slip_per_block.jump"]["points"] == 3
    # the near-1/2 catalogs: each stopped by a bound it names, none before its transient was over
    nh = data["near_half"]
    assert [(r["nu"], r["n"]) for r in nh["rows"]] == [(1e-3, 4), (1e-3, 8), (1e-3, 16), (1e-4, 8)]
    for r in nh["rows"]:
        assert r["cut"] in ("events", "cycles", "cpu", "long event") and r["events"] <= 400
        assert r["cut"] != "cycles" or r["cycles"] >= r["cycles_asked"]
    assert nh["groups"][0]["fss"]["cutoff"]["points"] == 3 and nh["groups"][0]["reading"][0] in (
        "critical-like", "characteristic-size", "undecided")
    # the same catalogs by connected slip patches: every event has at least one patch
    assert [(r["nu"], r["n"]) for r in nh["patch_rows"]] == [(r["nu"], r["n"]) for r in nh["rows"]]
    assert all(p["events"] >= r["events"] for p, r in zip(nh["patch_rows"], nh["rows"]))
    assert "### By connected slip patches" in text
    assert (out / "fig_mfd_half.png").stat().st_size > 1000
    assert "## Magnitude–frequency near ν_f = 1/2" in text and "### The sweep at ν = 0.0001" in text
    assert [r["n"] for r in data["sweeps_small_nu"]["table"]] == [1, 4]
    # re-rendered from data.json and near_half.npz without runs: the same report body
    main([str(wf), "--from-data"])
    assert (out / "REPORT.md").read_text() == text
