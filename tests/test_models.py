"""The model layer (issue 9): declarations, the registry, and a second model end to end.

The damped block (``bifurcation.models.damped_block``: Ü = νt − U + 1 − Φ(U̇/ν_f) − γU̇, γ a third
axis) runs workflow → submit → store → query → report with no code outside its own module; γ = 0 is
the single block bit for bit.
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models import (ACTIONS, DEFAULT_MODEL, Axis, Event, Model, Output, get_model, model_names,
                                register)
from bifurcation.store import create_store, open_store, write_tile
from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles, tile_count
from bifurcation.workflow import parse_workflow

DAMPED = textwrap.dedent("""
    [study]
    name = "damped"
    [model]
    name = "damped-block"
    [engine]
    laws = ["carlson-langer", "piecewise-linear"]
    [grid.gamma]
    values = [0.0, 0.1, 0.5]
    [grid.nu_f]
    values = [0.3, 0.4, 0.45, 0.5, 0.6]
    [grid.nu]
    values = [1e-9, 1e-6]
    [tiles]
    gamma = 2
    nu_f = 3
    nu = 2
    """)


# -- declarations ------------------------------------------------------------------------------------------
def test_registry_lists_the_models_default_first():
    assert model_names()[0] == DEFAULT_MODEL == "single-block"
    assert "damped-block" in model_names()
    with pytest.raises(InputError, match=r"^model='nope': is not a known model; use one of single-block"):
        get_model("nope")


def test_single_block_declaration_names_its_slots_and_dims():
    m = get_model()
    assert m.dims == ("law", "nu_f", "nu")
    slots = m.slots(n_pieces=2)
    # the slots the engine used as par[0], par[1], par[2], par[3 + k] before models had names
    assert (slots.index("nu"), slots.index("nu_f"), slots.index("forcing"), slots.piece(0), slots.piece(1)) == \
        (0, 1, 2, 3, 4)
    assert m.slots(1).size == 3          # a one-piece law has no selectors
    assert [o.name for o in m.outputs] == [*bf.FIELDS, "steps", "status"]
    assert {e.action for e in m.events} <= set(ACTIONS)
    assert m.axis("nu").scale == "log" and m.axis("nu").bounds == (1e-20, 1.0)


def test_declarations_check_themselves():
    with pytest.raises(ValueError, match="not an identifier"):
        Axis("nu-f", "ν_f", "x", bounds=(0.0, 1.0))
    with pytest.raises(ValueError, match="increasing"):
        Axis("a", "a", "x", bounds=(0.0, 1.0), scale="log")
    with pytest.raises(ValueError, match="must name what it records"):
        Event("max", "maximum", "no record")
    single = get_model()
    with pytest.raises(ValueError, match="set by no axis"):
        Model(**{**single.__dict__, "name": "broken", "parameters": ("nu", "nu_f", "forcing", "mu")})
    with pytest.raises(ValueError, match="reserved name 'done'"):
        Model(**{**single.__dict__, "name": "broken", "outputs": (*single.outputs, Output("done", "x"))})
    with pytest.raises(ValueError, match="already registered"):
        register(Model(**{**single.__dict__}))


def test_formula_laws_are_one_law_whatever_their_text():
    with pytest.raises(InputError, match=r"^engine.laws\[1\]=.*repeats engine.laws\[0\]"):
        parse_workflow(DAMPED.replace('["carlson-langer", "piecewise-linear"]', '["1/(1+x/2)**2", "1/(1 + x/2)^2"]'))


# -- the workflow, tiles and store read the model --------------------------------------------------------
def test_workflow_of_the_damped_model_has_its_axes():
    w = parse_workflow(DAMPED)
    assert w.model == "damped-block" and w.shape == (2, 3, 5, 2) and w.gamma == (0.0, 0.1, 0.5)
    assert w.tiles == (2, 3, 2) and tile_count(w) == 2 * 2 * 2 * 1
    assert parse_workflow(w.to_toml()) == w
    # the model is part of what makes a study: the same grid under another model is another study
    assert w.fingerprint != parse_workflow(w.to_toml().replace("damped-block", "single-block")
                                           .replace("[grid.gamma]\nvalues = [0.0, 0.1, 0.5]\n", "")
                                           .replace("gamma = 2\n", "")).fingerprint


@pytest.mark.parametrize("text, key", [
    (DAMPED.replace("values = [0.0, 0.1, 0.5]", "values = [-0.1]"), "grid.gamma.values[0]"),
    (DAMPED.replace("[grid.gamma]\nvalues = [0.0, 0.1, 0.5]\n", ""), "grid.gamma"),
    (DAMPED.replace("gamma = 2", "gama = 2"), "tiles.gama"),
    (DAMPED.replace('name = "damped-block"', 'name = "dampd"'), "model.name"),
    (DAMPED.replace('name = "damped-block"', 'name = "single-block"'), "grid.gamma"),
])
def test_damped_workflow_errors_name_the_key(text, key):
    with pytest.raises(InputError) as info:
        parse_workflow(text)
    assert info.value.argument == key


def test_store_of_the_damped_model_has_its_dims_and_cf_attributes(tmp_path):
    w = parse_workflow(DAMPED)
    create_store(tmp_path / "d.zarr", w)
    ds = open_store(tmp_path / "d.zarr")
    assert ds["delta"].dims == ("law", "gamma", "nu_f", "nu") and ds.attrs["model"] == "damped-block"
    assert ds["gamma"].attrs["long_name"].startswith("viscous damping") and ds["gamma"].attrs["symbol"] == "γ"
    assert ds["nu"].attrs["scale"] == "log" and ds["delta"].attrs["units"] == "1" and "F0/k" in ds["delta"].attrs["long_name"]
    assert int(ds["done"].sum()) == 0


# -- end to end (the engine reads the declaration) -------------------------------------------------------
@pytest.fixture(scope="module")
def damped_store(tmp_path_factory):
    w = parse_workflow(DAMPED)
    path = tmp_path_factory.mktemp("damped") / "d.zarr"
    run_id = create_store(path, w)["run_id"]
    for tile in iter_tiles(w):
        write_tile(path, tile, compute_tile(tile), run_id)
    return w, path


def test_gamma_zero_is_the_single_block_bit_for_bit(damped_store):
    w, path = damped_store
    ds = open_store(path)
    for k, law in enumerate(w.laws):
        r = bf.slip(law, nu=np.asarray(w.nu)[None, :], nu_f=np.asarray(w.nu_f)[:, None])
        for name in (*bf.FIELDS, "steps", "status"):
            stored = np.asarray(ds[name].values[k, 0])
            expected = np.asarray(r[name])
            if stored.dtype.kind == "f":
                stored, expected = stored.view(np.int64), expected.view(np.int64)
            np.testing.assert_array_equal(stored, expected, err_msg=f"{law} {name}")


def test_damping_moves_the_creep_threshold_to_one_over_two_plus_gamma(damped_store):
    # docs/physics.md: 2α = 1/ν_f − γ, so creep above ν_f* = 1/(2 + γ): 0.476 at γ = 0.1, 0.4 at γ = 0.5
    w, path = damped_store
    ds = open_store(path)
    status = np.asarray(ds["status"].values)
    nu_f = np.asarray(w.nu_f)
    creep, stick = int(bf.Status.CREEP), int(bf.Status.STICK_SLIP)
    for g, gamma in enumerate(w.gamma):
        threshold = 1 / (2 + gamma)
        for k in range(len(w.laws)):
            at_small_nu = status[k, g, :, 0]   # ν = 1e-9
            assert np.all(at_small_nu[nu_f > threshold + 1e-9] == creep), (gamma, k)
            assert np.all(at_small_nu[nu_f < threshold - 1e-9] == stick), (gamma, k)
    # and damping takes energy: with γ > 0 the slip is smaller wherever both stick-slip
    delta = np.asarray(ds["delta"].values)
    both = (status[:, 0] == stick) & (status[:, 1] == stick)
    assert np.all(delta[:, 1][both] < delta[:, 0][both])


def test_damped_store_equals_the_serial_engine(damped_store):
    w, path = damped_store
    reference = compute_serial(w)
    ds = open_store(path)
    for name, values in reference.items():
        stored = np.asarray(ds[name].values)
        if stored.dtype.kind == "f":
            stored, values = stored.view(np.int64), values.view(np.int64)
        np.testing.assert_array_equal(stored, values, err_msg=name)


def test_query_and_cli_serve_the_damped_store(damped_store):
    w, path = damped_store
    from bifurcation.store.query import query

    (record,) = query(path, law="carlson-langer", gamma=0.1, nu_f=0.3, nu=1e-9)
    assert (record["gamma"], record["nu_f"], record["nu"], record["status"]) == (0.1, 0.3, 1e-9, "stick-slip")
    result = CliRunner().invoke(cli, ["query", "--store", str(path), "--gamma", "0.5", "--nu", "1e-6",
                                      "--law", "piecewise-linear", "--format", "csv"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.strip().splitlines()
    assert lines[0].startswith("law,gamma,nu_f,nu,status,delta")   # the model's axis order and len(lines) == 1 + len(w.nu_f)
    result = CliRunner().invoke(cli, ["query", "--store", str(path), "--gamma", "0.2"])
    assert result.exit_code == 2
    assert "--gamma=0.2: is not a label of this store (nearest: 0.1, 0.0;" in result.stderr


def test_report_serves_the_damped_store(damped_store, tmp_path):
    _, path = damped_store
    out = tmp_path / "report"
    result = CliRunner().invoke(cli, ["report", "--store", str(path), "--out", str(out)])
    assert result.exit_code == 0, result.output
    md = (out / "REPORT.md").read_text()
    assert "Model damped-block" in md and "| gamma | γ | 0 | 0.5 | 3 |" in md
    assert "not made for model damped-block" in md
    assert len(list(out.glob("*.png"))) == 2
    # the transition along γ: at ν_f = 0.45 (threshold 1/(2 + γ) crosses 0.45 at γ = 0.222...)
    assert "0.1 (stick-slip) → 0.5 (creep)" in md


def test_a_model_registered_at_run_time_is_served(tmp_path):
    # a test model outside the package: the damped block under another name, one fixed γ = 0.2 slot
    from bifurcation.models import damped_block

    base = damped_block.DAMPED_BLOCK
    fixed = Model(**{**base.__dict__, "name": "test-fixed-damping", "axes": base.axes[1:],
                     "fixed": {"forcing": 1.0, "gamma": 0.2}})
    register(fixed, replace=True)
    w = parse_workflow(DAMPED.replace("damped-block", "test-fixed-damping")
                       .replace("[grid.gamma]\nvalues = [0.0, 0.1, 0.5]\n", "").replace("gamma = 2\n", ""))
    out = compute_serial(w)
    assert out["delta"].shape == (2, 5, 2) and np.all(out["done"])
    full = get_model("damped-block")
    from bifurcation.engine.solve import solve

    ref = solve(full, "carlson-langer", {"gamma": np.full(5, 0.2), "nu_f": np.asarray(w.nu_f), "nu": np.full(5, 1e-9)})
    np.testing.assert_array_equal(out["delta"][0, :, 0], ref["delta"])
    assert not math.isnan(float(ref["delta"][0]))


# -- a test model with a structural axis and a load history ("set" events) --------------------------------
def _ramp_model():
    """n chained ramps x_k' = (k + 1)·rate, the load ``rate`` stepped to 5 at t = 1 by a "set" event, ending
    when x_{n−1} reaches 10 (with "step" events at 5 and 7 that must change nothing). Exact end time: 10/(n·rate) if n·rate ≥ 10, else 1 + (10 − n·rate)/(5n)."""
    import heyoka as hy

    from bifurcation.models import StateVar, System
    from bifurcation.models.single_block import LAW

    def equations(law, slots, num, *, n, precision):
        xs = hy.make_vars(*(f"x{k}" for k in range(n))) if n > 1 else [hy.make_vars("x0")]
        rate = slots.par("rate")
        return System(state=tuple(xs), rhs=tuple((k + 1) * rate for k in range(n)),
                      events={"end": (xs[-1] - num(10), "positive"), "step": [(hy.time - num(1), "positive")],
                              "rung": [(xs[-1] - num(5), "positive"), (xs[-1] - num(7), "positive")]},
                      sets={"step": [{"rate": 5.0}]}, info={"n": n})

    def classify(raw, points):
        assert raw["info"]["n"] >= 1   # what the compiled system told classify
        return {"end_time": raw["time"], "steps": raw["steps"], "status": raw["status"]}, raw["messages"]

    return Model(
        name="test-ramp", title="ramps", description="test", source="tests/test_models.py", labels=LAW,
        axes=(Axis("n", "n", "ramps", bounds=(1, 8), dtype="int64", structural=True),
              Axis("rate", "r", "load rate", bounds=(0.1, 100.0))),
        parameters=("rate",), state=(StateVar("x", "ramp"),),
        events=(Event("end", "end", "x reaches 10"), Event("step", "set", "the load steps to 5", per_piece=True),
                Event("rung", "step", "ends a step at x = 5 and 7, nothing else", per_piece=True)),
        outputs=(Output("end_time", "time of the end"), Output("steps", "steps", dtype="int64", fill=0),
                 Output("status", "status", dtype="int8", fill=0)),
        statuses=(bf.Status.STICK_SLIP, bf.Status.NO_STOP), equations=equations, classify=classify,
        initial=lambda n: (0.0,) * n)


@pytest.mark.parametrize("batch", [1, 4])
def test_structural_axis_and_set_events(batch):
    from bifurcation.engine.solve import solve

    model = register(_ramp_model(), replace=True)
    n = np.array([1, 2, 4, 1, 2, 4, 8])
    rate = np.array([0.5, 0.5, 0.5, 20.0, 20.0, 3.0, 0.2])
    out = solve(model, "carlson-langer", {"n": n, "rate": rate}, batch=batch)
    exact = np.where(n * rate >= 10, 10 / (n * rate), 1 + (10 - n * rate) / (5 * n))
    # piecewise-linear motion: the Taylor series are exact, only the event root finding rounds (~1e-16)
    np.testing.assert_allclose(out["end_time"], exact, rtol=1e-14)
    assert np.all(out["status"] == int(bf.Status.STICK_SLIP))


def test_damped_workflow_through_submit_equals_the_serial_engine(tmp_path):
    # the whole service path: a TOML workflow of the damped model, `bifurcation submit` on an embedded
    # Dask cluster, the store, then a query of the store (no model-specific code outside its module)
    from bifurcation.store.query import query

    (tmp_path / "damped.toml").write_text(DAMPED)
    store = tmp_path / "damped.zarr"
    result = CliRunner().invoke(cli, ["submit", str(tmp_path / "damped.toml"), "--store", str(store),
                                      "--workers", "1", "--json"])
    assert result.exit_code == 0, result.output
    w = parse_workflow(DAMPED)
    reference = compute_serial(w)
    ds = open_store(store)
    for name, values in reference.items():
        stored = np.asarray(ds[name].values)
        if stored.dtype.kind == "f":
            stored, values = stored.view(np.int64), values.view(np.int64)
        np.testing.assert_array_equal(stored, values, err_msg=name)
    assert len(query(store, gamma=[0.0, 0.5], law="piecewise-linear")) == 2 * len(w.nu_f) * len(w.nu)


# -- a model with its own engine (a runner instead of equations/classify) ----------------------------------
def _runner_model():
    """Closed-form 'engine': the period 2π/√k of a unit-mass oscillator, and an error status for k > 50
    (what the runner reports, the store must keep)."""
    from bifurcation.models.single_block import LAW

    def runner(model, label, points, *, precision, t_max, max_steps, batch):
        k = np.asarray(points["k"], dtype=float)
        bad = k > 50
        period = np.where(bad, np.nan, 2 * np.pi / np.sqrt(k))
        status = np.where(bad, int(bf.Status.NONFINITE), int(bf.Status.STICK_SLIP)).astype(np.int8)
        return ({"period": period, "status": status},
                {int(i): f"k = {k[i]} > 50" for i in np.flatnonzero(bad)})

    return Model(name="test-runner", title="oscillator", description="test", source="tests/test_models.py",
                 labels=LAW, axes=(Axis("k", "k", "stiffness", bounds=(0.1, 100.0), scale="log"),),
                 parameters=(), state=(), events=(),
                 outputs=(Output("period", "period 2π/√k"), Output("status", "status", dtype="int8", fill=0)),
                 statuses=(bf.Status.STICK_SLIP, bf.Status.NONFINITE), equations=None, classify=None,
                 runner=runner)


def test_a_model_with_its_own_runner_goes_through_tiles_and_store(tmp_path):
    model = register(_runner_model(), replace=True)
    w = parse_workflow(textwrap.dedent("""
        [study]
        name = "runner"
        [model]
        name = "test-runner"
        [engine]
        laws = ["carlson-langer"]
        [grid.k]
        values = [1.0, 4.0, 64.0]
        [tiles]
        k = 2
        """))
    out = compute_serial(w)
    # closed form: 2π/√k; k = 64 is beyond the runner's range: its status, never a number
    np.testing.assert_allclose(out["period"][0, :2], [2 * np.pi, np.pi], rtol=1e-15)
    assert math.isnan(out["period"][0, 2]) and out["status"][0, 2] == int(bf.Status.NONFINITE)
    store = tmp_path / "runner.zarr"
    run_id = create_store(store, w)["run_id"]
    for tile in iter_tiles(w):
        write_tile(store, tile, compute_tile(tile), run_id)
    ds = open_store(store)
    np.testing.assert_array_equal(ds["period"].values, out["period"])
    assert ds.attrs["model"] == model.name


def test_a_model_needs_equations_or_a_runner():
    base = _runner_model()
    with pytest.raises(ValueError, match="equations and classify, or a runner"):
        Model(**{**base.__dict__, "runner": None})
