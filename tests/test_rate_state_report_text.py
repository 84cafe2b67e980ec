"""The rate-state report's wording and digits (referee3): what its text may claim from what it prints.

- Floquet multipliers below 1e-9 come from central differences whose noise is ~1e-10, so they are printed as
  "< 1e-9", never with digits (the committed report printed 46 such values to 6 and 10 digits, e.g.
  3.145682499e-13, while saying that only the seconds changed between runs).
- The quasi-static fate table: a stop at large ln V is *counted* as a blow-up, not shown to be one, and the
  text points to the check with slip as the clock (tests/test_rate_state_fates_in_slip.py).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from bifurcation.models.rate_state.report import MULTIPLIER_NOISE, multiplier_text

ROOT = Path(__file__).resolve().parents[1]
REPORT = ROOT / "results" / "rate-state" / "REPORT.md"


@pytest.mark.parametrize("value, digits, text", [
    (3.145682499e-13, 10, "< 1e-9"), (-4.19844e-10, 6, "< 1e-9"), (1.00213, 6, "1.00213"),
    (0.999999999983, 10, "1"), (2.0e-9, 6, "2e-09"), (0.2322214, 6, "0.232221")])
def test_multiplier_text(value, digits, text):
    assert multiplier_text(value, digits) == text


def test_the_committed_report_prints_no_multiplier_below_the_noise_with_digits():
    text = REPORT.read_text(encoding="utf-8")
    tables = re.findall(r"(?:through the fold|every 8th fold)[^\n]*\n\n?((?:\|[^\n]*\n)+)", text)
    assert len(tables) == 4          # two branches through their folds, two fold curves
    small = []
    for table in tables:
        for row in table.splitlines()[2:]:
            cells = [c.strip() for c in row.strip("|").split("|")]
            multipliers = cells[6] if len(cells) == 8 else cells[5]
            for m in multipliers.split(", "):
                if not m.startswith("<") and float(m) < MULTIPLIER_NOISE:
                    small.append(m)
    assert small == []


def test_the_fate_table_says_a_stop_is_counted_not_shown():
    text = REPORT.read_text(encoding="utf-8")
    assert "is a blow-up, the step" not in text
    assert "is counted as a blow-up by the verdict" in text
    assert (ROOT / "tests" / "test_rate_state_fates_in_slip.py").exists()


def test_the_stick_slip_paragraph_names_both_measures_from_the_branches():
    # a neutral family spanning 45.7 in ln V over a cycle whose lowest point is 15.9 below ln V_lp (the
    # committed store's quasi-static aging branch): the old text called ln V_min < −23 "10 decades" and
    # cited a case (slip law, ln V_min = −22.3) that passes only the over-a-cycle measure
    from types import SimpleNamespace as NS

    from bifurcation.models.rate_state.report import stick_slip_text

    results = [{"branch": NS(v_lp=1.0, points=[NS(ln_v_min=-15.93, ln_v_max=29.79), NS(ln_v_min=-1.0, ln_v_max=1.0)]),
                "spec": NS(label="aging, quasi-static")},
               {"branch": NS(v_lp=math.e, points=[NS(ln_v_min=-6.0, ln_v_max=4.0)]),
                "spec": NS(label="prz, inertial")}]
    text = stick_slip_text(results)
    assert "(lowest ln(V_min/V_lp): -15.93, aging, quasi-static;" in text
    assert "the widest cycle spans 45.72 in ln V over a cycle, aging, quasi-static)" in text
    assert "ln(V_max/V_min) > 23 for κ < 0.044" in text and "9.7 decades below V_lp" in text
    committed = REPORT.read_text(encoding="utf-8")
    assert "(lowest ln(V_min/V_lp): -15.93, aging, quasi-static; the widest cycle spans 45.72" in committed
