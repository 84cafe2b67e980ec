"""The engine CLI: exit codes first, then the output; bad input is one line with exit status 2."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli


def run(*args):
    return CliRunner().invoke(cli, list(args))


def test_laws_lists_every_builtin():
    result = run("laws", "--json")
    assert result.exit_code == 0
    names = [row["name"] for row in json.loads(result.stdout)]
    assert names == bf.law_names()


def test_slip_json_has_the_engine_fields():
    result = run("slip", "--law", "carlson-langer", "--nu", "1e-12", "--nu-f", "0.4", "--json")
    assert result.exit_code == 0, result.output
    record = json.loads(result.stdout)
    assert set(bf.FIELDS) | {"steps", "status", "law", "nu", "nu_f"} <= set(record)
    assert record["status"] == "stick-slip" and record["creep_time"] is None
    # Same numbers as the Python API, printed with full precision (repr round trip).
    assert record["delta"] == bf.slip("carlson-langer", nu=1e-12, nu_f=0.4).delta.item()


def test_slip_quad_and_table_output():
    result = run("slip", "--law", "piecewise-linear", "--nu", "1e-9", "--nu-f", "0.3", "--precision", "quad")
    assert result.exit_code == 0
    assert "delta" in result.stdout and "stick-slip" in result.stdout


def test_limit_json():
    result = run("limit", "--law", "piecewise-linear", "--nu-f", "0.5", "--json")
    assert result.exit_code == 0
    record = json.loads(result.stdout)
    # Eq. (18) at ν_f = 1/2 (α = 1): the limit (1 + ω/α)^{(1 + α/ω)/2} → sqrt(e) = 1.6487212707001282
    # (float of mpmath.sqrt(mpmath.e)); 1e-15 is 4 ulps: JSON printing must not lose digits.
    assert abs(record["delta0"] - 1.6487212707001282) < 1e-15


@pytest.mark.parametrize(
    "args, text",
    [
        (("slip", "--law", "carlson-langer", "--nu", "0", "--nu-f", "0.4"), "nu=0.0: must be finite and > 0"),
        (("slip", "--law", "carlson-langer", "--nu", "-1e-9", "--nu-f", "0.4"), "nu=-1e-09"),
        (("slip", "--law", "carlson-langer", "--nu", "nan", "--nu-f", "0.4"), "nu=nan"),
        (("slip", "--law", "carlson-langer", "--nu", "inf", "--nu-f", "0.4"), "nu=inf"),
        (("slip", "--law", "carlson-langer", "--nu", "fast", "--nu-f", "0.4"), "--nu: 'fast' is not a number"),
        (("slip", "--law", "carlson-langer", "--nu", "1e-9", "--nu-f", "0"), "--nu-f=0.0"),
        (("slip", "--law", "coulomb", "--nu", "1e-9", "--nu-f", "0.4"), "law='coulomb': is not a known law"),
        (("slip", "--law", "1/(1+x", "--nu", "1e-9", "--nu-f", "0.4"), "law='1/(1+x'"),
        (("slip", "--law", "__import__('os')", "--nu", "1e-9", "--nu-f", "0.4"), "law="),
        (("slip", "--law", "1/(1+x)^2", "--nu", "1e-9", "--nu-f", "0.4"), "Φ'(0) = -2"),
        (("slip", "--law", "2-x", "--nu", "1e-9", "--nu-f", "0.4"), "Φ(0) = 2"),
        (("slip", "--law", "carlson-langer", "--nu", "1e-9", "--nu-f", "0.4", "--precision", "half"), "half"),
        (("limit", "--law", "carlson-langer", "--nu-f", "-0.5"), "--nu-f=-0.5"),
        (("slip", "--nu", "1e-9", "--nu-f", "0.4"), "Missing option '--law'"),
    ],
)
def test_bad_input_is_one_line_exit_2(args, text):
    result = run(*args)
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bifurcation: error:"), result.stderr
    assert text in lines[0]
    assert "Traceback" not in result.output and result.stdout == ""


def test_console_script_exit_status_and_no_traceback():
    # The installed entry point, as a user runs it (not the in-process runner).
    proc = subprocess.run([sys.executable, "-m", "bifurcation", "slip", "--law", "carlson-langer",
                           "--nu", "-1", "--nu-f", "0.4"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


@pytest.mark.parametrize("module", ["scipy", "numbalsoda"])
def test_bench_without_its_baselines_says_how_to_install_them(monkeypatch, module):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == module else real(name, *a))
    result = run("bench", "--points", "10")
    assert result.exit_code == 2
    # the message lists every missing baseline package (numbalsoda may be absent too on this host)
    need = result.stderr.split("need ", 1)[1].split(";", 1)[0]
    assert module in need.split(", ")
    assert 'install them with python -m pip install -e ".[bench]"' in result.stderr
