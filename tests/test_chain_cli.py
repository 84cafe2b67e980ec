"""``bifurcation chain`` through click's CliRunner: output keys, and one-line errors with exit 2."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models.chain import CATALOG_FIELDS

BASE = ["chain", "--law", "carlson-langer", "--ell", "1", "--nu", "1e-6", "--nu-f", "0.3"]


def _run(args):
    return CliRunner().invoke(cli, args, catch_exceptions=False)


def test_json_keys_are_the_field_names_and_match_the_api():
    res = _run(BASE + ["--n", "4", "--amplitude", "0.1", "--seed", "3", "--events", "5", "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert set(CATALOG_FIELDS) <= set(doc) and doc["events"] == 5 and doc["status"] == "complete"
    api = bf.chain("carlson-langer", n=4, ell=1.0, nu=1e-6, nu_f=0.3, amplitude=0.1, seed=3, events=5)
    for key in CATALOG_FIELDS:
        assert np.array_equal(np.array(doc[key]), api[key]), key
    assert len(doc["u"]) == 4 and len(doc["stress"]) == 4


def test_table_output_with_u0():
    res = _run(BASE + ["--n", "3", "--u0", "0,-0.1,0.05", "--events", "2", "--ends", "periodic"])
    assert res.exit_code == 0, res.output
    assert "hypocentre" in res.output and "status complete" in res.output


def test_table_numbers_are_query_s_shortest_exact_form():
    """The table prints each double as `query` does (repr: the shortest text that reads back to the same
    double; was %.15g, which lost up to 2 digits): every cell read back equals the API's value bit for bit
    (issue 21, walk 4)."""
    from bifurcation.store.query import _cell

    res = _run(BASE + ["--n", "4", "--amplitude", "0.1", "--seed", "3", "--events", "5"])
    assert res.exit_code == 0, res.output
    api = bf.chain("carlson-langer", n=4, ell=1.0, nu=1e-6, nu_f=0.3, amplitude=0.1, seed=3, events=5)
    lines = res.output.splitlines()
    assert lines[0].split() == ["event", *CATALOG_FIELDS]
    for i, line in enumerate(lines[1:6]):
        cells = line.split()
        assert int(cells[0]) == i
        for key, text in zip(CATALOG_FIELDS, cells[1:]):
            value = api[key][i]
            if key in ("hypocentre", "n_blocks"):
                assert int(text) == value, key
            else:
                assert text == _cell(float(value)) and float(text) == value, key
    assert f"status complete; t = {float(api.t)!r}\n" in res.output


_DEFAULTS = {"--law": "carlson-langer", "--ell": "1", "--nu": "1e-6", "--nu-f": "0.3", "--n": "3", "--seed": "1",
             "--amplitude": "0.1", "--events": "3"}


@pytest.mark.parametrize("change,needle", [
    ({"--n": "0"}, "n=0"),
    ({"--ell": "-1"}, "ell=-1"),
    ({"--amplitude": None, "--u0": "0,0"}, "u0="),
    ({"--amplitude": None, "--u0": "0,nan,0"}, "u0="),
    ({"--amplitude": None, "--u0": "-2,0,0"}, "≥ 1 at t = 0"),
    ({"--events": "0"}, "events=0"),
    ({"--ends": "open"}, "ends='open'"),
    ({"--amplitude": "nan"}, "amplitude"),
    ({"--amplitude": None}, "amplitude"),
    ({"--nu": "nan"}, "nu=nan"),
    ({"--nu-f": "-1"}, "--nu-f=-1"),
    ({"--law": "friction"}, "law='friction'"),
    ({"--amplitude": None, "--u0": "a,b,c"}, "--u0"),
    ({"--u0": "0,0,0"}, "u0"),
    ({"--n": "0", "--amplitude": None}, "n=0"),   # the chain is checked before its start
])
def test_bad_input_is_one_line_exit_2(change, needle):
    opts = {**_DEFAULTS, **change}
    if opts.get("--amplitude") is None:   # a start from --u0 takes no seed
        opts.pop("--seed")
    args = ["chain"] + [x for k, v in opts.items() if v is not None for x in (k, v)]
    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 2, res.output
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("bifurcation: error:"), res.output
    assert needle in lines[0]
    assert "Traceback" not in res.output


def test_api_rejects_bad_input_with_the_argument_named():
    with pytest.raises(bf.InputError, match="n=0"):
        bf.chain("carlson-langer", n=0, ell=1.0, nu=1e-6, nu_f=0.3, amplitude=0.1, events=1)
    with pytest.raises(bf.InputError, match="events"):
        bf.chain("carlson-langer", n=2, ell=1.0, nu=1e-6, nu_f=0.3, amplitude=0.1, events=2.5)
    with pytest.raises(bf.InputError, match="u0"):
        bf.chain("carlson-langer", n=2, ell=1.0, nu=1e-6, nu_f=0.3, u0=[0.0, 1.5], events=2)


def test_progress_reporting_leaves_the_catalog_bit_identical():
    # the CLI's progress line runs the events in growing pieces (ChainLoop.run called repeatedly);
    # the catalog and the final state must be those of one uninterrupted run, bit for bit
    kwargs = dict(n=6, ell=1.0, nu=1e-3, nu_f=0.3, amplitude=0.5, seed=2, events=40)
    calls = []
    whole = bf.chain("carlson-langer", **kwargs)
    pieces = bf.chain("carlson-langer", **kwargs, progress=lambda done, events, t: calls.append((done, events, t)))
    for key in (*CATALOG_FIELDS, "u", "stress"):
        assert np.array_equal(np.asarray(whole[key]).view(np.int64) if np.asarray(whole[key]).dtype.kind == "f"
                              else whole[key],
                              np.asarray(pieces[key]).view(np.int64) if np.asarray(pieces[key]).dtype.kind == "f"
                              else pieces[key]), key
    assert whole.t == pieces.t and whole.status == pieces.status
    assert len(calls) > 1 and calls[-1][:2] == (40, 40)   # pieces of 1, 2, 4, ... events: several calls
    assert [c[0] for c in calls] == sorted(c[0] for c in calls)


def test_a_flag_given_twice_is_one_line_without_an_empty_value():
    res = CliRunner().invoke(cli, BASE + ["--n", "2", "--amplitude", "0.1", "--seed", "1", "--events", "2",
                                          "--json", "--json"])
    assert res.exit_code == 2 and res.stderr.strip() == "bifurcation: error: --json is given twice: give it once"


def test_a_random_start_without_a_seed_is_refused_by_the_api_too():
    """Issue 21: ``chain(amplitude=A)`` without ``seed`` silently took seed 0; the API now asks for it,
    as the CLI does, before any work."""
    with pytest.raises(InputError) as err:
        bf.chain("carlson-langer", n=4, ell=1.0, nu=1e-3, nu_f=0.2, amplitude=0.1, events=2)
    assert err.value.argument == "seed" and "seed=1" in str(err.value)
