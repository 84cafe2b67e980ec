"""Period doubling, the doubling cascade and torus detection from Floquet multipliers."""

import numpy as np
import pytest

from bifurcation.models.rate_state.doubling import crossings


def test_crossings_of_the_unit_circle_on_a_synthetic_sequence():
    # Multipliers along a made-up branch: a real pair turns complex (not a crossing), the pair turns real
    # again on the negative axis, one multiplier passes −1 between points 3 and 4 (a doubling); then a
    # real one passes +1 (a fold) and a complex pair's modulus passes 1 (0.949 → 1.012: a torus).
    seq = [(0.5, 0.1), (0.3 + 0.2j, 0.3 - 0.2j), (-0.2 + 0.3j, -0.2 - 0.3j), (-0.6, -0.05), (-1.3, -0.02),
           (-2.0, -0.01)]
    assert crossings(seq) == [(3, "period-doubling")]
    assert crossings([(0.99, 0.1), (1.01, 0.1)]) == [(0, "fold")]
    assert crossings([(0.9 + 0.3j, 0.9 - 0.3j), (0.95 + 0.35j, 0.95 - 0.35j)]) == [(0, "torus")]
    # moving about inside (or outside) the circle is no crossing; nor is a multiplier on −1's far side
    assert crossings([(-0.9, 0.2), (-0.95, 0.3), (0.4 + 0.5j, 0.4 - 0.5j), (0.5 + 0.6j, 0.5 - 0.6j)]) == []
    assert crossings([(-1.5, 0.2), (-2.5, 0.1)]) == []
