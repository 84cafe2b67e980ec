"""The chain report's preset CSN fits say what their KS number is (tidy, after referee3's rs-chain fix).

`powerlaw`'s D uses the empirical CDF (i − 1)/n at the i-th smallest size (powerlaw-devs/powerlaw issue #111;
tests/test_rs_chain_report_ks.py pins that convention), so the two-sided supremum lies in [D, D + 1/n_tail].
The preset catalogs are not kept (_study_presets.py, subevent_study.py), so REPORT.md and PUBLISHED_NU.md label
D and give that upper bound, rounded up at the 4th decimal; D and n_tail are read from the committed
results/chain/data.json and subevents_*.json.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "results" / "chain"


def test_the_chain_report_labels_powerlaws_d_and_bounds_the_two_sided_value():
    text = (ROOT / "REPORT.md").read_text(encoding="utf-8")
    assert not re.search(r"\bKS 0\.\d{4};", text), "an unlabelled 'KS 0.xxxx;' (powerlaw's D) is back"
    assert "issue #111" in text
    fits = [x["fit"] for x in json.loads((ROOT / "data.json").read_text(encoding="utf-8"))["presets"] if x.get("fit")]
    assert fits
    for f in fits:
        m = re.search(rf"KS \(powerlaw's D\) {f['ks']:.4f}, two-sided ≤ (0\.\d{{4}});", text)
        assert m, f"preset fit with D = {f['ks']:.4f} not labelled"
        # the printed bound is ≥ D + 1/n_tail and not more than one unit of the 4th decimal above it
        bound = float(m.group(1))
        assert f["ks"] + 1 / f["n_tail"] <= bound + 1e-12 < f["ks"] + 1 / f["n_tail"] + 1e-4 + 1e-12


def test_published_nu_page_labels_powerlaws_d_too():
    """PUBLISHED_NU.md (subevent_study.write_report, from the committed subevents_*.json) the same way."""
    text = (ROOT / "PUBLISHED_NU.md").read_text(encoding="utf-8")
    assert not re.search(r"\bKS 0\.\d{4};", text) and "issue #111" in text
    fits = [json.loads(q.read_text(encoding="utf-8"))["fit"] for q in sorted(ROOT.glob("subevents_*.json"))]
    assert fits
    for f in fits:
        m = re.search(rf"KS \(powerlaw's D\) {f['ks']:.4f}, two-sided ≤ (0\.\d{{4}});", text)
        assert m, f"fit with D = {f['ks']:.4f} not labelled"
        assert f["ks"] + 1 / f["n_tail"] <= float(m.group(1)) + 1e-12 < f["ks"] + 1 / f["n_tail"] + 1e-4 + 1e-12
