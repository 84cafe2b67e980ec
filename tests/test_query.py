"""query: selection by exact or nearest label, records, table / CSV / JSON output."""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.store.query import COLUMNS, FORMATS, format_records, query
from bifurcation.store import create_store, open_store, write_tile
from bifurcation.run.tiles import compute_tile, iter_tiles
from bifurcation.workflow import Workflow

W = Workflow(name="query-test", laws=("piecewise-linear", "carlson-langer"), nu=(1e-6, 1e-9, 1e-12),
             nu_f=(0.2, 0.4, 0.5, 0.6, 0.8), tiles=(2, 2))


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    path = tmp_path_factory.mktemp("query") / "q.zarr"
    run_id = create_store(path, W)["run_id"]
    for tile in iter_tiles(W):
        if tile.index != (1, 4, 2):   # leave one tile (carlson-langer, ν_f 0.8, ν 1e-6) not computed
            write_tile(path, tile, compute_tile(tile), run_id)
    return path


def test_exact_selection_matches_the_engine(store):
    (record,) = query(store, law="carlson-langer", nu=1e-9, nu_f=0.4)
    r = bf.slip("carlson-langer", nu=1e-9, nu_f=0.4)
    assert (record["law"], record["nu"], record["nu_f"]) == ("carlson-langer", 1e-9, 0.4)
    assert record["delta"] == r.delta[()] and record["steps"] == r.steps[()]
    assert record["status"] == "stick-slip" and record["creep_time"] is None   # U̇ never reaches ν_f
    assert list(record) == list(COLUMNS)


def test_a_value_that_is_not_a_label_is_refused_naming_the_nearest(store):
    # issue 9: --nu-f 5 --nu 1e-30 on a grid ending at 0.8 and 1e-12 returned the corner point
    with pytest.raises(InputError, match=r"^nu_f=5.0: is not a label of this store \(nearest: 0.8, 0.6;"):
        query(store, nu_f=5.0)
    with pytest.raises(InputError, match=r"^nu=1e-30: is not a label of this store \(nearest: 1e-12, 1e-09;"):
        query(store, nu=1e-30, nearest=False)
    # within a relative 1e-12 is the same label (two decimal texts of one number), 1e-11 is not
    assert len(query(store, law="carlson-langer", nu=1e-9 * (1 + 5e-13), nu_f=0.4)) == 1
    with pytest.raises(InputError, match=r"^nu="):
        query(store, nu=1e-9 * (1 + 1e-11))


def test_nearest_selection_reports_the_selected_labels(store):
    notes = []
    records = query(store, law="piecewise-linear", nu=3e-10, nu_f=[0.41, 0.79], nearest=True, notes=notes)
    assert [(r["nu"], r["nu_f"]) for r in records] == [(1e-9, 0.4), (1e-9, 0.8)]
    assert notes == ["nu_f: no label 0.41; took the nearest, 0.4", "nu_f: no label 0.79; took the nearest, 0.8",
                     "nu: no label 3e-10; took the nearest, 1e-09"]   # in the store's axis order
    # ν is nearest in log: 1e-7 is one decade from 1e-6 and two from 1e-9 (linearly it is nearer 1e-9)
    assert [r["nu"] for r in query(store, law="piecewise-linear", nu=1e-7, nu_f=0.2, nearest=True)] == [1e-6]


def test_formula_laws_match_by_their_expression(tmp_path):
    w = Workflow(name="formula-query", laws=("1/(1+x/2)^2", "exp(-x)"), nu=(1e-6,), nu_f=(0.3,))
    path = tmp_path / "f.zarr"
    run_id = create_store(path, w)["run_id"]
    for tile in iter_tiles(w):
        write_tile(path, tile, compute_tile(tile), run_id)
    (a,) = query(path, law="1/(1 + x/2)**2")
    (b,) = query(path, law=" 1/(1+x/2.0)^2")
    assert a == b and a["law"] == "1/(1+x/2)^2" and a["status"] == "stick-slip"
    with pytest.raises(InputError, match=r"^law='1/\(1\+x/2\)\^3': is not a law of this store"):
        query(path, law="1/(1+x/2)^3")


def test_all_points_in_order_and_not_computed_points(store):
    records = query(store)
    assert len(records) == W.n_points
    assert [(r["law"], r["nu_f"], r["nu"]) for r in records[:4]] == [
        ("piecewise-linear", 0.2, 1e-12), ("piecewise-linear", 0.2, 1e-9), ("piecewise-linear", 0.2, 1e-6),
        ("piecewise-linear", 0.4, 1e-12)]
    (missing,) = [r for r in records if r["status"] == "not-computed"]
    assert (missing["law"], missing["nu_f"], missing["nu"], missing["delta"]) == ("carlson-langer", 0.8, 1e-6, None)
    assert len(query(store, computed_only=True)) == W.n_points - 1
    assert len(query(open_store(store), law=["carlson-langer"], nu_f=0.8)) == 3   # a Dataset works too


def test_formats(store):
    records = query(store, nu=1e-12)
    parsed = json.loads(format_records(records, "json"))
    assert parsed == records and all(set(r) == set(COLUMNS) for r in parsed)
    rows = list(csv.DictReader(io.StringIO(format_records(records, "csv"))))
    assert len(rows) == len(records)
    for row, record in zip(rows, records):
        assert float(row["delta"]) == record["delta"] and float(row["nu"]) == record["nu"]   # exact repr
        assert (row["creep_time"] == "") == (record["creep_time"] is None)
    table = format_records(records, "table").splitlines()
    assert table[0].split() == list(COLUMNS) and len(table) == len(records) + 1
    with pytest.raises(InputError, match=r"^--format='xml'"):
        format_records(records, "xml")


def test_bad_selections_are_refused(store):
    with pytest.raises(InputError, match=r"^law='dieterich'.*use one of piecewise-linear, carlson-langer"):
        query(store, law="dieterich")
    with pytest.raises(InputError, match=r"^nu=-1.0"):
        query(store, nu=-1.0)
    with pytest.raises(InputError, match=r"^nu_f='x'"):
        query(store, nu_f="x")


def test_cli_query_formats(store):
    result = CliRunner().invoke(cli, ["query", "--store", str(store), "--law", "carlson-langer", "--nu", "1e-9",
                                      "--format", "csv"])
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert [float(r["nu_f"]) for r in rows] == list(W.nu_f)
    result = CliRunner().invoke(cli, ["query", "--store", str(store), "--law", "nope"])
    assert result.exit_code == 2 and result.stderr.startswith("bifurcation: error: --law='nope'")
    result = CliRunner().invoke(cli, ["query", "--store", str(store), "--nu", "1e-9", "--nu-f", "0.5"])
    assert result.exit_code == 0 and len(result.stdout.strip().splitlines()) == 3
    assert np.isfinite(float(result.stdout.splitlines()[1].split()[COLUMNS.index("delta")]))
    result = CliRunner().invoke(cli, ["query", "--store", str(store), "--nu", "1e-12", "--format", "json"])
    assert result.exit_code == 0, result.output
    assert result.stdout == format_records(query(store, nu=1e-12), "json") + "\n"


def test_cli_format_choices_are_the_formats():
    # the CLI takes its choices from the constant (bifurcation.cli._options)
    (option,) = [p for p in cli.get_command(None, "query").params if p.name == "fmt"]
    assert tuple(option.type.choices) == FORMATS


def test_a_streamed_table_fits_the_models_longest_status_name():
    # rate-state's "unbounded-growth" is longer than every single-block status: the streamed table
    # (fixed widths, written as records come) must size its status column from the store's model
    import io

    from bifurcation.models import get_model
    from bifurcation.store.query import RecordStream, _status_width, write_records

    model = get_model("rate-state")
    rows = [{"state_law": "aging", "status": "unbounded-growth", "k": 0.25},
            {"state_law": "aging", "status": "steady-sliding", "k": 0.5}]
    out = io.StringIO()
    write_records(RecordStream(iter(rows), 5, ("state_law", "status", "k"), _status_width(model)), "table", out,
                  law_width=5)
    lines = out.getvalue().splitlines()
    assert _status_width(model) == len("unbounded-growth")
    # the k column starts at one offset in the header and in every row
    assert len({line.index(value) for line, value in zip(lines, ("k", "0.25", "0.5"))}) == 1
