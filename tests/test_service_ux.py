"""What a user sees around a submit: progress in a terminal and in a log, the dashboard, result views.

The progress checks drive ``Progress`` directly with in-memory streams (a terminal is faked by
``isatty``); the dashboard check starts a real embedded cluster and fetches the page it links to.
"""

from __future__ import annotations

import io
import urllib.request

import numpy as np
import pytest
import xarray as xr

import bifurcation as bf
from bifurcation.run.progress import Progress, format_eta


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_log_lines_carry_points_rate_and_eta():
    stream = io.StringIO()
    p = Progress(None, 1000, stream=stream, interval=0.0)
    p.begin()
    p.note("connecting to embedded local cluster")
    p.update(250)
    p.update(750)
    p.close()
    lines = stream.getvalue().splitlines()
    assert lines[0] == "bifurcation: connecting to embedded local cluster"
    assert lines[1].startswith("bifurcation: 250/1000 points (25.0%), ")
    assert "points/s" in lines[1] and "ETA " in lines[1]
    # the last line is the final count (update at 100% and close both write it: a log always ends with it)
    assert lines[-1].startswith("bifurcation: 1000/1000 points (100.0%)")
    assert "\r" not in stream.getvalue()   # plain lines, nothing a log file cannot show


def test_log_lines_are_periodic_not_per_tile():
    stream = io.StringIO()
    p = Progress(None, 100, stream=stream, interval=3600.0)
    for _ in range(100):
        p.update(1)
    assert stream.getvalue() == ""       # within the interval: silent
    p.close()
    assert stream.getvalue().count("\n") == 1   # then one final line


def test_terminal_gets_a_bar_and_quiet_modes_print_nothing():
    tty = _Terminal()
    p = Progress(None, 10, stream=tty)
    p.update(10)
    p.close()
    assert "10/10" in tty.getvalue() and "\r" in tty.getvalue()
    for quiet in (False, lambda done, total: None):
        stream = _Terminal()
        q = Progress(quiet, 10, stream=stream)
        q.note("x")
        q.update(10)
        q.close()
        assert stream.getvalue() == ""


@pytest.mark.parametrize("seconds, text", [(5, "5 s"), (119.4, "119 s"), (600, "10 min"),
                                           (7200, "2.0 h"), (float("nan"), "unknown")])
def test_eta_format(seconds, text):
    assert format_eta(seconds) == text


def test_slip_result_views_round_trip_through_netcdf(tmp_path):
    r = bf.slip("carlson-langer", nu=[1e-3, 1e-9], nu_f=[[0.4], [0.6]])
    ds = r.to_xarray()
    assert ds.sizes == {"point": 4}
    np.testing.assert_array_equal(ds.delta.values, r.delta.ravel())
    np.testing.assert_array_equal(ds.nu_f.values, r.nu_f.ravel())
    assert ds.status.attrs["flag_meanings"].split()[int(bf.Status.STICK_SLIP)] == "stick-slip"
    ds.to_netcdf(tmp_path / "r.nc")
    with xr.open_dataset(tmp_path / "r.nc") as back:
        xr.testing.assert_identical(back.load(), ds)
    frame = r.to_dataframe()
    assert list(frame["status"]) == list(r.status_names().ravel())
    assert repr(r) == ("SlipResult(law='carlson-langer', precision='double', shape=(2, 2), "
                       "statuses={'creep': 2, 'stick-slip': 2})")
    assert "<table" in r._repr_html_()


def test_limit_result_views():
    r = bf.limit("piecewise-linear", nu_f=[0.3, 0.7])
    ds = r.to_xarray()
    assert list(ds.coords) == ["nu_f"] and ds.delta0.attrs["units"] == "1" and "F0/k" in ds.delta0.attrs["long_name"]
    assert list(r.to_dataframe()["status"]) == ["stick-slip", "creep"]


def test_package_advertises_types_and_submit():
    from importlib.resources import files

    assert files("bifurcation").joinpath("py.typed").is_file()
    assert bf.submit is __import__("bifurcation.run", fromlist=["submit"]).submit


@pytest.mark.slow   # 9 s: starts a cluster with bokeh and fetches the page
@pytest.mark.distributed
def test_dashboard_link_serves_the_page(tmp_path, monkeypatch):
    """`--dashboard`: the embedded cluster serves Dask's bokeh dashboard at the printed link."""
    import bifurcation.run.progress as progress_module

    workflow = tmp_path / "w.toml"
    workflow.write_text('[study]\nname = "dash"\n[engine]\nlaws = ["carlson-langer"]\n'
                        '[grid.nu]\nvalues = [1e-6]\n[grid.nu_f]\nvalues = [0.3]\n')
    pages = []
    note = progress_module.Progress.note

    def fetch_the_link(self, text):   # fetch while the cluster is up (it is closed after the submit)
        note(self, text)
        if text.startswith("dashboard: "):
            with urllib.request.urlopen(text.split(" ", 1)[1], timeout=30) as page:
                pages.append((page.status, page.read().decode("utf-8", "replace")))

    monkeypatch.setattr(progress_module.Progress, "note", fetch_the_link)
    summary = bf.submit(workflow, store=tmp_path / "d.zarr", workers=1, dashboard=True, progress=True)
    assert summary.complete
    [(status, body)] = pages
    assert status == 200
    assert "needs bokeh" not in body.lower()   # what the page says when bokeh is missing
    assert "bokeh" in body.lower()             # the dashboard's own page loads bokeh's scripts


def test_an_option_given_twice_is_refused_in_one_line():
    from click.testing import CliRunner

    from bifurcation.cli import cli

    for args in (["slip", "--law", "carlson-langer", "--nu", "1e-9", "--nu", "1e-12", "--nu-f", "0.4"],
                 ["slip", "--law=carlson-langer", "--nu=1e-9", "--nu-f", "0.4", "--nu-f=0.3"]):
        result = CliRunner().invoke(cli, args)
        assert result.exit_code == 2, result.output
        [line] = result.output.splitlines()
        assert "is given twice" in line and "give it once" in line
    # repeatable options stay repeatable
    assert "--nu" in {p.opts[0] for p in cli.commands["query"].params if getattr(p, "multiple", False)}


def test_ctrl_c_exits_130_and_says_what_was_kept(monkeypatch):
    """Ctrl-C: exit 130 and one line for the command at hand. `slip` writes nothing, so it says so (a
    submit's "submit the same workflow again to resume" is tests/test_interrupt_messages.py's)."""
    from click.testing import CliRunner

    import bifurcation.engine
    from bifurcation.cli import cli

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(bifurcation.engine, "slip", interrupted)
    result = CliRunner().invoke(cli, ["slip", "--law", "carlson-langer", "--nu", "1e-9", "--nu-f", "0.4"])
    assert result.exit_code == 130
    assert "interrupted. Nothing of this run was written." in result.output
    assert "submit the same workflow again" not in result.output


def test_text_output_prints_shortest_exact_numbers_and_no_none():
    from click.testing import CliRunner

    from bifurcation.cli import cli

    result = CliRunner().invoke(cli, ["slip", "--law", "carlson-langer", "--nu", "1e-12", "--nu-f", "0.6"])
    assert result.exit_code == 0, result.output
    rows = dict(line.split(None, 1) for line in result.output.splitlines())
    assert rows["nu"] == "1e-12" and rows["nu_f"] == "0.6"
    assert rows["creep_time"] == "—"            # undefined in creep: a dash, not None or nan
    assert float(rows["delta"]) == bf.slip("carlson-langer", nu=1e-12, nu_f=0.6).delta   # exact
    assert "None" not in result.output


def test_detach_needs_an_existing_scheduler(tmp_path):
    from click.testing import CliRunner

    from bifurcation.cli import cli

    workflow = tmp_path / "w.toml"
    workflow.write_text('[study]\nname = "d"\n[engine]\nlaws = ["carlson-langer"]\n'
                        '[grid.nu]\nvalues = [1e-6]\n[grid.nu_f]\nvalues = [0.3]\n')
    result = CliRunner().invoke(cli, ["submit", str(workflow), "--store", str(tmp_path / "s.zarr"), "--detach"])
    assert result.exit_code == 2
    [line] = result.output.splitlines()
    assert "--detach" in line and "--scheduler ADDRESS" in line
    assert not (tmp_path / "s.zarr").exists()   # nothing written
