"""Adversarial checks of the event-exact chain engine (bifurcation/models/chain/_loop.py): ties,
degenerate sizes, extreme parameters and bad input, each against an independent reference (the
single-block engine ``bifurcation.slip``, closed forms, quad precision) or a law of physics.

Each test is small (N ≤ 16, a few events) and fast; the bugs they pin down are named in their
docstrings."""

from __future__ import annotations

import numpy as np
import pytest

import bifurcation as bf
from bifurcation.models.chain import ChainStatus, chain


def test_blocks_tied_with_the_hypocentre_start_with_it_at_small_nu():
    """Two uncoupled blocks (ℓ = 0) with the same displacement c fail at the same instant: each event
    is two single blocks, so its duration is the single-block engine's ``stop_time`` (start to stop).
    σ = −c with −c + (1 + c) = 1 − 2⁻⁵³ in double: the quiescent jump σ_j + (1 − max σ) left the
    partner 1.1e-16 below threshold, it started 1.1e-16/ν later and the event lasted 1.2e-5 (relative)
    too long at ν = 1e-12 (found by this test; fixed: σ_j − max σ + 1). Tolerance 1e-14: the two
    engines agree to ~1e-16 on this event (measured 1.1e-16)."""
    c = 0.11632244573811656
    assert -c + (1 + c) < 1                         # the rounding that broke the tie
    for nu in (1e-9, 1e-12):
        single = bf.slip("carlson-langer", nu=nu, nu_f=0.2)
        u0 = np.full(12, 200.0)
        u0[3] = u0[8] = c
        r = chain("carlson-langer", n=12, ell=0.0, nu=nu, nu_f=0.2, u0=u0, events=3)
        assert list(r.n_blocks) == [2, 2, 2] and list(r.hypocentre) == [3, 3, 3]
        assert np.max(np.abs(r.duration / float(single.stop_time) - 1)) <= 1e-14
        assert np.max(np.abs(r.potency / (2 * float(single.delta)) - 1)) <= 1e-14
