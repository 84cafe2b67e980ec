"""Cutoff potency, tapered Gutenberg–Richter fit and their reading, against samples with known laws."""

from __future__ import annotations

import math

import numpy as np

from bifurcation.models.chain.analysis import finite_size_fit
from bifurcation.models.chain.scaling import mfd_reading, moment_cutoff, tapered_gr


def _tapered(rng, k, b, corner, a=1.0):
    """Tapered Pareto: the minimum of a Pareto (survival (P/a)^-b) and a + Exp(corner) has survival
    (P/a)^-b e^{-(P-a)/corner}, the product of the two (Kagan 2002, Vere-Jones et al. 2001)."""
    pareto = a * rng.uniform(size=k) ** (-1 / b) if b > 0 else np.full(k, np.inf)
    return np.minimum(pareto, a + rng.exponential(corner, k))


def test_moment_cutoff_of_a_gamma_law_and_its_batch_error():
    """Gamma(shape k, scale s): ⟨P⟩ = ks, ⟨P²⟩/⟨P⟩ = (k + 1)s exactly. 40 000 draws: within 3σ of the
    batch-means σ; over 150 samples of 2000 the mean batch σ equals the spread of the estimates to 15 %
    (10 batches: each σ has 9 degrees of freedom, ~24 % scatter; the spread of 150 is known to ~6 %)."""
    rng = np.random.default_rng(3)
    k, s = 0.4, 25.0
    c = moment_cutoff(rng.gamma(k, s, 40000))
    assert abs(c["cutoff"] - (k + 1) * s) <= 3 * c["cutoff_sigma"]
    assert abs(c["mean"] - k * s) <= 3 * c["mean_sigma"]
    fits = [moment_cutoff(rng.gamma(k, s, 2000)) for _ in range(150)]
    spread = np.std([f["cutoff"] for f in fits], ddof=1)
    assert abs(np.mean([f["cutoff_sigma"] for f in fits]) / spread - 1) < 0.15
    assert math.isnan(moment_cutoff([1.0, 2.0, 3.0])["cutoff_sigma"]) and moment_cutoff([2.0, 2.0])["cutoff"] == 2.0


def test_moment_cutoff_follows_the_corner_of_a_power_law():
    """P^-(1+b) tapered at P_ξ with b = 0.5 (τ = 1.5 in (1, 2)): doubling P_ξ from 1e3 to 2e3 doubles
    ⟨P²⟩/⟨P⟩ as P_ξ → ∞ (to the lower cut's correction ~ (a/P_ξ)^(2−τ) ≈ 3 % here; 10 % allowed with the
    sampling error of 200 000 draws, σ ≈ 2 %)."""
    rng = np.random.default_rng(4)
    c1 = moment_cutoff(_tapered(rng, 200000, 0.5, 1e3))["cutoff"]
    c2 = moment_cutoff(_tapered(rng, 200000, 0.5, 2e3))["cutoff"]
    assert abs(c2 / c1 - 2) < 0.2


def test_tapered_gr_recovers_b_and_corner():
    """b = 0.6, corner 200 above a = 1: both within 3σ (Fisher) from 20 000 draws; KS accepts the fitted
    law; the likelihood ratio against the pure power law is far beyond χ²₁'s 3.84. Over 150 samples of
    1500 the Fisher σ of b covers |b̂ − b| in 68 % ± 11 % of them (binomial 3σ at n = 150)."""
    rng = np.random.default_rng(5)
    f = tapered_gr(_tapered(rng, 20000, 0.6, 200.0), 1.0)
    assert abs(f["b"] - 0.6) <= 3 * f["b_sigma"] and abs(f["gamma"] - 1 / 200) <= 3 * f["gamma_sigma"]
    assert abs(f["corner"] - 200) <= 3 * f["corner_sigma"]
    assert f["ks"] < f["ks_crit"] and f["lr"] > 50
    hits = sum(abs((g := tapered_gr(_tapered(rng, 1500, 0.6, 200.0), 1.0))["b"] - 0.6) <= g["b_sigma"]
               for _ in range(150))
    assert abs(hits / 150 - 0.683) < 0.11


def test_tapered_gr_limits_pure_power_law_and_exponential():
    """A pure Pareto (b = 0.8) gives γ within 2σ of 0 (or exactly 0 at the boundary) and b within 3σ;
    an exponential of scale 30 above a = 1 (b = 0) gives b within 3σ of 0 and the corner within 3σ
    of 30. The p_min scale is carried: the same data in units 1000× smaller give the same b and a
    corner 1000× smaller."""
    rng = np.random.default_rng(6)
    pl = tapered_gr(rng.uniform(size=20000) ** (-1 / 0.8), 1.0)
    assert pl["gamma"] <= 2 * pl["gamma_sigma"] and abs(pl["b"] - 0.8) <= 3 * pl["b_sigma"] and pl["lr"] < 9
    x = 1 + rng.exponential(30.0, 20000)
    ex = tapered_gr(x, 1.0)
    assert ex["b"] <= 3 * ex["b_sigma"] and abs(ex["corner"] - 30) <= 3 * ex["corner_sigma"]
    small = tapered_gr(x / 1000, 1e-3)
    assert math.isclose(small["b"], ex["b"], rel_tol=1e-9, abs_tol=1e-12)
    assert math.isclose(small["corner"], ex["corner"] / 1000, rel_tol=1e-9)
    assert math.isnan(tapered_gr([1.0, 2.0, 3.0], 1.0)["b"])        # fewer than 10 events


def _rows(rng, sizes, b, corners, excess):
    return [{"n": n, "tapered": tapered_gr(_tapered(rng, 4000, b, c), 1.0), "spanning_excess": e}
            for n, c, e in zip(sizes, corners, excess)]


def test_mfd_reading_tells_the_two_pictures_apart():
    """Critical-like: one b = 0.5 at every N, corner ∝ N. Characteristic-size: an exponential law (b = 0).
    With two sizes only, or a cutoff that does not grow: undecided, naming the failed test."""
    rng = np.random.default_rng(8)
    sizes = [16, 64, 256]
    crit = _rows(rng, sizes, 0.5, [n * 2.0 for n in sizes], [math.nan] * 3)
    cut = finite_size_fit(sizes, [2.0 * n for n in sizes], [0.1 * n for n in sizes])
    span = finite_size_fit(sizes, [0.01, 0.003, 0.001], [0.001, 0.0003, 0.0001])
    word, why = mfd_reading(crit, cut, span)
    assert word == "critical-like" and "N^1.00" in why
    flat = finite_size_fit(sizes, [30.0, 30.5, 29.5], [1.0, 1.0, 1.0])
    assert mfd_reading(crit, flat, span)[0] == "undecided" and "does not grow" in mfd_reading(crit, flat, span)[1]
    expo = [{"n": n, "tapered": tapered_gr(1 + rng.exponential(n / 4, 4000), 1.0), "spanning_excess": 10.0}
            for n in sizes]
    assert mfd_reading(expo, cut, span)[0] == "characteristic-size"
    assert mfd_reading(crit[:2], cut, span)[0] == "undecided"
    # the same critical-like samples from catalogs whose chain is rarely all stuck: merged events, undecided
    busy = [dict(r, slip_fraction=f) for r, f in zip(crit, (0.3, 0.6, 0.9))]
    word, why = mfd_reading(busy, cut, span)
    assert word == "undecided" and "60 % (N = 64), 90 % (N = 256)" in why


def test_slip_clusters_split_an_event_at_blocks_that_did_not_move():
    """Hand-made slip vectors: patches are the runs of moving blocks, potencies their sums; periodic
    ends join a patch across the ends; no slip gives no patch."""
    from bifurcation.models.chain.scaling import slip_clusters

    s = np.array([0.5, 0.25, 0, 0, 1.0, 0, 0.125, 0.125, 0.25])
    n, p = slip_clusters(s)
    assert n.tolist() == [2, 1, 3] and p.tolist() == [0.75, 1.0, 0.5]
    n, p = slip_clusters(s, periodic=True)
    assert n.tolist() == [5, 1] and p.tolist() == [1.25, 1.0]
    assert slip_clusters(np.ones(4), periodic=True)[0].tolist() == [4]
    assert slip_clusters(np.zeros(4))[0].size == 0
    assert slip_clusters(np.array([0, 1.0, 1.0, 0]), periodic=True)[0].tolist() == [2]


def test_slip_clusters_of_a_chain_event_add_up_to_its_potency():
    """A real N = 64 catalog near ν_f = 1/2 (where one event holds several separate slips): per event the
    patches' potencies add up to the catalogued potency (to rounding, 1e-12 relative: sums of the same
    increments in another order), their blocks to at most n_blocks (a block that started and stopped
    without moving is counted by the catalog only), and some event splits into ≥ 2 patches."""
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._loop import ChainLoop
    from bifurcation.models.chain._validate import check_initial
    from bifurcation.models.chain.scaling import slip_clusters

    loop = ChainLoop(resolve_law("carlson-langer"), 64, 1.0, 1e-3, 0.5, "free", check_initial(64, 1.0, "free", None, 0.1, 1))
    split = 0
    for _ in range(150):
        u = loop.u.copy()
        e = loop.run(1)["catalog"]
        n, p = slip_clusters(loop.u - u)
        assert abs(p.sum() - float(e["potency"][0])) <= 1e-12 * float(e["potency"][0])
        assert n.sum() <= int(e["n_blocks"][0])
        split += n.size >= 2
    assert split > 0
