"""The words of the chain report's finite-size fits (_study_text.fss_words): a decay counts as "vanishes" only
when the constant is rejected by its χ² test at 5 %, not by χ²/dof > 2 (with 3 degrees of freedom χ²/dof 2.3
is p ≈ 0.07, which the committed report's D jump had)."""

import math

import pytest

from bifurcation.models.chain._study_text import chi2_p, fss_words


def _fit(theta, sigma, chi2_c, dof_c=3):
    return {"points": dof_c + 1, "theta": theta, "theta_sigma": sigma, "chi2_power": 0.6, "dof_power": dof_c - 1,
            "constant": 0.1, "constant_sigma": 0.005, "chi2_constant": chi2_c, "dof_constant": dof_c,
            "sizes": [4, 16, 64, 256][:dof_c + 1]}


@pytest.mark.parametrize("chi2,dof", [(6.9, 3), (4.0, 2), (17.3 * 3, 3), (0.3, 3)])
def test_chi2_p_matches_scipy(chi2, dof):
    stats = pytest.importorskip("scipy.stats")
    # scipy's χ² survival function is an independent implementation; both are accurate to ~1e-14 here
    assert chi2_p(chi2, dof) == pytest.approx(stats.chi2.sf(chi2, dof), rel=1e-10)


def test_chi2_p_without_dof_is_nan():
    assert math.isnan(chi2_p(1.0, 0))


def test_decay_with_constant_not_rejected_is_undecided():
    # the committed report's D jump: θ = 0.14 ± 0.05, constant χ²/dof 2.3 over 4 sizes (p ≈ 0.07)
    verdict, words = fss_words(_fit(0.14, 0.05, 2.3 * 3))
    assert verdict == "undecided"
    assert "a constant is not rejected" in words and "p = 0.07" in words


def test_decay_with_constant_rejected_vanishes():
    verdict, words = fss_words(_fit(0.14, 0.05, 3.0 * 3))    # χ² = 9 with 3 dof: p = 0.029
    assert verdict == "vanishes" and words.startswith("decreases with N")


def test_persists_grows_and_rejected_constant_without_trend():
    assert fss_words(_fit(0.02, 0.05, 0.9))[0] == "persists"
    assert fss_words(_fit(-0.52, 0.12, 52.0))[0] == "grows"
    verdict, words = fss_words(_fit(0.02, 0.05, 30.0))
    assert verdict == "undecided" and "a constant is rejected" in words
