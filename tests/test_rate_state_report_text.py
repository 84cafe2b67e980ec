"""The rate-state report's wording and digits (referee3): what its text may claim from what it prints.

- Floquet multipliers below 1e-9 come from central differences whose noise is ~1e-10, so they are printed as
  "< 1e-9", never with digits (the committed report printed 46 such values to 6 and 10 digits, e.g.
  3.145682499e-13, while saying that only the seconds changed between runs).
- The quasi-static fate table: a stop at large ln V is *counted* as a blow-up, not shown to be one, and the
  text points to the check with slip as the clock (tests/test_rate_state_fates_in_slip.py).
"""

from __future__ import annotations

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
