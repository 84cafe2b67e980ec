"""A defined transition point and its finite-size scaling (issue 17, item 5), on synthetic curves whose
answer is known by construction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bifurcation.models.chain.transition import half_crossing, scale_transition


def _step(x, x0, width, hi=1.0, lo=0.1):
    return lo + (hi - lo) / (1 + np.exp((x - x0) / width))


def test_a_symmetric_step_crosses_half_at_its_centre():
    # a logistic step is symmetric about x0: its half level is crossed exactly at x0 (up to the linear
    # interpolation between grid points, zero here as x0 is on the grid's midpoint symmetry)
    x = np.linspace(0.2, 0.8, 13)
    y = _step(x, 0.525, 0.01)
    out = half_crossing(x, y, np.full_like(x, 1e-4), plateau=2)
    assert out["nu_f"] == pytest.approx(0.525, abs=1e-6) and out["bracket"] == (0.5, 0.55)
    assert out["statistical"] < 1e-3    # tiny errors of y give a tiny statistical error ...
    # ... but the grid cannot place a step much narrower than its spacing: the grid error (linear against
    # log interpolation in the bracket) is a sizeable part of the bracket, and below half of it
    assert 0.002 < out["grid"] < 0.025 and out["sigma"] >= out["grid"]


def test_the_error_grows_with_the_noise_and_is_about_right():
    # linear ramp between the brackets: x* moves by δy/slope; slope = Δy/Δx = 0.9/0.05 over one interval,
    # so σ_x ≈ σ_y·Δx/Δy·√(1/2) (two points of the bracket, each weighted ~1/2) ≈ 0.02·0.05/0.9·0.71
    x = np.array([0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6])
    y = np.array([1.0, 1.0, 1.0, 1.0, 0.1, 0.1, 0.1])
    out = half_crossing(x, y, np.full_like(x, 0.02), plateau=2, draws=4000)
    assert out["nu_f"] == pytest.approx(0.475, abs=1e-12)
    expected = 0.02 * 0.05 / 0.9 * math.sqrt(0.5)
    assert 0.6 * expected < out["statistical"] < 1.6 * expected


def test_no_crossing_no_number():
    x = np.linspace(0.2, 0.8, 7)
    out = half_crossing(x, np.ones(7), np.full(7, 0.01))
    assert math.isnan(out["nu_f"]) and out["reason"]


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
