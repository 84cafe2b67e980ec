"""Chain statistics against samples with known answers."""

from __future__ import annotations

import math

import numpy as np

from bifurcation.models.chain.analysis import (b_value, magnitude_frequency, recurrence, spanning_excess,
                                               sweep_nu_f)


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


def test_sweep_of_one_block_releases_all_slip_in_spanning_events():
    """N = 1: every event spans the chain, so Ψ = 1 up to the O(1/k) loading left over at each step."""
    out = sweep_nu_f("carlson-langer", n=1, ell=1.0, nu=1e-3, nu_f_values=[0.2, 0.3, 0.2], events_per_step=20)
    assert all(s == "complete" for s in out["status"])
    assert np.all(np.abs(np.array(out["psi"]) - 1) < 0.1)


def test_report_runner_writes_report_figures_and_data(tmp_path):
    """A tiny workflow through the report runner: REPORT.md with both tables, figures, data.json."""
    import json

    from bifurcation.models.chain.report import main

    wf = tmp_path / "tiny.toml"
    wf.write_text(f"""
[study]
name = "tiny"
out = "{tmp_path / 'out'}"
[chain]
law = "carlson-langer"
ell = 1.0
nu = 1e-3
ends = "free"
amplitude = 0.1
seed = 1
[catalog]
n = 8
nu_f = [0.2]
events = 120
skip = 20
[sweep]
sizes = [1, 4]
nu_f = [0.2, 0.3]
events_per_step = [5, 5]
""")
    main([str(wf)])
    out = tmp_path / "out"
    text = (out / "REPORT.md").read_text()
    assert "Aki–Utsu" in text and "Loop width" in text
    assert (out / "fig_mfd.png").stat().st_size > 1000 and (out / "fig_hysteresis.png").stat().st_size > 1000
    data = json.loads((out / "data.json").read_text())
    assert [s["n"] for s in data["sweeps"]] == [1, 4] and data["catalogs"][0]["events"] == 100
