"""Workflow specs: strict TOML validation (every refusal names its key), exact grids, shipped workflows."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from bifurcation.errors import InputError
from bifurcation.workflow import Workflow, load_workflow, parse_workflow

WORKFLOWS = Path(__file__).resolve().parents[1] / "workflows"

VALID = """
[study]
name = "t"

[engine]
laws = ["carlson-langer"]

[grid.nu]
values = [1e-9]

[grid.nu_f]
values = [0.4]
"""

# (TOML text, the key the refusal must name). Each is VALID with one thing wrong.
MALFORMED = [
    (VALID + "[sutdy]\nname = 'x'\n", "sutdy"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nprecison = "quad"'), "engine.precison"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = "carlson-langer"'), "engine.laws"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["no-such-law"]'), "engine.laws[0]"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer", "carlson-langer"]'), "engine.laws[1]"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nprecision = "single"'), "engine.precision"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nt_max = -1.0'), "engine.t_max"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nmax_steps = 1.5'), "engine.max_steps"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nbatch = 0'), "engine.batch"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nbatch = "8"'), "engine.batch"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nbatch = 65'), "engine.batch"),
    (VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nbatch = 8\nprecision = "quad"'),
     "engine.batch"),
    (VALID.replace("values = [1e-9]", "log = { start = 1e-3, stop = 1e-15, per_decade = 0 }"), "grid.nu.log.per_decade"),
    (VALID.replace("values = [1e-9]", "log = { start = 1e-3, stop = 1e-15, per_decade = 4.0 }"), "grid.nu.log.per_decade"),
    (VALID.replace("values = [1e-9]", "log = { start = 1e-3, stop = 1e-15, per_decade = 4, num = 49 }"),
     "grid.nu.log.per_decade"),
    (VALID.replace("values = [1e-9]", "log = { start = 1e-3, stop = 1e-25, per_decade = 4 }"), "grid.nu.log.stop"),
    (VALID.replace("values = [1e-9]", "values = [1e-9, 0.0]"), "grid.nu.values[1]"),
    (VALID.replace("values = [1e-9]", "values = [1e-9, 2.0]"), "grid.nu.values[1]"),
    (VALID.replace("values = [1e-9]", 'values = ["1e-9"]'), "grid.nu.values[0]"),
    (VALID.replace("values = [1e-9]", "values = []"), "grid.nu.values"),
    (VALID.replace("values = [1e-9]", "step = 4"), "grid.nu.step"),
    (VALID.replace("values = [0.4]", "ranges = [{ start = 0.6, stop = 0.4, num = 3 }]"), "grid.nu_f.ranges[0].stop"),
    (VALID.replace("values = [0.4]", "ranges = [{ start = 0.1, stop = 0.4, num = 1 }]"), "grid.nu_f.ranges[0].num"),
    (VALID.replace("values = [0.4]", "ranges = [{ start = 0.1, stop = 0.4, n = 4 }]"), "grid.nu_f.ranges[0].n"),
    (VALID.replace("values = [0.4]", "ranges = [{ start = 0.1, stop = 0.4 }]"), "grid.nu_f.ranges[0].num"),
    (VALID.replace("values = [0.4]", "values = [0.4, -0.1]"), "grid.nu_f.values[1]"),
    (VALID.replace('name = "t"', 'name = "a/b"'), "study.name"),
    (VALID.replace('name = "t"', 'title = "t"'), "study.title"),
    (VALID.replace('name = "t"', ""), "study.name"),
    (VALID + "[tiles]\nnu = 0\n", "tiles.nu"),
    (VALID + "[tiles]\nnu_f = true\n", "tiles.nu_f"),
    (VALID + "[tiles]\nnu_f = 4096\nnu = 4096\n", "tiles"),
    (VALID.split("[grid.nu]")[0], "grid"),
    (VALID.replace("[grid.nu_f]\nvalues = [0.4]", "[grid.nu_f]"), "grid.nu_f"),
    (VALID.replace("values = [0.4]", "values = [0.4"), "workflow"),
]


@pytest.mark.parametrize("text, key", MALFORMED, ids=[k for _, k in MALFORMED])
def test_malformed_workflow_is_refused_naming_the_key(text, key):
    with pytest.raises(InputError) as info:
        parse_workflow(text)
    message = str(info.value)
    assert info.value.argument == key
    assert message.startswith((f"{key}=", f"{key} is missing"))   # a key not given: "grid is missing; ..."
    assert "\n" not in message


def test_valid_base_parses():
    w = parse_workflow(VALID)
    assert (w.laws, w.nu, w.nu_f, w.precision, w.tiles) == (("carlson-langer",), (1e-9,), (0.4,), "double", (64, 64))


def test_missing_file_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"^workflow=.*no such file"):
        load_workflow(tmp_path / "nope.toml")


def test_direct_construction_is_validated_and_frozen():
    with pytest.raises(InputError, match=r"^grid\.nu="):
        Workflow(name="x", laws=("carlson-langer",), nu=[2.0], nu_f=[0.4])
    with pytest.raises(InputError, match=r"^tiles\.nu="):
        Workflow(name="x", laws=("carlson-langer",), nu=[1e-9], nu_f=[0.4], tiles=(8, 0))
    w = Workflow(name="x", laws=["carlson-langer"], nu=[1e-3, 1e-9, 1e-9], nu_f=[0.5, 0.4])
    assert w.nu == (1e-9, 1e-3) and w.nu_f == (0.4, 0.5)   # sorted, deduplicated
    with pytest.raises(dataclasses.FrozenInstanceError):
        w.nu = (1e-3,)


def test_range_points_are_the_decimals_a_user_types():
    w = parse_workflow(VALID.replace("values = [0.4]", "ranges = [{ start = 0.0001, stop = 1.0001, num = 11 }]")
                       .replace("[grid.nu_f]", "[grid.nu_f]\nvalues = [0.3001, 0.4]"))
    # numpy.linspace gives 0.30010000000000003 here; the decimal range gives 0.3001, so the explicit
    # value deduplicates with it and 0.4 stays a separate, exact point
    assert w.nu_f.count(0.3001) == 1 and 0.4 in w.nu_f
    assert len(w.nu_f) == 12
    assert w.nu_f == tuple(sorted({*(round(0.0001 + k / 10, 4) for k in range(11)), 0.4}))


def test_log_axis_has_both_ends_exact_powers_and_per_decade():
    w = parse_workflow(VALID.replace("values = [1e-9]", "log = { start = 1e-3, stop = 1e-15, per_decade = 4 }"))
    assert len(w.nu) == 49 and w.nu[0] == 1e-15 and w.nu[-1] == 1e-3
    for k in range(3, 16):
        assert float(f"1e-{k}") in w.nu
    ratios = [math.log10(b / a) for a, b in zip(w.nu, w.nu[1:])]
    assert max(ratios) == pytest.approx(0.25, rel=1e-12)
    # 2.5 decades at 4 per decade: 10 intervals, 11 points, both ends kept
    w = parse_workflow(VALID.replace("values = [1e-9]", "log = { start = 1e-3, stop = 3.1622776601683795e-6, per_decade = 4 }"))
    assert len(w.nu) == 11 and w.nu[0] == 3.1622776601683795e-6 and w.nu[-1] == 1e-3


def test_fingerprint_ignores_formatting_but_not_the_grid():
    w = parse_workflow(VALID)
    reformatted = parse_workflow("# a comment\n" + VALID.replace('name = "t"', 'name = "renamed"\ndescription = "d"'))
    assert reformatted.fingerprint == w.fingerprint and reformatted.sha256 != w.sha256
    assert parse_workflow(VALID.replace("[1e-9]", "[1e-9, 1e-6]")).fingerprint != w.fingerprint
    assert parse_workflow(VALID + "[tiles]\nnu = 8\n").fingerprint != w.fingerprint
    round_trip = parse_workflow(w.to_toml())
    assert round_trip == w and round_trip.fingerprint == w.fingerprint


def test_shipped_workflows():
    fig2 = load_workflow(WORKFLOWS / "paper-fig2.toml")
    assert fig2.laws == ("piecewise-linear",) and 1e-9 in fig2.nu and len(fig2.nu) >= 3
    assert 0 < min(fig2.nu_f) and max(fig2.nu_f) < 1 and len(fig2.nu_f) >= 100

    fig3 = load_workflow(WORKFLOWS / "paper-fig3.toml")
    assert fig3.laws == ("carlson-langer",) and 1e-9 in fig3.nu and 0.4 in fig3.nu_f
    assert 0 < min(fig3.nu_f) and max(fig3.nu_f) < 1

    cp = load_workflow(WORKFLOWS / "critical-point.toml")
    assert set(cp.laws) == {"piecewise-linear", "carlson-langer"}
    assert {0.2, 0.3, 0.4, 0.5} <= set(cp.nu_f)
    band = [x for x in cp.nu_f if 0.45 <= x <= 0.55]
    assert len(band) >= 50 and 0.45 in band and 0.55 in band
    assert cp.nu[0] == 1e-15 and cp.nu[-1] == 1e-3
    for k in range(3, 15):   # at least 4 points in every decade [1e-(k+1), 1e-k)
        assert sum(10.0 ** -(k + 1) <= x < float(f"1e-{k}") for x in cp.nu) >= 4
    # all three together run in well under a minute on 2 cores (~35 µs a point)
    assert fig2.n_points + fig3.n_points + cp.n_points < 50_000


def test_batch_round_trips_and_changes_the_fingerprint_only_when_used():
    plain = parse_workflow(VALID)
    batched = parse_workflow(VALID.replace('laws = ["carlson-langer"]', 'laws = ["carlson-langer"]\nbatch = 8'))
    assert batched.batch == 8 and parse_workflow(batched.to_toml()) == batched
    # batch results equal scalar ones to rounding only, so a batched study is another study; batch = 1
    # (the default) leaves the fingerprints of existing stores as they were
    assert batched.fingerprint != plain.fingerprint
    assert parse_workflow(VALID.replace('laws = ["carlson-langer"]',
                                        'laws = ["carlson-langer"]\nbatch = 1')).fingerprint == plain.fingerprint
