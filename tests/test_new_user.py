"""What a new user meets on a first walk (issue 21): a clean checkout after the commands, outputs that
say what they are, one vocabulary across CLI, store and reports."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli

REPO = Path(__file__).resolve().parents[1]


@pytest.mark.skipif(shutil.which("git") is None or not (REPO / ".git").exists(), reason="needs a git checkout")
@pytest.mark.parametrize("path", [
    "results/local/paper/REPORT.md",             # reproduce's default --out
    "results/local/rate-state/branches.zarr",    # continue's default --out
    "results/local/chain/fig_mfd.png",           # workflows/chain-report.toml's out
    "results/critical-point.zarr/zarr.json",     # submit's default store
])
def test_default_outputs_are_ignored_by_git(path):
    """What the README's commands write by default is ignored: the checkout stays clean."""
    done = subprocess.run(["git", "check-ignore", "-q", path], cwd=REPO)
    assert done.returncode == 0, f"{path} would show in git status"


def test_default_out_of_reproduce_and_continue_is_not_a_committed_directory():
    from bifurcation.cli._analysis import reproduce

    default = next(p.default for p in reproduce.params if p.name == "out")
    assert default == "results/local/paper"
    text = (REPO / "workflows" / "chain-report.toml").read_text()
    assert 'out = "results/local/chain"' in text


def test_continue_branch_store_is_read_like_any_store(tmp_path):
    """status/query/verify read continue's committed branches.zarr (a store of the model rate-state-branches
    since issue 20; tests/test_branch_store.py reads a small one through report --store too)."""
    committed = REPO / "results" / "rate-state" / "branches.zarr"
    r = CliRunner().invoke(cli, ["status", "--store", str(committed)])
    assert r.exit_code == 0 and "531/531 points done (100.0%), 0 failed" in r.output, r.output   # 9 branches × 59
    r = CliRunner().invoke(cli, ["query", "--store", str(committed), "--law", "prz, quasi-static", "--point", "0",
                                 "--json"])
    assert r.exit_code == 0 and '"criticality": "subcritical"' in r.output, r.output
    r = CliRunner().invoke(cli, ["verify", "--store", str(committed)])
    assert r.exit_code == 0 and "0 damaged" in r.output, r.output


def test_an_older_branch_store_is_named_for_what_it_is(tmp_path):
    """A branches.zarr of continue before it wrote through the store layer: one line saying what to do."""
    import numpy as np
    import xarray as xr

    old = tmp_path / "branches.zarr"
    xr.Dataset({"kappa": (("branch", "point"), np.ones((1, 2)))},
               attrs={"model": "rate-state", "branch_labels": ["prz"]}).to_zarr(str(old), zarr_format=3,
                                                                                 consolidated=False)
    for command in (["status"], ["query"], ["verify"], ["report", "--out", str(tmp_path / "r")],
                    ["export", "--out", str(tmp_path / "x.nc")]):
        r = CliRunner().invoke(cli, [*command, "--store", str(old)])
        assert r.exit_code == 2, r.output
        assert "is a branch store of an older `bifurcation continue`" in r.output and "xarray.open_zarr" in r.output
        assert len(r.output.strip().splitlines()) == 1


def test_quasi_static_blow_up_is_unbounded_without_nan_warnings(capfd):
    """Below k_c the quasi-static slider's V blows up in finite time: the run stops one step before its
    Taylor coefficients overflow (status unbounded), and heyoka prints no NaN-step warning."""
    import math

    from bifurcation.models.rate_state import rate_state

    k_c = (0.015 - 0.01) / 0.01
    period = 2 * math.pi / (math.sqrt(0.5) * 100)
    # the aging case of the study's fates that stepped into NaN before (status nonfinite)
    r = rate_state(a=0.01, b=0.015, dc=0.01, state_law="aging", k=0.9 * k_c, v_lp=1.0,
                   t=[0.0, 400 * period], v0=1.0, theta0=[0.01 * math.exp(0.01)])
    assert r.status == "unbounded" and "blows up in finite time" in r.message
    err = capfd.readouterr().err
    assert "nan" not in err.lower(), err


def test_criticality_is_printed_as_its_word():
    from bifurcation.models import get_model
    from bifurcation.store.query import _Records

    model = get_model("rate-state")
    maker = _Records(model)
    coords = {a.name: 1.0 for a in model.axes}
    values = {o.name: 0.0 for o in model.outputs if o.name != "status"}
    for code, word in ((1, "subcritical"), (2, "supercritical"), (3, "degenerate"), (0, None)):
        record = maker.make("slip", coords, 0, {**values, "criticality": code})
        assert record["criticality"] == word


def test_a_named_law_is_found_by_its_formula():
    """carlson-langer is Φ = 1/(1+x): a query by the formula finds it (and a workflow listing both is
    told they are the same law)."""
    from bifurcation.errors import InputError
    from bifurcation.models.single_block import law_identity
    from bifurcation.workflow import parse_workflow

    assert law_identity("carlson-langer") == law_identity("1/(1 + x)") == law_identity("1/(1+x)")
    assert law_identity("exponential") == law_identity("exp(-x)")
    assert law_identity("carlson-langer") != law_identity("1/(1+x/2)^2")
    text = ('[study]\nname = "t"\n[engine]\nlaws = ["carlson-langer", "1/(1+x)"]\n'
            '[grid.nu]\nvalues = [1e-6]\n[grid.nu_f]\nvalues = [0.3]\n')
    with pytest.raises(InputError, match=r"repeats engine.laws\[0\] \('carlson-langer' is the same law Φ\)"):
        parse_workflow(text)


def test_integer_labels_are_shown_as_integers():
    from bifurcation.errors import InputError
    from bifurcation.models import get_model
    from bifurcation.store.labels import match_value

    n = next(a for a in get_model("chain").axes if a.name == "n")
    with pytest.raises(InputError) as info:
        match_value("n", [4.0, 16.0], 5, show=n.shown)
    assert "(nearest: 4, 16; 4 … 16, 2 labels)" in str(info.value) and "5.0" not in str(info.value)
    ends = next(a for a in get_model("chain").axes if a.name == "periodic")
    assert (ends.shown(0), ends.shown(1), ends.parse("periodic"), ends.parse("1")) == ("free", "periodic", 1.0, "1")


def test_report_replaces_an_out_you_named_only_with_force(tmp_path):
    """Issue 21: `report --out DIR` run again rewrote DIR's REPORT.md without a word. Now a run into DIR is
    refused in one line (exit 2, naming --out, the path and --force) with DIR untouched; --force replaces."""
    from bifurcation.run.tiles import compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.workflow import Workflow

    workflow = Workflow(name="force", laws=("carlson-langer",), nu=(1e-6,), nu_f=(0.3, 0.4), tiles=(2, 1))
    store = tmp_path / "s.zarr"
    run_id = create_store(store, workflow)["run_id"]
    for tile in iter_tiles(workflow):
        write_tile(store, tile, compute_tile(tile), run_id)
    out = tmp_path / "rep"   # a report written before (one report run below keeps the test at ~1 s)
    out.mkdir()
    (out / "REPORT.md").write_text("edited by the user\n")
    (out / "report.html").write_text("<p>an earlier report</p>\n")
    args = ["report", "--store", str(store), "--out", str(out)]
    before = sorted((p.name, p.stat().st_mtime_ns) for p in out.iterdir())
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 2 and r.stdout == ""
    [line] = r.stderr.splitlines()
    assert line == (f"bifurcation: error: --out='{out}': holds an earlier output (REPORT.md, report.html); "
                    "pass --force to replace it, or choose another directory")
    assert sorted((p.name, p.stat().st_mtime_ns) for p in out.iterdir()) == before
    r = CliRunner().invoke(cli, [*args, "--force"])
    assert r.exit_code == 0, r.output
    assert (out / "REPORT.md").read_text() != "edited by the user\n"
