"""Published parameter sets as named presets (issue 17, item 3; bifurcation/models/chain/presets.py)."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli
from bifurcation.models.chain import chain
from bifurcation.models.chain.presets import PRESETS, get_preset
from bifurcation.workflow import parse_workflow

PARAMS = ("law", "n", "ell", "nu", "nu_f", "sigma", "ends")


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_every_number_says_where_it_was_read(name):
    p = get_preset(name)
    assert set(p.provenance) >= set(PARAMS) - {"ends"} and all(p.provenance.values())
    unread = [k for k, v in p.provenance.items() if "NOT READ" in v]
    assert p.verified == (not unread), unread       # verified only when every number was read


def test_only_the_seed_preset_is_verified():
    assert [n for n, p in PRESETS.items() if p.verified] == ["vasconcelos-1996"]


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_a_preset_is_its_parameters_given_explicitly(name):
    p = get_preset(name).parameters()
    n = min(p["n"], 12)                 # small chains: the test checks the filling, not the physics
    a = chain(preset=name, n=n, amplitude=0.5, seed=2, events=4)
    b = chain(p["law"], n=n, ell=p["ell"], nu=p["nu"], nu_f=p["nu_f"], sigma=p["sigma"], ends=p["ends"],
              amplitude=0.5, seed=2, events=4)
    for f in ("t_start", "potency", "n_blocks", "hypocentre"):
        assert np.array_equal(a[f], b[f]), f
    assert (a.nu, a.nu_f, a.ell, a.sigma, a.ends) == (p["nu"], p["nu_f"], p["ell"], p["sigma"], p["ends"])


def test_given_values_win_over_the_preset():
    r = chain(preset="carlson-langer-1991", n=8, sigma=0.05, nu_f=0.3, amplitude=0.5, seed=1, events=2)
    assert (r.sigma, r.nu_f, r.ell) == (0.05, 0.3, 10.0)


def test_unknown_or_missing():
    with pytest.raises(bf.InputError, match="preset"):
        chain(preset="carlson-langer", amplitude=0.5, seed=1, events=1)
    with pytest.raises(bf.InputError, match="law"):
        chain(n=3, ell=1.0, nu=1e-3, nu_f=0.3, amplitude=0.5, seed=1, events=1)


@pytest.mark.parametrize("args,needle", [
    (["--preset", "nope"], "--preset"),
    (["--preset", ""], "--preset"),
    (["--n", "4"], "--law"),                        # no preset: the law is missing
    (["--preset", "carlson-langer-1991", "--sigma", "1"], "--sigma"),
])
def test_cli_bad_preset_input_is_one_line_exit_2(args, needle):
    res = CliRunner().invoke(cli, ["chain", *args, "--amplitude", "0.5", "--seed", "1", "--events", "2"])
    assert res.exit_code == 2, res.output
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and needle in lines[0] and "Traceback" not in res.output


def test_cli_preset_is_the_api():
    import json

    res = CliRunner().invoke(cli, ["chain", "--preset", "mori-kawamura-2006", "--n", "10", "--amplitude", "0.5",
                                   "--seed", "3", "--events", "3", "--json"], catch_exceptions=False)
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    api = chain(preset="mori-kawamura-2006", n=10, amplitude=0.5, seed=3, events=3)
    assert doc["potency"] == api.potency.tolist() and doc["ends"] == "periodic" and doc["sigma"] == 0.01


WF = """
[study]
name = "preset-test"
[model]
name = "{model}"
preset = "{preset}"
[grid.n]
values = [12]
[grid.amplitude]
values = [0.5]
[grid.seed]
values = [1]
[grid.events]
values = [5]
"""


def test_a_workflow_preset_fills_the_axes_it_leaves_out():
    w = parse_workflow(WF.format(model="chain", preset="carlson-langer-1991") + "[grid.sigma]\nvalues = [0.0, 0.01]\n")
    grid = dict(w.grid)
    assert w.laws == ("carlson-langer",)
    assert grid["ell"] == (10.0,) and grid["nu"] == (0.01,) and grid["nu_f"] == (0.2,) and grid["periodic"] == (0,)
    assert grid["n"] == (12,) and grid["sigma"] == (0.0, 0.01)      # the grid's own values win


@pytest.mark.parametrize("model,preset,needle", [("chain", "nope", "model.preset"),
                                                 ("single-block", "vasconcelos-1996", "model.preset")])
def test_a_workflow_refuses_a_bad_preset(model, preset, needle):
    with pytest.raises(bf.InputError, match=needle):
        parse_workflow(WF.format(model=model, preset=preset))
