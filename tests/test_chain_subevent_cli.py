"""Bad input to `python -m bifurcation.models.chain.subevent_study`: one line, exit 2, nothing written."""

import subprocess
import sys

import pytest

BAD = [("run", "nosuch", "--out", "{tmp}"), ("run", "mori-kawamura-2006", "--events", "0", "--out", "{tmp}"),
       ("run", "mori-kawamura-2006", "--v-threshold", "0", "--out", "{tmp}"),
       ("run", "mori-kawamura-2006", "--v-threshold", "nan", "--out", "{tmp}"),
       ("run", "mori-kawamura-2006", "--cpu", "-5", "--out", "{tmp}"),
       ("run", "mori-kawamura-2006", "--out", "{tmp}/missing"), ("report", "{tmp}/missing")]


def test_bad_input_through_python_m_is_one_line_and_exit_2(tmp_path):
    # one case through a real `python -m` (the exit status crosses the process boundary); the rest in process
    r = subprocess.run([sys.executable, "-m", "bifurcation.models.chain.subevent_study",
                        *[a.format(tmp=tmp_path) for a in BAD[0]]], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr, r.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args", BAD)
def test_bad_input_is_one_line_and_exit_2(tmp_path, args, capsys):
    from bifurcation.models.chain.subevent_study import main

    code = main([a.format(tmp=tmp_path) for a in args])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert list(tmp_path.iterdir()) == []


def test_a_zero_threshold_is_refused_before_any_work():
    from bifurcation.errors import InputError
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._subevents import SubeventRun

    for bad in (0.0, -1e-3, float("nan"), float("inf"), True):
        with pytest.raises(InputError, match="v_threshold"):
            SubeventRun(resolve_law("carlson-langer"), 4, 1.0, 1e-3, 0.3, "free", [0.0] * 4, v_threshold=bad)
