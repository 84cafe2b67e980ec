"""A defined transition point and its finite-size scaling (issue 17, item 5), on synthetic curves whose
answer is known by construction: the half-way crossing (crossing.locate, the one implementation the chain
report and transition.py's study share) and transition.scale_transition."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bifurcation.models.chain.crossing import locate
from bifurcation.models.chain.transition import scale_transition


def _step(x, x0, width, hi=1.0, lo=0.1):
    return lo + (hi - lo) / (1 + np.exp((x - x0) / width))


def test_a_symmetric_step_crosses_half_near_its_centre():
    # a logistic step is symmetric about x0 = 0.525: its half level (hi + lo)/2 is crossed at x0. The lower
    # plateau (points within 10 % of the drop above the minimum) also holds the step's tail at 0.55
    # (0.168), which raises the level; the crossing by the definition, worked by hand, moves < 1e-3
    x = np.linspace(0.2, 0.8, 13)
    y = _step(x, 0.525, 0.01)
    out = locate(x, y, np.full_like(x, 1e-4), samples=2000)["half"]
    level = 0.5 * (y[0] + y[x >= 0.549].mean())
    by_hand = 0.5 + 0.05 * (y[6] - level) / (y[6] - y[7])
    assert out["value"] == pytest.approx(by_hand, abs=1e-12) and abs(by_hand - 0.525) < 1e-3
    assert out["statistical"] < 1e-3    # tiny errors of y give a tiny statistical error ...
    # ... but the grid cannot place a step much narrower than its spacing: the grid error (linear against
    # log interpolation in the bracket) is a sizeable part of the bracket, and below half of it
    assert 0.002 < out["grid"] < 0.025 and out["sigma"] >= out["grid"]


def test_the_error_grows_with_the_noise_and_is_about_right():
    # a step between grid points: x* = x_i + Δx (y_i − L)/(y_i − y_(i+1)), L = (y_0 + mean(y_4, y_5, y_6))/2;
    # to first order ∂x*/∂y = Δx/Δy × (−1/2, 1/2, 1/3, −1/6, −1/6) for y_0, y_3, y_4, y_5, y_6 (y_4 is in
    # the bracket and the plateau), so σ_x = σ_y Δx/Δy √(2/3). Bounds ±15 %: the bootstrap's σ from 4000
    # draws scatters ~1 %, the linearisation is off by ~(σ_y/Δy)² ~ 5e-4, and a plateau point leaves the
    # plateau (> 0.09 above the minimum, ~3σ) in a few draws
    x = np.array([0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6])
    y = np.array([1.0, 1.0, 1.0, 1.0, 0.1, 0.1, 0.1])
    out = locate(x, y, np.full_like(x, 0.02), samples=4000)["half"]
    assert out["value"] == pytest.approx(0.475, abs=1e-12)
    expected = 0.02 * 0.05 / 0.9 * math.sqrt(2 / 3)
    assert 0.85 * expected < out["statistical"] < 1.15 * expected


def test_no_crossing_no_number():
    x = np.linspace(0.2, 0.8, 7)
    out = locate(x, np.ones(7), np.full(7, 0.01), samples=200)["half"]
    assert math.isnan(out["value"]) and out["status"] == "no drop"
    # a fall of 0.03 from D at the smallest ν_f to the plateau's mean (4 points), against
    # σ = √(0.02² + (0.02/√4)²) = 0.022: within 2σ, no transition
    out = locate(x, [1.0, 0.99, 0.98, 0.97, 0.97, 0.97, 0.97], np.full(7, 0.02), samples=200)
    assert math.isnan(out["half"]["value"]) and out["half"]["status"].startswith("no drop beyond 2σ")
    assert math.isnan(out["width"]["value"]) and math.isnan(out["window"]["value"])


def test_the_limit_of_a_known_scaling_is_recovered():
    rng = np.random.default_rng(2)
    n = np.array([8, 16, 32, 64, 128, 256])
    truth = 0.5 + 0.4 * n**-1.0
    s = np.full(n.size, 2e-4)
    out = scale_transition(n, truth + rng.standard_normal(n.size) * s, s)
    assert abs(out["limit"] - 0.5) < 3 * out["limit_sigma"] + 1e-4
    assert out["theta"] == pytest.approx(1.0, abs=0.2) and out["dof"] == 3


def test_three_sizes_interpolate_and_say_so():
    out = scale_transition([4, 16, 64], [0.6, 0.55, 0.52], [0.01, 0.01, 0.01])
    assert out["dof"] == 0 and "interpolates" in out["reason"]
    assert math.isnan(scale_transition([4, 16], [0.6, 0.55], [0.01, 0.01])["limit"])
