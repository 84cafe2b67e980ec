"""`bifurcation study chain` says how far its runs are on stderr, at a bounded rate (issue 21: at large N it
printed nothing for > 60 s): each counted run its events every EVENT_INTERVAL s (as `bifurcation chain`),
the study the runs done every HEARTBEAT_SECONDS while it waits for one."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

from bifurcation.run import progress as progress_module

CHAIN = {"law": "carlson-langer", "ell": 1.0, "nu": 1e-3, "ends": "free", "amplitude": 0.1}


def test_catalog_run_reports_its_events(monkeypatch, capsys):
    from bifurcation.models.chain.study import _catalog

    monkeypatch.setattr(progress_module, "EVENT_INTERVAL", 0.0)   # every piece of the run (not every 10 s)
    r = _catalog((CHAIN, {"seed": 1, "skip": 0}, 8, 0.3, 40))
    assert r["status"] == "complete"
    lines = capsys.readouterr().err.splitlines()
    assert lines and all(l.startswith("bifurcation: study chain: catalog N = 8, ν_f = 0.3: ") and " of 40 events, t = "
                         in l for l in lines), lines
    assert lines[-1].split(": ")[-1].startswith("40 of 40 events")


def test_near_half_catalog_reports_its_events(monkeypatch, capsys):
    from bifurcation.models.chain._study_mfd import _budgeted_catalog

    monkeypatch.setattr(progress_module, "EVENT_INTERVAL", 0.0)
    nh = {"seed": 1, "events": 30, "cpu": 60, "longest_event": 2.0}
    _budgeted_catalog((CHAIN, nh, 1e-3, 0.45, 8, 100.0, 0.0))
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) >= 10 and all(l.startswith("bifurcation: study chain: near ν_f = 1/2, N = 8") for l in lines)
    assert "of 30 events" in lines[-1], lines[-1]


def test_event_lines_are_rate_bounded(capsys):
    line = progress_module.event_lines("x", interval=3600.0)
    for k in range(1000):
        line(k, 1000, float(k))
    assert capsys.readouterr().err == ""   # nothing within the interval


def test_study_waiting_for_a_run_says_how_many_are_done(monkeypatch, capsys):
    from bifurcation.models.chain import study

    monkeypatch.setattr(study, "HEARTBEAT_SECONDS", 0.1)
    with ThreadPoolExecutor(2) as pool:
        futures = [("a", pool.submit(lambda: 1)), ("b", pool.submit(lambda: time.sleep(0.5) or 2))]
        t0 = time.perf_counter()
        assert [study._waiting(f, futures, t0) for _, f in futures] == [1, 2]
    lines = capsys.readouterr().err.splitlines()
    assert lines and all(l.startswith("bifurcation: study chain: 1 of 2 runs done, ") for l in lines), lines


def test_continue_prints_bautin_points_as_a_line_with_names_and_units():
    """`continue` printed them as a raw dict ({'aging': 0.41, 'slip': nan, ...}) (issue 21 walk)."""
    import math

    from bifurcation.models.rate_state.study import bautin_line

    line = bautin_line({"aging": 0.123456789, "slip": math.nan, "prz": 1.5})
    assert "{" not in line and "nan" not in line, line
    assert "η = M V_lp²/(a Dc) (dimensionless" in line and "aging 0.123457" in line and "prz 1.5" in line
    assert "slip none (l1 keeps its sign" in line
    assert bautin_line({}) == "  Bautin points: not computed ([hopf] bautin = false)"
