"""The fault and bad-input rows of issue 8, each re-run: one line on stderr, the right exit status, no
traceback, nothing written or lost. (Integrity faults: test_integrity.py; two writers: test_lock.py.)

Disk full and a read-only directory are injected (OSError from the writer) so the suite needs no root;
bifurcation/bench/store_faults.py and the closing note give the runs on a real full tmpfs and a read-only mount.
"""

from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli

from _store_helpers import local_cluster

BIN = Path(sys.executable).parent
TOML = """
[study]
name = "faults"

[engine]
laws = ["carlson-langer"]

[grid.nu]
values = [1e-6, 1e-9]

[grid.nu_f]
values = [0.3, 0.6]

[tiles]
nu_f = 1
nu = 2
"""


@pytest.fixture(scope="module")
def scheduler():
    with local_cluster(1) as address:
        yield address


def one_line(result, needle: str, code: int = 2) -> str:
    """The one error line (a submit may first have said what it is about to do, on stderr too)."""
    assert result.exit_code == code, (result.exit_code, result.output)
    assert "Traceback" not in result.output
    (line,) = [line for line in result.stderr.splitlines() if line.startswith("bifurcation: error: ")]
    assert result.stderr.strip().splitlines()[-1] == line and needle in line, line
    return line


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ok.toml").write_text(TOML)
    return tmp_path


def run(*args):
    return CliRunner().invoke(cli, list(args))


def test_store_under_a_file(here):
    (here / "file").write_text("x")
    one_line(run("submit", "ok.toml", "--store", "file/sub.zarr"), "--store='file/sub.zarr': cannot be created")
    assert (here / "file").read_text() == "x"


def test_store_in_a_read_only_directory(here, monkeypatch):
    real_mkdir = Path.mkdir

    def refuse(self, *args, **kwargs):   # what a read-only mount answers (root ignores chmod)
        if "ro" in self.parts:
            raise OSError(errno.EROFS, "Read-only file system", str(self))
        return real_mkdir(self, *args, **kwargs)

    monkeypatch.setattr(Path, "mkdir", refuse)
    one_line(run("submit", "ok.toml", "--store", "ro/s.zarr"), "cannot be created (Read-only file system)")
    assert not (here / "ro").exists()


def test_disk_full_while_creating_the_store(here, scheduler, monkeypatch):
    import xarray

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xarray.Dataset, "to_zarr", full)
    line = one_line(run("submit", "ok.toml", "--store", "s.zarr", "--scheduler", scheduler), "No space left", 1)
    assert "run the same command again" in line
    assert not (here / "s.zarr").exists()   # no half-made store, no lock left


def test_disk_full_while_writing_tiles(here, scheduler, monkeypatch):
    import bifurcation.store

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    with monkeypatch.context() as patch:
        patch.setattr(bifurcation.store, "write_tile", full)
        result = run("submit", "ok.toml", "--store", "s.zarr", "--scheduler", scheduler, "--write-from", "client")
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert "error: tile 0-0-0 (carlson-langer): OSError: [Errno 28] No space left on device" in result.stdout
    assert result.stderr.strip().splitlines()[-1] == "bifurcation: 4 points failed; submit again to retry them"
    result = run("submit", "ok.toml", "--store", "s.zarr", "--scheduler", scheduler, "--json")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["computed"] == 4   # the retry completes


def test_report_out_is_a_file(here):
    (here / "REPORT").write_text("keep")
    one_line(run("report", "--store", "none.zarr", "--out", "REPORT"), "--out='REPORT': is a file")
    assert (here / "REPORT").read_text() == "keep"


@pytest.mark.parametrize("text, needle", [
    (TOML.replace('"faults"', '"' + 'n' * 300 + '"'), "has 300 characters"),
    ("[study]\nname = \"d\"\n[engine]\nlaws = " + "[" * 100_000 + "]" * 100_000 + "\n", "is nested too deeply"),
    (TOML.replace('["carlson-langer"]', '["1 - tan(x)"]'), "near x = 1.5707963268"),
    (TOML.replace("[engine]", "[engine]\nmax_steps = 1000000000000000000"), "engine.max_steps="),
    (TOML.replace("[engine]", "[engine]\nt_max = 1e300"), "engine.t_max="),
    # 200 ranges of 1e5 points (a 10 KB file): refused from the counts, nothing materialised
    (TOML.replace("values = [0.3, 0.6]", "ranges = [" + ", ".join(
        f"{{ start = {0.001 + 0.004 * k:.3f}, stop = {0.003 + 0.004 * k:.3f}, num = 100000 }}" for k in range(200))
        + "]"), "grid.nu_f='20000000 points': declares more than 100000 points on one axis"),
    (TOML.replace("values = [1e-6, 1e-9]", "log = { start = 1e-3, stop = 1e-15, num = 100000 }").replace(
        "values = [0.3, 0.6]", "ranges = [{ start = 0.1, stop = 0.9, num = 100000 }]").replace(
        '["carlson-langer"]', '["carlson-langer", "piecewise-linear"]'), "declares more than 100000000 points"),
], ids=["long-name", "deep-toml", "tan-pole", "max-steps", "t-max", "200-ranges", "grid-1e10"])
def test_workflows_refused_before_any_work(here, text, needle):
    (here / "bad.toml").write_text(text)
    one_line(run("submit", "bad.toml", "--store", "s.zarr"), needle)
    assert not (here / "s.zarr").exists() and not (here / "results").exists()


@pytest.mark.parametrize("args, needle, real", [
    (["slip", "--law", "carlson-langer", "--nu", "5e-324", "--nu-f", "0.4", "--json"], "nu=5e-324: is outside [1e-20, 1]",
     True),
    (["slip", "--law", "carlson-langer", "--nu", "2", "--nu-f", "0.4"], "nu=2.0: is outside [1e-20, 1]", False),
    (["slip", "--law", "carlson-langer", "--nu", "1e-9", "--nu-f", "20"], "--nu-f=20.0: is outside [0.0001, 10]", False),
    (["limit", "--law", "carlson-langer", "--nu-f", "1e-5"], "--nu-f=1e-05: is outside [0.0001, 10]", True),
])
def test_engine_commands_share_the_workflow_bounds(args, needle, real):
    # one case of each command in a real process: nothing on stdout (heyoka's warnings included), one line
    # on stderr; the others in process (an interpreter start each, ~1 s)
    if real:
        out = subprocess.run([str(BIN / "bifurcation"), *args], capture_output=True, text=True, timeout=120)
        code, stdout, stderr = out.returncode, out.stdout, out.stderr
    else:
        out = run(*args)
        code, stdout, stderr = out.exit_code, out.stdout, out.stderr
    assert code == 2 and stdout == ""
    (line,) = stderr.strip().splitlines()
    assert needle in line


def test_native_prints_go_to_stderr_and_json_stays_clean():
    # what heyoka/LLVM write on file descriptor 1 must not land inside --json output
    code = ("import os, sys\nfrom bifurcation.cli._common import native_stdout_to_stderr, echo_json\n"
            "with native_stdout_to_stderr():\n    os.write(1, b'native warning\\n')\n    echo_json({'a': 1})\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                         env={**os.environ})
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == {"a": 1} and "native warning" in out.stderr


def test_workers_wait_with_a_message_and_a_timeout(here, scheduler):
    result = run("submit", "ok.toml", "--store", "s.zarr", "--scheduler", scheduler, "--workers", "5",
                 "--workers-timeout", "1")
    assert result.exit_code == 2 and "Traceback" not in result.output
    *_, waiting, error = result.stderr.strip().splitlines()
    assert waiting == f"bifurcation: waiting for 5 workers at {scheduler} (1 connected), up to 1 s"
    assert error.startswith("bifurcation: error: --workers=5: only 1 workers connected") and "--workers 1" in error
    assert not (here / "s.zarr").exists()


def test_the_python_api_refuses_the_same_bounds():
    import bifurcation as bf
    from bifurcation.errors import InputError

    for kwargs, needle in ((dict(nu=1e-21, nu_f=0.4), "nu=1e-21: is outside [1e-20, 1]"),
                           (dict(nu=1e-9, nu_f=0.4, max_steps=10**18), "max_steps=1000000000000000000"),
                           (dict(nu=1e-9, nu_f=0.4, t_max=1e300), "t_max=1e+300")):
        with pytest.raises(InputError, match=needle.replace("[", r"\[").replace("+", r"\+")):
            bf.slip("carlson-langer", **kwargs)
    with pytest.raises(InputError, match=r"nu_f=20.0: is outside"):
        bf.limit("carlson-langer", nu_f=20.0)
