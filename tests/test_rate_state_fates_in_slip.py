"""The rate-state report's "Quasi-static fate below k_c" rows, followed with slip as the clock.

The engine's runs in time stop (``stalled``) near ln V ≈ 22–30 where the step falls below the resolution
of t, and the report's rule counts such a stop above ln V = 10 as a blow-up. A stall cannot tell a blow-up
from a large spike that returns (the report's Basins section), so these runs are repeated here with slip δ
as the clock — x = ln V, y = ln θ, dt/dδ = e^{−x}, a dx/dδ = k(e^{−x} − 1) − b dy/dδ — in code of its own
(scipy's Radau, not the package's ``basin.in_slip``), from the same start (steady sliding at V_lp = 1 with
ln θ raised by 0.01; a = 0.01, b = 0.015, Dc = 0.01: ``study._quasi_static_fates``).

Measured (referee3, 2026-11-26): aging κ = 0.9, slip κ = 0.9 and 0.99 reach ln V = 600 (runaway); PRZ
κ = 0.9 and 0.99 complete the maxima 2.30 and 2.48 that the report prints, then Ω = ln(Vθ/Dc) passes 25
and Radau gives up at ln V ≈ 76–81 (a finite-slip blow-up: dΩ/dδ grows like e^Ω/4 for PRZ); aging κ = 0.99
oscillates with growing spikes (ln V max 20.4, 22.6, 25.2, 28.3, 32.2, 37.0, 43.3, 51.9), each of which
returns: the engine's stall at ln V = 29.7 is on the spike that peaks at 32.2 and comes back, so that row
is a growing oscillation, not a shown blow-up.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

A, B, DC = 0.01, 0.015, 0.01


def _in_slip(law: str, kappa: float, slip_max: float):
    """(status, slip of the end / Dc, ln V at the end, Ω at the end, local maxima of ln V, ran away)."""
    from scipy.integrate import solve_ivp

    k = kappa * (B - A) / DC

    def dy(x, y):
        if law == "aging":
            return math.exp(-x - y) - 1 / DC
        if law == "slip":
            return -(x + y - math.log(DC)) / DC
        return math.exp(-x - y) - math.exp(x + y) / (4 * DC * DC)

    def f(_, u):
        g = dy(u[0], u[1])
        return [(k * (math.exp(-u[0]) - 1) - B * g) / A, g]

    def cap(_, u):
        return u[0] - 600.0
    cap.terminal = True

    c = 2.0 if law == "prz" else 1.0
    sol = solve_ivp(f, (0.0, slip_max * DC), [0.0, math.log(c * DC) + 0.01], method="Radau", rtol=1e-10,
                    atol=1e-12, events=[cap], max_step=DC / 10)
    x, y = sol.y
    maxima = [x[i] for i in range(1, x.size - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1]]
    omega = x[-1] + y[-1] - math.log(DC)
    return sol.status, sol.t[-1] / DC, x[-1], omega, maxima, bool(sol.t_events[0].size)


# aging is slow: 7.3 s of CPU on a cold run (load ~12) against slip's 3.8; the same Radau check of the same
# rule stays fast through slip κ = 0.9 here and PRZ κ = 0.9 below
@pytest.mark.parametrize("law, kappa", [pytest.param("aging", 0.9, marks=pytest.mark.slow), ("slip", 0.9)])
def test_these_rows_run_away_in_slip(law, kappa):
    # 2-4 s each; ln V = 600 is e^600 V_lp: no spike of this slider comes back from there
    _, _, x_end, _, _, away = _in_slip(law, kappa, 1000.0)
    assert away and x_end == pytest.approx(600.0)


@pytest.mark.parametrize("kappa, top", [(0.9, 2.3), pytest.param(0.99, 2.48, marks=pytest.mark.slow)])  # 2 s, 14 s
def test_prz_completes_the_printed_maximum_then_its_state_explodes(kappa, top):
    status, _, x_end, omega, maxima, _ = _in_slip("prz", kappa, 2000.0 if kappa == 0.99 else 400.0)
    # the report prints the largest completed maximum to 3 significant digits
    assert round(max(m for m in maxima if m < 10), 2) == pytest.approx(top, abs=0.006)
    # Radau stops (steps below the spacing of δ) with Ω far above any steady value (|Ω| ≲ ln 4 there) and
    # V e^70 above V_lp: the e^Ω term of PRZ's dΩ/dδ blows up in finite slip
    assert status == -1 and omega > 20 and x_end > 70


@pytest.mark.slow
def test_aging_099_stalls_on_a_spike_that_returns():
    # 38 s: the engine's run (report: stalled, largest completed maximum 28.3, stopped at ln V = 29.7)
    _, _, _, _, maxima, away = _in_slip("aging", 0.99, 5000.0)
    big = [m for m in maxima if m > 10]
    assert not away
    i = int(np.argmin([abs(m - 28.3) for m in big]))
    assert big[i] == pytest.approx(28.3, abs=0.05)      # the engine's last completed maximum
    assert big[i + 1] > 29.7 and big[i + 2] > big[i + 1]  # the stalled spike peaks above the stop, and returns
    assert np.all(np.diff(big) > 0)                       # a growing oscillation
