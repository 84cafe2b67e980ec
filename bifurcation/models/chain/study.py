"""The chain study, the entry of ``bifurcation study chain`` (it writes the chain report): lone-block
threshold, order parameter and hysteresis with finite-size scaling, magnitude–frequency statistics, a
verdict table.

    bifurcation study chain workflows/chain-report.toml [--out DIR] [--from-data | --presets-only | --published-nu-only
                                                                    | --ell-scan-only]

Runs the workflow's ν_f sweeps (several seeds per N), catalogs and lone-block checks on two
processes and writes ``REPORT.md`` and ``report.html`` (one document of ``report.document``'s typed blocks, by
its one renderer), ``data.json`` and the figures into the workflow's ``out``
directory (``results/local/chain``, ignored by git) or ``--out DIR``. ``--from-data`` re-renders them
from ``DIR/data.json`` without running anything: ``--from-data --out results/chain`` rewrites the
committed report byte for byte (deterministic figures, no software tag). ``--presets-only`` runs the
``[presets]`` catalogs (``_study_presets``) and takes every other section from ``DIR/data.json``; a
``[[presets.run]]`` already there with the same entry and the same shared ``[presets]`` settings is kept.
``--ell-scan-only`` runs the ``[ell_scan]`` sweeps still missing from ``DIR/ell_scan.json`` (``_study_ell``; each
kept as it finishes, so a stopped scan resumes) and re-renders from ``DIR/data.json``. A "## Speed" section already in ``REPORT.md`` (written from ``bifurcation bench``) is carried over, read
back into blocks. Sections and verdicts: ``_study_text`` (prose), ``_study_mfd_text``, ``_study_presets``;
figures: ``_study_figures``, ``_study_mfd``; the workflow's check: ``study_workflow``.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from .analysis import (b_value, finite_size_fit, hysteresis, magnitude_frequency, recurrence, spanning_excess,
                       sweep_nu_f)

__all__ = ["main", "saved_data", "study_blocks"]


def _exit_with_parent(parent: int) -> None:
    """In a pool worker: end when ``parent`` (the study) is gone. A kill -9 of `study chain` left its forked
    workers alive and idle for good (~200 MB each), waiting on a queue that no one would fill."""
    import signal
    import threading

    # forked with the CLI's handlers, SIGTERM raised Terminated inside the run, which the pool sent back as a
    # result and went on: the pool's terminate() did not end it. Ctrl-C reaches the whole process group; the
    # study (the parent) decides, and ends the workers
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)

    def watch():
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)

    threading.Thread(target=watch, daemon=True, name="exit-with-parent").start()


@contextlib.contextmanager
def _pool(workers: int):
    """The study's worker processes, each ending with this process (``_exit_with_parent``). A Ctrl-C, SIGTERM
    or error in the study ends them at once: ``with ProcessPoolExecutor`` waited for every queued run first
    (SIGINT of `study chain` after 86 s printed "interrupted", then hung for good: the process joined workers
    that waited on a queue its exiting manager thread no longer fed)."""
    pool = ProcessPoolExecutor(workers, initializer=_exit_with_parent, initargs=(os.getpid(),))
    try:
        yield pool
    except BaseException:
        for process in list((getattr(pool, "_processes", None) or {}).values()):   # no public way before 3.14
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _sweep(args):
    c, sw, n, seed, grid, cycles = args
    t0, c0 = time.perf_counter(), time.process_time()
    out = sweep_nu_f(c["law"], n=n, ell=c["ell"], nu=c["nu"], nu_f_values=grid + grid[::-1], cycles_per_step=cycles,
                     max_events_per_step=sw["max_events_per_step"], transient_cycles=sw["transient_cycles"],
                     ends=c["ends"], amplitude=c["amplitude"], seed=seed)
    out.update(n=n, seed=seed, seconds=time.perf_counter() - t0, cpu=time.process_time() - c0)
    return out


def _catalog(args):
    from ...bounds import CHAIN_EVENT_WORK
    from ...run.progress import event_lines
    from .simulate import chain

    c, cat, n, nu_f, events = args
    t0, c0 = time.perf_counter(), time.process_time()
    r = chain(c["law"], n=n, ell=c["ell"], nu=c["nu"], nu_f=nu_f, ends=c["ends"], amplitude=c["amplitude"],
              seed=cat["seed"], events=events, max_work=CHAIN_EVENT_WORK["exact", "double"],
              progress=event_lines(f"study chain: catalog N = {n}, ν_f = {nu_f:g}"))
    s = cat["skip"]
    one = _one_block(c["law"], n, c["ell"], c["nu"], nu_f, c["ends"], r.potency[s:], r.n_blocks[s:], r.hypocentre[s:])
    return {"n": n, "nu_f": nu_f, "seconds": time.perf_counter() - t0, "cpu": time.process_time() - c0,
            "status": str(r.status), "one_block": one,
            "potency": r.potency[s:].tolist(), "n_blocks": r.n_blocks[s:].tolist(),
            "hypocentre": r.hypocentre[s:].tolist(), "t_start": r.t_start[s:].tolist()}


def _threshold(args):
    from .threshold import lone_block_crossing, lone_block_nu_f_star, lone_block_slip, lone_block_stiffness

    c, th, ell, end = args
    t0, c0 = time.perf_counter(), time.process_time()
    rows = [lone_block_crossing(c["law"], ell=ell, nu=nu, end=end, level=th["level"]) for nu in th["nus"]]
    k = lone_block_stiffness(ell, end)
    ratio = np.linspace(0.7, 1.3, th["scan_points"])
    star = lone_block_nu_f_star(ell, end)
    scan = [k * lone_block_slip(c["law"], ell=ell, nu=th["scan_nu"], nu_f=r * star, end=end) for r in ratio]
    return {"ell": ell, "end": end, "rows": rows, "scan_ratio": ratio.tolist(), "scan_delta": scan, "scan_nu": th["scan_nu"],
            "seconds": time.perf_counter() - t0, "cpu": time.process_time() - c0}


def _jobs(cfg):
    c, sw, cat, th = cfg["chain"], cfg["sweep"], cfg["catalog"], cfg["threshold"]
    jobs = []
    for n, seeds, top, cycles in zip(sw["sizes"], sw["seeds"], sw["nu_f_max"], sw["cycles_per_step"]):
        grid = [float(x) for x in sw["nu_f"] if x <= top + 1e-12]
        jobs += [(_sweep, (c, sw, n, s, grid, cycles), n * cycles) for s in range(1, seeds + 1)]
    for n, events in zip(cat["sizes"], cat["events"]):
        jobs += [(_catalog, (c, cat, n, nf, events), events * n / 500) for nf in cat["nu_f"]]
    jobs += [(_threshold, (c, th, ell, end), 0) for ell in th["ells"] for end in (False, True)]
    from ._study_mfd import near_half_jobs, small_nu_jobs

    jobs += near_half_jobs(cfg) + small_nu_jobs(cfg)
    from ._study_presets import preset_jobs

    jobs += preset_jobs(cfg)
    from ._study_ell import ell_scan_jobs

    jobs += ell_scan_jobs(cfg)
    return sorted(jobs, key=lambda j: -j[2])      # the longest first: two workers stay busy to the end


#: Seconds between two lines saying how many runs are done while the study waits for one (its runs say
#: their own events every 10 s where they count them: catalogs, presets)
HEARTBEAT_SECONDS = 30.0


def _waiting(fut, futures, t0: float):
    """``fut.result()``, with a line on stderr every HEARTBEAT_SECONDS while it runs: runs done of planned."""
    while True:
        try:
            return fut.result(timeout=HEARTBEAT_SECONDS)
        except TimeoutError:
            done = sum(f.done() for _, f in futures)
            print(f"bifurcation: study chain: {done} of {len(futures)} runs done, "
                  f"{time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)


def main(argv=None) -> None:
    argv = list(sys.argv[1:] if argv is None else argv)
    out_arg = None
    if "--out" in argv:   # another directory than the workflow's `out` (e.g. the committed results/chain)
        i = argv.index("--out")
        if i + 1 >= len(argv):
            sys.exit("bifurcation: error: --out needs a directory, e.g. --out results/chain")
        out_arg = argv[i + 1]
        del argv[i:i + 2]
    path = Path(argv[0])
    from ...errors import InputError
    from .study_workflow import load_report_workflow

    try:   # every key checked before anything runs or is written
        cfg = load_report_workflow(path)
    except InputError as exc:
        print(f"bifurcation: error: {exc}", file=sys.stderr)
        sys.exit(2)
    out = Path(out_arg or cfg["study"]["out"])
    if "--from-data" in argv[1:] and not (out / "data.json").is_file():
        sys.exit(f"bifurcation: error: --from-data: {out / 'data.json'} does not exist; run the report once "
                 "(without --from-data), or give --out results/chain (the committed data)")
    if "--catalogs-only" in argv[1:] and not (out / "data.json").is_file():
        sys.exit(f"bifurcation: error: --catalogs-only: {out / 'data.json'} does not exist")
    if "--published-nu-only" in argv[1:] and not (out / "data.json").is_file():
        sys.exit(f"bifurcation: error: --published-nu-only: {out / 'data.json'} does not exist; run the whole report "
                 "once, or give --out results/chain (the committed data)")
    if "--ell-scan-only" in argv[1:] and not (out / "data.json").is_file():
        sys.exit(f"bifurcation: error: --ell-scan-only: {out / 'data.json'} does not exist; run the whole report once, "
                 "or give --out results/chain (the committed data)")
    if "--presets-only" in argv[1:] and not (out / "data.json").is_file():
        sys.exit(f"bifurcation: error: --presets-only: {out / 'data.json'} does not exist; run the whole report once "
                 "(without --presets-only), or give --out results/chain (the committed data)")
    out.mkdir(parents=True, exist_ok=True)
    if "--presets-only" in argv[1:]:  # run the [presets] catalogs only; every other section from data.json
        from ._study_presets import preset_jobs

        data = json.loads((out / "data.json").read_text())
        t0 = time.perf_counter()
        shared = {k: v for k, v in cfg["presets"].items() if k != "run"}
        done = {json.dumps(x.get("run_cfg"), sort_keys=True): x for x in data.get("presets", [])
                if data.get("presets_cfg") == shared and x.get("run_cfg")}
        jobs = sorted(preset_jobs(cfg), key=lambda j: -j[2])
        runs = [done[json.dumps(a[1], sort_keys=True)] for f, a, _ in jobs if json.dumps(a[1], sort_keys=True) in done]
        jobs = [j for j in jobs if json.dumps(j[1][1], sort_keys=True) not in done]   # a run already in data.json is kept
        with _pool(cfg["study"].get("workers", 2)) as pool:
            futures = [pool.submit(f, a) for f, a, _ in jobs]
            for fut in futures:
                runs.append(fut.result())
                print(f"{time.perf_counter() - t0:6.0f} s  preset {runs[-1]['preset']}: {runs[-1]['cpu']:.0f} cpu s",
                      file=sys.stderr, flush=True)
        data["presets"] = sorted(runs, key=lambda x: (x["preset"], -x["parameters"]["nu_f"]))
        data["presets_cfg"] = {k: v for k, v in cfg["presets"].items() if k != "run"}
        data["presets_wall_seconds"] = time.perf_counter() - t0
        data["workflow"] = path.read_text()
        _write_data(out, data)
        data["sweeps"].update(_sweep_stats(data["sweeps"]["runs"], cfg))
        _extra_stats(out, cfg, data, None)
        _render(out, cfg, path, data)
        return
    if "--ell-scan-only" in argv[1:]:   # the [ell_scan] runs still missing from ell_scan.json; the rest from data.json
        _ell_scan_only(out, cfg, path)
        return
    if "--catalogs-only" in argv[1:]:   # the [catalog] runs again, their raw catalogs kept; the rest from data.json
        data = json.loads((out / "data.json").read_text())
        c, cat = cfg["chain"], cfg["catalog"]
        args = [(c, cat, n, nf, events) for n, events in zip(cat["sizes"], cat["events"]) for nf in cat["nu_f"]]
        with _pool(cfg["study"].get("workers", 2)) as pool:
            cats = list(pool.map(_catalog, args))
        _save_catalogs(out, cats)
        _write_data(out, data)
        _render(out, cfg, path, saved_data(out, cfg))
        return
    if "--published-nu-only" in argv[1:]:   # the [published_nu] catalogs into subevents_*.json, then re-render
        import tomllib

        from .subevent_study import published_nu_jobs, write_json

        data = json.loads((out / "data.json").read_text())
        ran = tomllib.loads(data.get("workflow", ""))
        now = tomllib.loads(path.read_text())
        if {k: v for k, v in ran.items() if k != "published_nu"} != {k: v for k, v in now.items() if k != "published_nu"}:
            sys.exit(f"bifurcation: error: --published-nu-only: {out / 'data.json'} was run with another workflow than "
                     f"{path} (tables other than [published_nu] differ); run those sections again first")
        t0 = time.perf_counter()
        with _pool(cfg["study"].get("workers", 2)) as pool:
            futures = [pool.submit(f, a) for f, a, _ in published_nu_jobs(cfg)]
            for fut in futures:
                r = fut.result()
                print(f"{time.perf_counter() - t0:6.0f} s  {write_json(r, out)}: {r['events']} events, "
                      f"{r['cpu_run'] + r['cpu_stats']:.0f} cpu s", file=sys.stderr, flush=True)
        from .subevent_study import write_report

        data["workflow"] = path.read_text()      # only its [published_nu] table may have changed (checked above)
        _write_data(out, data)
        write_report(out)
        _render(out, cfg, path, saved_data(out, cfg))
        return
    if "--from-data" in argv[1:]:     # re-render REPORT.md and figures from data.json, no runs
        _render(out, cfg, path, saved_data(out, cfg))
        return
    t0 = time.perf_counter()
    with _pool(cfg["study"].get("workers", 2)) as pool:
        futures = [(f.__name__, pool.submit(f, a)) for f, a, _ in _jobs(cfg)]
        results = {"_sweep": [], "_catalog": [], "_threshold": [], "_budgeted_catalog": [], "_sweep_small_nu": [],
                   "_preset_catalog": [], "_ell_sweep": []}
        for name, fut in futures:
            results[name].append(_waiting(fut, futures, t0))
            r = results[name][-1]
            print(f"{time.perf_counter() - t0:6.0f} s  {name[1:]} N = {r.get('n', '-')} seed/ν_f/ℓ = "
                  f"{r.get('seed', r.get('nu_f', r.get('ell')))}: {r['cpu']:.0f} cpu s", file=sys.stderr, flush=True)
    wall = time.perf_counter() - t0
    cpu = sum(r["cpu"] for rs in results.values() for r in rs)
    data = {"workflow": path.read_text(), "wall_seconds": wall, "cpu_seconds": cpu,
            "sweeps": _sweep_stats(results["_sweep"], cfg), "catalogs": [_catalog_stats(c) for c in results["_catalog"]],
            "threshold": sorted(results["_threshold"], key=lambda d: (d["ell"], d["end"]))}
    data["sweeps"]["runs"] = results["_sweep"]
    if results["_preset_catalog"]:
        data["presets"] = sorted(results["_preset_catalog"], key=lambda x: (x["preset"], -x["parameters"]["nu_f"]))
        data["presets_cfg"] = {k: v for k, v in cfg["presets"].items() if k != "run"}
    for st, c in zip(data["catalogs"], results["_catalog"]):
        st["cpu"] = c["cpu"]
    if results["_ell_sweep"]:     # the ℓ scan's runs into ell_scan.json (a new run replaces the kept ones)
        from ._study_ell import record_run

        for i, r in enumerate(results["_ell_sweep"]):
            record_run(out, cfg, r, fresh=i == 0)
    data["catalogs"].sort(key=lambda d: (d["n"], d["nu_f"]))
    _extra_stats(out, cfg, data, results)
    import os

    data["load_average"] = os.getloadavg()[1]     # 5-minute load at the end: the machine is shared
    _write_data(out, data)
    _render(out, cfg, path, data)
    print(f"wrote {out}/REPORT.md in {wall:.0f} s")


def _ell_scan_only(out: Path, cfg, path: Path) -> None:
    """The ``[ell_scan]`` runs not yet in ``out/ell_scan.json``, each kept there as it finishes (a stopped run
    resumes), then the report re-rendered from ``out/data.json`` with this workflow's text."""
    from ._study_ell import missing_jobs, record_run

    data = json.loads((out / "data.json").read_text())
    jobs = sorted(missing_jobs(out, cfg), key=lambda j: -j[2])
    t0 = time.perf_counter()
    with _pool(cfg["study"].get("workers", 2)) as pool:
        futures = [(f.__name__, pool.submit(f, a)) for f, a, _ in jobs]
        for _, fut in futures:
            r = _waiting(fut, futures, t0)
            record_run(out, cfg, r)
            print(f"{time.perf_counter() - t0:6.0f} s  ell scan ℓ = {r['ell']:g}, N = {r['n']}, seed {r['seed']}: "
                  f"{r['cpu']:.0f} cpu s", file=sys.stderr, flush=True)
    data["workflow"] = path.read_text()
    _write_data(out, data)
    _render(out, cfg, path, saved_data(out, cfg))


def _write_data(out: Path, data: dict) -> None:
    """``out/data.json``, written beside it and renamed into place: a study stopped in the write (Ctrl-C,
    SIGTERM, kill) leaves the earlier data.json whole, not a truncated one that ``--from-data`` and the
    ``--*-only`` runs cannot read (tests/test_interrupt_write.py)."""
    text = json.dumps(data, indent=1, default=float)
    tmp = out / f".data.json.part-{os.getpid()}"
    try:
        tmp.write_text(text)
        os.replace(tmp, out / "data.json")
    finally:
        tmp.unlink(missing_ok=True)


def _render(out: Path, cfg, path: Path, data) -> None:
    from ...report.document import to_html, to_markdown
    from ._study_figures import figures

    figures(out, data)
    from ._study_transition import transition_figure, transition_stats

    data["transition"] = transition_stats(data)      # not stored: recomputed from the sweeps at each rendering
    transition_figure(out, data["transition"])
    if data.get("near_half"):
        from ._study_mfd import near_half_figure

        near_half_figure(out, data["near_half"])
    if data.get("presets"):
        from ._study_presets import presets_figure

        presets_figure(out, data["presets"])
    data["published_nu"] = published_nu(out)
    from ._study_ell import ell_scan_figure, ell_scan_stats

    data["ell_scan"] = ell_scan_stats(out, cfg)     # from ell_scan.json, recomputed at each rendering
    if data["ell_scan"] and data["ell_scan"]["rows"]:
        ell_scan_figure(out, data["ell_scan"])
    blocks = study_blocks(out, cfg, path, data)
    (out / "REPORT.md").write_text(to_markdown(blocks), encoding="utf-8")
    (out / "report.html").write_text(to_html(blocks, out), encoding="utf-8")


def saved_data(out: Path, cfg) -> dict:
    """The study's data as ``--from-data`` reads it: ``out/data.json`` with the statistics recomputed (the
    near-1/2 ones from ``out/near_half.npz``)."""
    data = json.loads((out / "data.json").read_text())
    data["sweeps"].update(_sweep_stats(data["sweeps"]["runs"], cfg))
    _extra_stats(out, cfg, data, None)
    data["published_nu"] = published_nu(out)
    from ._study_ell import ell_scan_stats

    data["ell_scan"] = ell_scan_stats(out, cfg)
    return data


def published_nu(out: Path) -> list:
    """The presets at their own ν, split by a velocity threshold: the ``subevents_*.json`` of ``out``
    (written by subevent_study.py, not by the study; read at every rendering)."""
    return [json.loads(q.read_text()) for q in sorted(out.glob("subevents_*.json"))]


def study_blocks(out: Path, cfg, path, data) -> list:
    """The report as typed blocks (``report.document``); a "## Speed" section of ``out/REPORT.md`` is carried
    over, read back into blocks."""
    from ._study_text import report_blocks

    old = out / "REPORT.md"
    speed = _carried_blocks(_section(old.read_text(), "## Speed")) if old.exists() else []
    return report_blocks(cfg, path, data, data["wall_seconds"], speed)


_RAW = ("t_start", "potency", "n_blocks", "hypocentre", "duration", "c_size", "c_potency", "c_event")


def _extra_stats(out: Path, cfg, data, results) -> None:
    """The ``[near_half]`` catalogs and the ``[sweep_small_nu]`` sweeps into ``data``. Their raw
    catalogs are kept in ``near_half.npz`` (``--from-data`` recomputes the statistics from it)."""
    from ._study_csn import CsnCache
    from ._study_mfd import near_half_stats

    csn = CsnCache(out)
    if results is not None and results.get("_catalog"):
        _save_catalogs(out, results["_catalog"])
    if (out / "catalogs.npz").exists():   # the [catalog] section's statistics from its raw catalogs, with CSN fits
        data["catalogs"] = _catalogs_from_raw(out, data.get("catalogs", []), csn)
    raw = out / "near_half.npz"
    if results is not None:
        if results["_budgeted_catalog"]:
            cats = results["_budgeted_catalog"]
            np.savez_compressed(raw, meta=json.dumps([{k: v for k, v in c.items() if not isinstance(v, list)} for c in cats]),
                                **{f"{k}_{i}": np.array(c[k]) for i, c in enumerate(cats)
                                   for k in _RAW})
        data["sweeps_small_nu"] = {"runs": results["_sweep_small_nu"]}
    if cfg.get("near_half") and raw.exists():
        z = np.load(raw)
        cats = [dict(m, **{k: z[f"{k}_{i}"].tolist() for k in _RAW if f"{k}_{i}" in z})
                for i, m in enumerate(json.loads(str(z["meta"])))]
        data["near_half"] = near_half_stats(cats, cfg, csn)
    csn.save()
    s = cfg.get("sweep_small_nu")
    if s and data.get("sweeps_small_nu", {}).get("runs"):
        small = dict(cfg, sweep=dict(cfg["sweep"], **s))
        data["sweeps_small_nu"].update(_sweep_stats(data["sweeps_small_nu"]["runs"], small))


_CAT_RAW = ("potency", "n_blocks", "hypocentre", "t_start")


def _save_catalogs(out: Path, cats) -> None:
    """The ``[catalog]`` runs' raw catalogs (after the skipped events) in ``catalogs.npz``, so that their
    statistics (and CSN fits) can be recomputed by ``--from-data``."""
    meta = [{k: v for k, v in c.items() if k not in _CAT_RAW} for c in cats]
    np.savez_compressed(out / "catalogs.npz", meta=json.dumps(meta, default=float),
                        **{f"{k}_{i}": np.array(c[k]) for i, c in enumerate(cats) for k in _CAT_RAW})


def _catalogs_from_raw(out: Path, old: list, csn) -> list:
    z = np.load(out / "catalogs.npz")
    cats = [dict(m, **{k: z[f"{k}_{i}"] for k in _CAT_RAW}) for i, m in enumerate(json.loads(str(z["meta"])))]
    rows = []
    for c in cats:
        st = _catalog_stats(c, csn)
        st["cpu"] = c["cpu"]
        rows.append(st)
    return sorted(rows, key=lambda d: (d["n"], d["nu_f"]))


def _section(text: str, head: str) -> str:
    """The section of ``text`` that starts with the heading ``head``, up to the next '## ' heading."""
    i = text.find("\n" + head)
    if i < 0:
        return ""
    j = text.find("\n## ", i + 1)
    return text[i + 1: None if j < 0 else j].rstrip() + "\n"


def _carried_blocks(text: str) -> list:
    """A section carried over from an earlier REPORT.md (the "## Speed" one, written from ``bifurcation
    bench``) read back into typed blocks: its chunks between blank lines are a heading, a table (cells split
    at unescaped ``|``), a bullet list, a figure or a paragraph; a chunk that is none of these stays a paragraph."""
    import re

    from ...report.document import Figure, Heading, Items, Paragraph, Table

    def cells(line):
        return [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]

    blocks = []
    for chunk in (c.strip("\n") for c in text.split("\n\n") if c.strip()):
        lines = chunk.split("\n")
        if m := re.fullmatch(r"(#{1,3}) (.+)", chunk):
            blocks.append(Heading(m.group(2), len(m.group(1))))
        elif (chunk.startswith("| ") and len(lines) > 1 and re.fullmatch(r"\|(---\|)+", lines[1])
              and all(len(cells(r)) == lines[1].count("---") for r in lines[:1] + lines[2:])):
            blocks.append(Table(cells(lines[0]), [cells(r) for r in lines[2:]]))
        elif all(line.startswith("- ") for line in lines):
            blocks.append(Items([line[2:] for line in lines]))
        elif m := re.fullmatch(r"!\[([^\]]*)\]\(([^)\s]+)\)", chunk):
            blocks.append(Figure(m.group(2), alt=m.group(1)))
        else:
            blocks.append(Paragraph(chunk))
    return blocks


def _sweep_stats(runs, cfg) -> dict:
    """Per N: seed-mean and standard error of D and Ψ on both branches, jump, loop, and the FSS fits.

    D is left out (NaN) at the steps where an event of some seed lasted longer than
    ``sweep.longest_event`` loading cycles (default 0.5): there blocks reload and slip again within
    one catalogued event (the chain slides for cycles), and D measures that event, not a block's slip
    (analysis.sweep_nu_f)."""
    per_n = {}
    for r in runs:
        per_n.setdefault(r["n"], []).append(r)
    sizes = sorted(per_n)
    table = []
    limit = cfg["sweep"].get("longest_event", 0.5)
    for n in sizes:
        rs = per_n[n]
        k = len(rs[0]["nu_f"]) // 2
        merged = np.max([r.get("longest_event", [0.0] * 2 * k) for r in rs], axis=0) > limit
        row = {"n": n, "seeds": len(rs), "nu_f": rs[0]["nu_f"][:k],
               "events": int(sum(sum(r["events"]) for r in rs)), "seconds": float(sum(r.get("cpu", math.nan) for r in rs)),
               "cycles_min": float(min(min(r["cycles"]) for r in rs)),
               "closure": [float(np.min([r["closure"] for r in rs])), float(np.max([r["closure"] for r in rs]))],
               "slip_fraction_max": float(np.max([r.get("slip_fraction", [math.nan]) for r in rs])),
               "longest_event": float(np.max([r.get("longest_event", [math.nan]) for r in rs]))}
        for key in ("slip_per_block", "psi"):
            a = np.array([r[key] for r in rs], dtype=float)
            if key == "slip_per_block":
                a[:, merged] = np.nan
            up, down = a[:, :k], a[:, k:][:, ::-1]
            se = (lambda x: x.std(axis=0, ddof=1) / math.sqrt(len(rs))) if len(rs) > 1 else (lambda x: 0 * x[0])
            m_up, m_down, s_up, s_down = up.mean(0), down.mean(0), se(up), se(down)
            row[key] = {"up": m_up.tolist(), "down": m_down.tolist(), "se_up": s_up.tolist(),
                        "se_down": s_down.tolist(), **hysteresis(row["nu_f"], m_up, m_down, s_up, s_down)}
        row["merged_steps"] = int(merged.sum())
        le = np.array([r.get("longest_event", [math.nan] * 2 * k) for r in rs], dtype=float).max(axis=0)
        row["longest_event_up"], row["longest_event_down"] = le[:k].tolist(), le[k:][::-1].tolist()
        table.append(row)
    fss = {}
    for key in ("slip_per_block", "psi"):
        chains = [r for r in table if r["n"] > 1]
        for q in ("jump", "width"):
            fss[f"{key}.{q}"] = finite_size_fit([r["n"] for r in chains], [r[key][q] for r in chains],
                                                [r[key][q + "_sigma"] for r in chains])
    return {"table": table, "fss": fss, "longest_event_limit": limit}


def _catalog_stats(c, csn=None) -> dict:
    """b-value above the magnitude of completeness of the multi-block events (the lone-block events
    sit in an atom fixed by the closed form) and below the system-spanning events, spanning excess,
    recurrence of large events, log-binned counts and potency."""
    n = c["n"]
    p, nb = np.array(c["potency"]), np.array(c["n_blocks"])
    m = np.log10(p)
    span, large = nb == n, nb >= max(2, n // 2)
    multi = nb >= 2
    mfd_multi = magnitude_frequency(p[multi]) if multi.sum() > 10 else None
    if mfd_multi is not None:     # maximum curvature: the most populated bin of the multi-block events
        i = int(np.argmax(mfd_multi["counts"]))
        m_min = float(mfd_multi["edges"][i])
    else:
        m_min = float(np.percentile(m, 10))
    m_max = float(m[span].min()) - 0.05 if span.any() else float(m.max())
    fit = b_value(p[multi], m_min=m_min, m_max=m_max)
    fit.update(_ks(m[multi], fit))
    return {"n": n, "nu_f": c["nu_f"], "events": int(p.size), "seconds": c["seconds"], "status": c["status"],
            "fit": fit, "csn": csn.fit(p[multi]) if csn is not None else None, "spanning": spanning_excess(p, nb, n, fit),
            "recurrence_spanning": recurrence(c["t_start"], span), "recurrence_large": recurrence(c["t_start"], large),
            "large_fraction": float(large.mean()), "one_block": c["one_block"],
            "mfd": {k: v.tolist() for k, v in magnitude_frequency(p).items()}}


def _ks(m, fit) -> dict:
    """KS distance between the fitted truncated exponential and the magnitudes in the fit range, with
    the 5 % critical value 1.36/√n (estimated b: the test is then conservative)."""
    if not math.isfinite(fit["b"]):
        return {"ks": math.nan, "ks_crit": math.nan}
    lo, hi, beta = fit["m_min"], fit["m_max"], fit["b"] * math.log(10)
    x = np.sort(m[(m >= lo) & (m <= hi)]) - lo
    cdf = -np.expm1(-beta * x) / -math.expm1(-beta * (hi - lo))
    i = np.arange(1, x.size + 1)
    return {"ks": float(max(np.max(i / x.size - cdf), np.max(cdf - (i - 1) / x.size))),
            "ks_crit": 1.36 / math.sqrt(x.size)}


def _one_block(law, n, ell, nu, nu_f, ends, potency, n_blocks, hypocentre) -> dict:
    """Lone-block events of the catalog against the closed form P = Δ(ν/√k, √k ν_f)/k (docs/chain.md):
    each starts stuck at σ = 1 among stuck neighbours, so its potency is fixed by the single block."""
    import bifurcation as bf

    from .threshold import lone_block_stiffness

    one = n_blocks == 1
    end = (ends == "free") & ((hypocentre == 0) | (hypocentre == n - 1))
    out = {"count": int(one.sum())}
    for name, sel, at_end in (("interior", one & ~end, False), ("end", one & end, True)):
        k = lone_block_stiffness(ell, at_end)
        ref = float(bf.slip(law, nu=nu / math.sqrt(k), nu_f=nu_f * math.sqrt(k)).delta) / k
        dev = np.abs(potency[sel] / ref - 1) if sel.any() else np.array([math.nan])
        out[name] = {"count": int(sel.sum()), "closed_form": ref, "max_rel_dev": float(np.max(dev))}
    return out


if __name__ == "__main__":
    main()
