"""The defined transition of the chain report (crossing.py, _study_transition.py): the locators against
synthetic D(ν_f) with closed-form answers, the bootstrap error's coverage, and the committed report's section
against the stored data."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bifurcation.models.chain.crossing import half_crossing, locate, location_fit, location_words, slope_peak

GRID = np.round(np.arange(0.15, 0.651, 0.05), 10)    # the report's ν_f grid
ROOT = Path(__file__).resolve().parents[1]


def _ramp(x, hi, lo, a, b):
    """hi below a, lo above b, straight in between: the half-way level (hi + lo)/2 is crossed at (a + b)/2."""
    return np.where(x <= a, hi, np.where(x >= b, lo, hi + (lo - hi) * (x - a) / (b - a)))


def test_half_crossing_closed_form():
    # a = 0.26, b = 0.40: the crossing (a + b)/2 = 0.33 lies between grid points 0.3 and 0.35, both on the
    # straight part, so linear interpolation is exact (to rounding: 1e-12)
    y = _ramp(GRID, 0.7, 0.05, 0.26, 0.40)
    x, status = half_crossing(GRID, y)
    assert status == "ok" and abs(x - 0.33) < 1e-12
    # a left-out step (NaN) away from the crossing changes nothing
    y2 = y.copy()
    y2[-2] = np.nan
    assert abs(half_crossing(GRID, y2)[0] - 0.33) < 1e-12


def test_no_lower_plateau_gives_no_number():
    # only the last kept point lies within 10 % of the drop above the minimum: N = 256's up branch
    y = np.array([0.541, 0.444, 0.383, 0.321, 0.265] + [np.nan] * 6)
    x, status = half_crossing(GRID, y)
    assert math.isnan(x) and status == "no lower plateau on the grid"
    r = locate(GRID, y, np.full(GRID.size, 0.01), samples=200)
    assert math.isnan(r["half"]["value"]) and math.isnan(r["width"]["value"]) and math.isnan(r["window"]["value"])


def test_slope_peak_closed_form():
    # D = −[(x − x0) − (x − x0)³/(3 s²)]: −D' = 1 − (x − x0)²/s². A finite difference of a cubic is the mean
    # of D' over the interval, D'(m) + D'''h²/24, so the differences are exactly a parabola in the midpoint m
    # with its vertex at x0: the parabola vertex returns x0 to rounding
    x0, s = 0.41, 0.5
    y = -((GRID - x0) - (GRID - x0) ** 3 / (3 * s**2))
    peak, top, status = slope_peak(GRID, y)
    assert status == "ok" and abs(peak - x0) < 1e-12
    # its height: 1 − ((m − x0)² + h²/12)/s² at the midpoint m = 0.425 nearest x0 (mean of t² over the interval)
    assert abs(top - (1 - ((0.425 - x0) ** 2 + 0.05**2 / 12) / s**2)) < 1e-12
    # a peak on the first interval is not located
    y_edge = np.exp(-GRID / 0.05)      # steepest at the smallest ν_f
    assert slope_peak(GRID, y_edge)[2] == "peak at the grid's edge"


@pytest.mark.slow     # ~12 s: 200 × 300 bootstrap relocations
def test_bootstrap_error_covers_the_true_crossing():
    """Coverage of ν_½ ± 2σ over noisy copies of the closed-form ramp: a 2σ interval should hold the true
    0.33 about 95 % of the time; with 200 trials the binomial spread is ±1.5 %, so [0.88, 0.995] fails only
    for a σ off by ~25 % or more (both too small and too large)."""
    rng = np.random.default_rng(7)
    true = _ramp(GRID, 0.7, 0.05, 0.26, 0.40)
    se = np.full(GRID.size, 0.02)
    hits = 0
    for k in range(200):
        y = true + se * rng.standard_normal(GRID.size)
        r = locate(GRID, y, se, samples=300, seed=k)["half"]
        hits += abs(r["value"] - 0.33) <= 2 * r["sigma"]
    assert 0.88 <= hits / 200 <= 0.995, hits


def test_location_fit_and_words():
    n = np.array([4, 16, 64])
    f = location_fit(n, 0.30 + 0.2 / n, [0.01] * 3)      # exactly ν_∞ + a/N: recovered, χ² = 0
    assert abs(f["nu_inf"] - 0.30) < 1e-12 and abs(f["slope"] - 0.2) < 1e-10 and f["chi2"] < 1e-20
    star = 0.5 / math.sqrt(3)
    assert location_words(f, star)[0] == "approaches ν_f*"
    assert location_words(location_fit(n, 0.50 + 0.2 / n, [0.005] * 3), star)[0] == "approaches 1/2"
    assert location_words(location_fit(n, 0.40 + 0.0 / n, [0.005] * 3), star)[0] == "approaches neither"
    assert location_words(location_fit(n, 0.40 + 0.0 / n, [0.2] * 3), star)[0] == "undecided"     # both within 2σ
    assert location_words(location_fit(n[:2], [0.3, 0.3], [0.01] * 2), star)[0] == "undecided"    # 2 sizes
    assert location_words(location_fit(n, [0.3, 0.4, 0.3], [0.001] * 3), star)[0] == "undecided"  # χ²/dof > 2


@pytest.fixture(scope="module")
def committed():
    out = ROOT / "results" / "chain"
    return json.loads((out / "data.json").read_text()), (out / "REPORT.md").read_text()


@pytest.mark.slow     # ~8 s: the report's 16 curves × 2000 draws
def test_report_section_is_the_stored_data(committed):
    """The committed section is what the stored D(ν_f) give now (seeded bootstrap: identical text)."""
    from bifurcation.models.chain._study_transition import transition_section, transition_stats
    from bifurcation.report.document import to_markdown

    data, report = committed
    st = transition_stats(data)
    text = to_markdown(transition_section(st))
    body = text[text.index("The jump above"):].strip()
    assert body in report
    # the numbers the section and the verdicts rest on (from the same data; rounding as printed)
    rows = {(r["nu"], r["n"], r["branch"]): r for r in st["rows"]}
    assert math.isnan(rows[(1e-3, 256, "up")]["half"]["value"])             # no crossing invented at N = 256
    assert abs(rows[(1e-3, 4, "up")]["half"]["value"] - 0.306) < 5e-4
    assert abs(rows[(1e-3, 1, "up")]["peak"]["value"] - 0.46) < 5e-4          # single block: nearer 1/2


def test_verdict_rows_read_the_defined_transition(committed):
    _, report = committed
    vas = next(line for line in report.splitlines() if line.startswith("| Vasconcelos (1996): the transition"))
    sak = next(line for line in report.splitlines() if line.startswith("| Sakaguchi (2002)"))
    for row in (vas, sak):
        assert "ν_½: N = 1: 0.382 ± 0.001; N = 4: 0.306 ± 0.009" in row and "W: N = 1: " in row
        assert "largest change of D per N" not in row and "FSS of that change" not in row
    assert "**undecided: at ν = 0.001 no chain's change is step-like" in sak.rsplit("|", 2)[-2]
    assert "it follows no one transition and is not read" in vas          # the old figure kept only as labelled


def test_grid_error_is_the_log_interpolation_difference():
    # the ramp's level 0.375 lies in the bracket 0.30 → 0.35 (y = 0.51429, 0.28214): interpolated in ln y it
    # sits at 0.30 + 0.05 ln(0.375/y0)/ln(y1/y0); the linear one is exact (0.33); the difference by hand
    from bifurcation.models.chain.crossing import grid_error

    y = _ramp(GRID, 0.7, 0.05, 0.26, 0.40)
    y0, y1 = 0.7 - 0.65 * 0.04 / 0.14, 0.7 - 0.65 * 0.09 / 0.14
    expected = abs(0.30 + 0.05 * math.log(0.375 / y0) / math.log(y1 / y0) - 0.33)
    assert abs(grid_error(GRID, y) - expected) < 1e-12 and expected > 1e-3
    r = locate(GRID, y, np.zeros(GRID.size), samples=50)       # no noise: σ is the grid error alone
    assert abs(r["half"]["sigma"] - expected) < 1e-12 and r["half"]["statistical"] == 0
