"""The store of `bifurcation continue` is a store like any other: written through bifurcation.store (checksums,
done mask, consolidated metadata, built beside its path and renamed into place) and read back by status, query,
verify and report --store. The branch values here are made up (distinct numbers to read back exactly): what is
tested is the store, not the continuation (tests/test_rate_state_cycles.py runs that)."""

from types import SimpleNamespace

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models.rate_state.branches import BranchStatus, write_branch_store
from bifurcation.models.rate_state.study import BranchSpec, StudySpec


def _point(i: int, j: int):
    x = 1.0 + i + j / 8   # a different exact binary fraction at every point
    return SimpleNamespace(kappa=x, k=x / 2, v_lp=float("nan") if j == 0 else x * 4, period=x * 3, ln_v_max=x / 4,
                           ln_v_min=-x / 4, slip=x * 5, multipliers=(complex(0, -x), 0.5),
                           status="ok" if (i, j) != (0, 1) else "no-convergence")


def _results():
    """Two branches, of 3 and 2 points (the second ends past its end in the store), one with a fold."""
    out = []
    for i, (label, n) in enumerate((("prz, quasi-static", 3), ("aging, inertial", 2))):
        hopf = SimpleNamespace(k_c=0.5 + i, omega_c=70.25 + i, lyapunov_coefficient=0.03125 - i / 16,
                               criticality=("subcritical", "supercritical")[i])
        branch = SimpleNamespace(points=[_point(i, j) for j in range(n)], hopf=hopf, v_lp=1.0,
                                 spec=SimpleNamespace(mass=None if i == 0 else 1e-5, damping=0.0),
                                 folds=[1] if i == 0 else [], meta={"stop": f"reached {n} points"})
        out.append({"spec": SimpleNamespace(label=label), "branch": branch,
                    "period_check": [1e-13 * (j + 1) for j in range(n)]})
    return out


SPEC = StudySpec("branch-store", "made-up branches", tuple(
    BranchSpec(label=label, state_law="prz", a=0.01, b=0.015, dc=0.01, v_lp=1.0, eta=0.0, points=3, max_step=0.5,
               kappa_min=0.05, kappa_max=20.0) for label in ("prz, quasi-static", "aging, inertial")),
    (2.0,), (1.0,), (0.0,), "[study]\nname = \"branch-store\"\n", False)


@pytest.fixture
def store(tmp_path):
    path = tmp_path / "out" / "branches.zarr"
    write_branch_store(path, SPEC, _results(), command="test")
    return path


def test_status_query_and_verify_read_the_continuation_store(store):
    from bifurcation.store import check_store
    from bifurcation.store.integrity import scan
    from bifurcation.store.query import query
    from bifurcation.store.status import study_status

    attrs = check_store(store)
    assert attrs["model"] == "rate-state-branches" and attrs["stop"] == ["reached 3 points", "reached 2 points"]
    assert not (store.parent / "branches.zarr.partial").exists()   # built beside it, renamed into place
    status = study_status(store)
    assert (status.points, status.done, status.failed) == (6, 6, 1)   # 1: the no-convergence point
    assert status.per_label["aging, inertial"]["statuses"] == {"periodic-orbit": 2, "past-end": 1}
    damage, tiles, chunks = scan(store)
    assert damage == [] and tiles == 2 and chunks == 2 * 18 + 2   # 17 outputs + done per branch, 2 coordinates
    records = query(store, law="prz, quasi-static", point=[0, 1])
    assert [r["status"] for r in records] == ["periodic-orbit", "no-convergence"]
    first = records[0]
    assert (first["kappa"], first["k"], first["v_lp"], first["period"], first["multiplier_max"]) == (1.0, 0.5, 1.0,
                                                                                                    3.0, 1.0)
    assert (first["k_c"], first["omega_c"], first["criticality"], first["fold_kappa"]) == (0.5, 70.25, "subcritical",
                                                                                          1.125)
    past = query(store, law="aging, inertial", point=2)[0]
    assert past["status"] == str(BranchStatus.PAST_END) and past["kappa"] is None and past["k_c"] is None
    runner = CliRunner()
    for argv in (["status"], ["verify"], ["query", "--format", "csv"]):
        r = runner.invoke(cli, [*argv, "--store", str(store)])
        assert r.exit_code == 0, r.output
    assert "0 damaged" in runner.invoke(cli, ["verify", "--store", str(store)]).output
    r = runner.invoke(cli, ["report", "--store", str(store), "--out", str(store.parent / "report")])
    assert r.exit_code == 0, r.output
    text = (store.parent / "report" / "REPORT.md").read_text()
    assert "| prz, quasi-static | kappa | 3 | 1 … 1.25 | subcritical | 0.5 |" in text
    # its labels are branches, not laws: no "law" column, no table of equations it cannot have
    assert "| branch | not-computed | periodic-orbit | no-convergence | past-end |" in text
    assert "| law |" not in text and "declares no description" not in text


def test_verify_finds_a_flipped_byte_and_query_shows_nothing_of_it(store):
    from bifurcation.store.integrity import StoreDamagedError, scan
    from bifurcation.store.query import query

    chunk = store / "period" / "c" / "1" / "0"
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x10
    chunk.write_bytes(bytes(data))
    damage, _, _ = scan(store)
    assert [(d.chunk, d.problem) for d in damage] == [("period/c/1/0", "checksum mismatch")]
    r = CliRunner().invoke(cli, ["verify", "--store", str(store)])
    assert r.exit_code == 1 and "period/c/1/0: checksum mismatch" in r.output
    # no point of it can be recomputed alone: the advice is to write it again, not verify --repair
    assert f"repair with: bifurcation continue WORKFLOW --out {store.parent}" in r.output
    with pytest.raises(StoreDamagedError, match=r"period/c/1/0.*; run `bifurcation continue WORKFLOW --out"):
        query(store, law="aging, inertial")
    assert query(store, law="prz, quasi-static")[0]["period"] == 3.0   # the other branch's chunks are sound
    # its points cannot be recomputed one by one: --repair says what to do instead, and touches nothing
    r = CliRunner().invoke(cli, ["verify", "--store", str(store), "--repair"])
    assert r.exit_code == 2 and "bifurcation continue WORKFLOW" in r.output and chunk.read_bytes() == bytes(data)


def test_status_of_a_lost_done_chunk_points_to_continue_not_submit(store):
    """A store written whole has points not done only by damage (its done chunk lost): status says how to
    write it again, not "submit the same workflow again" (a continue workflow is refused by submit)."""
    import shutil

    shutil.rmtree(store / "done" / "c" / "1")
    r = CliRunner().invoke(cli, ["status", "--store", str(store)])
    assert r.exit_code == 0, r.output
    last = next(line for line in r.output.splitlines() if line.startswith("3 points not done"))
    assert last.startswith("3 points not done in a store written whole") and "submit" not in last
    assert f"`bifurcation continue WORKFLOW --out {store.parent}`" in last


def test_one_writer_at_a_time_and_no_lock_left(store):
    """Two runs writing one --out at once removed each other's .partial (zarr ValueError tracebacks): the
    second is refused in one line naming --out, the first's store stays whole, and no lock is left."""
    from bifurcation.store.integrity import scan
    from bifurcation.store.lock import StoreLock

    with StoreLock(store.parent).acquire(command="another continue"):
        with pytest.raises(InputError, match=r"--out=.*is being written by"):
            write_branch_store(store, SPEC, _results()[:1])
    assert scan(store)[0] == [] and not (store.parent / "branches.zarr.partial").exists()
    write_branch_store(store, SPEC, _results()[:1])
    assert sorted(p.name for p in store.parent.iterdir()) == ["branches.zarr"]   # no LOCK_NAME left


def test_a_new_store_replaces_a_store_and_nothing_else(store, tmp_path):
    write_branch_store(store, SPEC, _results()[:1])   # rewritten whole: one branch now
    from bifurcation.store.query import query

    assert {r["branch"] for r in query(store)} == {"prz, quasi-static"}
    other = tmp_path / "mine"
    other.mkdir()
    (other / "notes.txt").write_text("a user's file\n")
    with pytest.raises(InputError, match="exists and is not a bifurcation store"):
        write_branch_store(other, SPEC, _results())
    assert [p.name for p in other.iterdir()] == ["notes.txt"]


def test_a_study_workflow_cannot_name_the_continuation_store():
    from bifurcation.workflow import parse_workflow

    with pytest.raises(InputError, match=r"model.name='rate-state-branches': is the store of `bifurcation continue`"):
        parse_workflow('[study]\nname = "x"\n[model]\nname = "rate-state-branches"\n[engine]\nlaws = ["a"]\n')
