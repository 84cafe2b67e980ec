"""``bifurcation study chain WORKFLOW``: the chain study (the chain model's ``study`` hook; docs/chain.md).

Runs ``bifurcation.models.chain.study`` on a checked workflow: the lone-block threshold, order
parameter and hysteresis with finite-size scaling, magnitude–frequency statistics and a verdict table,
into ``REPORT.md``, ``report.html``, ``data.json`` and the figures.
"""

from __future__ import annotations

from pathlib import Path

import click

from ..errors import InputError, shown_path
from ._common import examples

__all__ = ["chain_study_cmd"]

_MARKS = ("data.json", "REPORT.md")   # what a chain study leaves in its directory
#: data.json is read whole (twice): a study's is well under a megabyte (the large workflow's a few).
_MAX_DATA_BYTES = 256 << 20


@click.command("chain", epilog=examples(
    "bifurcation study chain workflows/chain-report.toml --from-data --out results/chain"))
@click.argument("workflow")
@click.option("--out", metavar="DIR", default=None,
              help="Where REPORT.md, data.json and the figures go (default: the workflow's [study] out, "
                   "results/local/chain for workflows/chain-report.toml). The committed reference is "
                   "results/chain: `--from-data --out results/chain` rewrites it from its data.")
@click.option("--from-data", "from_data", is_flag=True,
              help="Run nothing: re-render REPORT.md and the figures from DIR/data.json (byte for byte).")
@click.option("--presets-only", "presets_only", is_flag=True,
              help="Run only the workflow's [presets] catalogs (~15 CPU minutes for workflows/chain-report.toml) and "
                   "take every other section from DIR/data.json (refused without it).")
@click.option("--catalogs-only", "catalogs_only", is_flag=True,
              help="Run only the workflow's [catalog] runs again (~1 CPU minute), keep their raw catalogs in "
                   "DIR/catalogs.npz and re-render the report from DIR/data.json (refused without it).")
@click.option("--published-nu-only", "published_nu_only", is_flag=True,
              help="Run only the workflow's [published_nu] catalogs (the presets at their own ν, events split by a "
                   "velocity threshold; its `cpu` per catalog) into DIR/subevents_*.json and re-render the report "
                   "from DIR/data.json (refused without it).")
@click.option("--ell-scan-only", "ell_scan_only", is_flag=True,
              help="Run only the workflow's [ell_scan] sweeps still missing from DIR/ell_scan.json (each kept as it "
                   "finishes: a stopped scan resumes) and re-render the report from DIR/data.json (refused without it).")
@click.option("--force", is_flag=True, help="Run again into a DIR that holds a study (its data.json is replaced); "
                                            "default: refuse.")
def chain_study_cmd(workflow: str, out, from_data: bool, presets_only: bool, force: bool,
                    published_nu_only: bool = False, catalogs_only: bool = False, ell_scan_only: bool = False) -> None:
    """The chain study of WORKFLOW: lone-block threshold, order parameter and hysteresis with finite-size
    scaling, magnitude–frequency statistics, a verdict table (≤ 10 minutes on 2 cores for
    workflows/chain-report.toml)."""
    import json

    from ..models.chain.study_workflow import load_report_workflow
    from ._common import check_writable_dir

    cfg = load_report_workflow(workflow)   # the whole workflow, before anything runs or is written
    out = out if out is not None else cfg["study"].get("out", f"results/local/{cfg['study']['name']}")
    out = check_writable_dir(out)   # (the text, not Path(out): Path("") is ".")
    data = out / "data.json"
    if from_data and presets_only:
        raise InputError("--presets-only", "with --from-data", "runs the preset catalogs, which --from-data never does",
                         "give one of --from-data and --presets-only")
    if sum((from_data, presets_only, published_nu_only, catalogs_only)) > 1:
        raise InputError("--published-nu-only", "with --from-data, --presets-only or --catalogs-only", "is a run of "
                         "its own", "give one of --from-data, --presets-only, --catalogs-only and --published-nu-only")
    if ell_scan_only and (from_data or presets_only or published_nu_only or catalogs_only):
        raise InputError("--ell-scan-only", "with another of --from-data, --presets-only, --catalogs-only, "
                         "--published-nu-only", "is a run of its own", "give --ell-scan-only alone")
    # At most one "--*-only" flag is left here (the checks above): its workflow table, then the data it re-renders.
    for flag, given, table in (("--ell-scan-only", ell_scan_only, "ell_scan"),
                               ("--published-nu-only", published_nu_only, "published_nu")):
        if given and not cfg.get(table):
            raise InputError(flag, str(workflow), f"has no [{table}] table",
                             f"add one (workflows/chain-report.toml has it) or drop {flag}")
    for flag, given in (("--ell-scan-only", ell_scan_only), ("--catalogs-only", catalogs_only),
                        ("--published-nu-only", published_nu_only)):
        if given and not data.is_file():
            raise InputError(flag, str(data), "does not exist: the report is re-rendered from it",
                             "run the whole study once, or give --out results/chain")
    if presets_only and not data.is_file():
        raise InputError("--presets-only", str(data), "does not exist: the other sections are read from it",
                         "run the whole study once (without --presets-only), or give --out results/chain")
    if from_data:
        if not data.is_file():
            raise InputError("--from-data", str(data), "does not exist",
                             "run the study once (without --from-data), or give --out results/chain (the "
                             "committed data)")
        if data.stat().st_size > _MAX_DATA_BYTES:
            raise InputError("--from-data", str(data), f"is larger than {_MAX_DATA_BYTES >> 20} MB: not a study's "
                             "data (results/chain/data.json is 0.35 MB)", "give the --out of a chain study")
        try:
            saved = json.loads(data.read_bytes())
        except (ValueError, OSError) as exc:
            raise InputError("--from-data", str(data), f"cannot be read as a study's data ({exc})",
                             "run the study again without --from-data (with --force) to rewrite it") from None
        _check_saved(saved, cfg, data)
    elif published_nu_only or catalogs_only or ell_scan_only:
        pass      # writes subevents_*.json beside data.json and re-renders: no study replaced
    elif not force and any((out / mark).exists() for mark in _MARKS):
        raise InputError("--out", str(out), "already holds a chain study (REPORT.md or data.json), which a run "
                         "replaces", "give --force to run it again, --from-data to re-render it, or another --out")
    elif (out / "REPORT.md").exists() and not (out / "data.json").is_file():
        # --force replaces a chain study, never another command's report (results/rate-state, results/paper)
        raise InputError("--out", str(out), "holds a REPORT.md that is not a chain study's (no data.json beside it)",
                         "give another --out (--force replaces only a chain study)")
    from ..models.chain.study import main

    made = [p for p in [out.absolute(), *out.absolute().parents] if not p.exists()]
    try:
        main([str(workflow), "--out", str(out), *(["--from-data"] if from_data else []),
              *(["--presets-only"] if presets_only else []), *(["--published-nu-only"] if published_nu_only else []),
              *(["--catalogs-only"] if catalogs_only else []), *(["--ell-scan-only"] if ell_scan_only else [])])
    except BaseException:   # a stopped run ("left nothing new") left the empty --out it had made
        for directory in made:
            try:
                directory.rmdir()
            except OSError:
                break
        raise
    if from_data:   # (a run says where it wrote, and in how long, itself)
        click.echo(f"wrote {shown_path(out / 'REPORT.md')} and its figures from {shown_path(data)}")


#: what the report reads from data.json before anything else (``report.main``, ``--from-data``)
_DATA_KEYS = ("workflow", "wall_seconds", "cpu_seconds", "sweeps", "catalogs", "threshold")


def _check_saved(saved, cfg: dict, data: Path) -> None:
    """``saved`` (data.json) is a chain study's data, run with WORKFLOW's parameters: the report is
    rendered from WORKFLOW's values (ν, N, ν_f, ...) beside the saved numbers, so the data of another
    workflow would be labelled with parameters it was not run at. Only ``[study] out`` may differ (the
    committed data was run into results/chain)."""
    import tomllib

    fix = "give the WORKFLOW that data.json was run with, or run the study again without --from-data"
    if (not isinstance(saved, dict) or any(k not in saved for k in _DATA_KEYS)
            or not isinstance(saved["sweeps"], dict) or "runs" not in saved["sweeps"]):
        raise InputError("--from-data", str(data), "is not a chain study's data (keys "
                         f"{', '.join(_DATA_KEYS)} and sweeps.runs expected)", fix)
    try:
        ran = tomllib.loads(saved["workflow"]) if isinstance(saved["workflow"], str) else None
    except tomllib.TOMLDecodeError:
        ran = None

    def physics(doc):
        return {**doc, "study": {k: v for k, v in doc.get("study", {}).items() if k != "out"}}

    if not isinstance(ran, dict) or physics(ran) != physics(cfg):
        differ = "its workflow" if not isinstance(ran, dict) else ", ".join(sorted(
            k for k in set(ran) | set(cfg) if physics(ran).get(k) != physics(cfg).get(k)))
        raise InputError("--from-data", str(data), f"was run with another workflow than WORKFLOW ({differ} "
                         "differ)", fix)
