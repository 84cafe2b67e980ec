"""A rate-state study: a TOML workflow → Hopf table, branches of cycles, a Zarr store, a report.

``bifurcation continue workflows/rate-state.toml`` runs it. The workflow (see the shipped file for
every key) is validated into frozen specs before anything is computed or written; a bad key or value
is one ``InputError`` line naming it.

Output directory ``<out>``: ``--out``, default ``results/local/<study name>`` (ignored by git).
Store ``<out>/branches.zarr``: a store of the model ``rate-state-branches`` (``branches``: its arrays,
statuses and attributes), written through ``bifurcation.store`` once at the end, beside its path and renamed
into place, so an interrupted run leaves no half store; ``status``, ``query``, ``verify`` and ``report
--store`` read it like any store.
"""

from __future__ import annotations

import math
import re
import shutil
import time
from dataclasses import dataclass

from ...errors import InputError
from ...workflow.validate import WorkflowKind

__all__ = ["BranchSpec", "MAX_POINTS", "StudySpec", "WORKFLOW", "load_study", "run_study"]

_SLIDER_KEYS = ("a", "b", "dc", "v_lp")
_BRANCH_KEYS = ("label", "state_law", "eta", "damping", "points", "max_step", "kappa_min", "kappa_max", "parameter",
                "start_point", "v_lp_min", "v_lp_max", *_SLIDER_KEYS)
_PARAMETERS = ("kappa", "v_lp")
_HOPF_KEYS = ("b_over_a", "v_lp", "eta", "bautin")


@dataclass(frozen=True)
class BranchSpec:
    label: str
    state_law: str
    a: float
    b: float
    dc: float
    v_lp: float
    eta: float
    points: int
    max_step: float
    kappa_min: float
    kappa_max: float
    #: "kappa": the branch in k/k_c from the Hopf point; "v_lp": the cycle ``start_point`` of that branch
    #: (computed with the same keys) continued in V_lp at its k, within [v_lp_min, v_lp_max]
    parameter: str = "kappa"
    start_point: int = 0
    v_lp_min: float = 1e-6
    v_lp_max: float = 1e6
    #: radiation damping η ≥ 0 (friction per unit slip rate; not the normalised mass ``eta``)
    damping: float = 0.0

    @property
    def mass(self):
        return None if self.eta == 0 else self.eta * self.a * self.dc / self.v_lp ** 2


@dataclass(frozen=True)
class StudySpec:
    name: str
    description: str
    branches: tuple
    hopf_b_over_a: tuple
    hopf_v_lp: tuple
    hopf_eta: tuple
    text: str
    bautin: bool = True


#: The workflows of ``bifurcation continue`` (the ``workflow`` hook of the rate-state model).
WORKFLOW = WorkflowKind("continue", ("slider", "branch", "hopf"),
                        "a rate-state continuation workflow of `bifurcation continue` ([slider], [[branch]], [hopf])",
                        "run it with `bifurcation continue FILE`")

#: Bounds of a study's size: each branch point is a periodic orbit solved and checked by simulation
#: (seconds), so 10^3 points on a branch are already an hour; the closed-form check takes every
#: combination of the [hopf] lists.
MAX_POINTS = 1000
MAX_BRANCHES = 100
MAX_HOPF_VALUES = 100
#: ... and of a study in all (issue 21 walk: 100 branches of 1000 points, or three [hopf] lists of 100 values,
#: were each accepted, days of work): branch points summed (the shipped study has 204: 91 s of CPU), and the
#: closed-form check's combinations (3 laws × each; 32 ms a Hopf point at 30 digits, so 1000 are ~100 s)
MAX_TOTAL_POINTS = 2000
MAX_HOPF_CASES = 1000
MAX_ETA = 1e3
_ETA_FIX = "give eta >= 0, e.g. 0.1, or 0 for the quasi-static slider (η = M V_lp²/(a Dc))"
_DAMPING_FIX = ("give damping >= 0, e.g. 0.002, or 0 for no radiation damping (friction per unit slip rate; "
                "docs/rate-state.md, \"Radiation damping\")")
_POINTS_FIX = ("give 3 to 1000 points (a branch point is a periodic orbit: seconds each), or a larger max_step "
               "to cover the branch with fewer points")
_NAME = re.compile(r"^[A-Za-z0-9_-]+$")


#: The longest branch label: it names the branch in the store (query --law), the table and the legend.
_LABEL_MAX = 100


def load_study(path) -> StudySpec:
    """Read and validate a rate-state workflow (one ``InputError`` line on the first problem), with the
    workflows' one validator (``bifurcation.workflow.validate``)."""
    from ...workflow.validate import Table, read_toml
    from .laws import resolve_state_law

    text, doc = read_toml(path, WORKFLOW, argument="WORKFLOW", example="workflows/rate-state.toml")
    root = Table(doc, "", ("study", "slider", "branch", "hopf"), source=path)
    study = root.table("study", ("name", "description"), required=False)
    name = study.raw("name", None) if study is not None else None
    if not isinstance(name, str) or not _NAME.fullmatch(name):   # (match's $ let "name\n" through)
        raise InputError("study.name", name, "is missing or not a plain name", "give e.g. name = \"rate-state\"")
    description = study.string("description", "")
    slider = root.table("slider", _SLIDER_KEYS, required=False) or Table({}, "slider", _SLIDER_KEYS)
    out, labels = [], {}
    for i, br in enumerate(root.tables("branch", _BRANCH_KEYS, most=MAX_BRANCHES)):
        def at(key, br=br):   # a slider key set in the branch is read (and named) there, else in [slider]
            return br if br.has(key) else slider

        for key in sorted(_SLIDER_KEYS):
            if not at(key).has(key):
                raise InputError(br.path(key), None, "is missing", f"set {key} in [slider] or the branch")
        law = resolve_state_law(br.string("state_law", ""), argument=br.path("state_law")).name
        # a ≤ 1 and V_lp ≤ 1e6 (the rs-chain grid's bounds): beyond them the Hopf root did not converge, after
        # the study had started (a = 1e300 was reported as a bad b)
        a = at("a").number("a", above=0, high=1.0)
        label = br.string("label", f"{law} {i}")
        if not label.strip():   # the store finds a branch by its label (query --law): an empty one cannot be
            raise InputError(br.path("label"), label, "is empty", "give the branch a label, e.g. \"prz, quasi-static\"")
        if not label.isprintable() or len(label) > _LABEL_MAX:   # a line break split the printed table; 5000
            # characters pushed the figure's legend off the page (both were run, then written)
            shown = label if len(label) <= 40 else f"{label[:40]}..."
            raise InputError(br.path("label"), shown, "has a line break or a control character" if not
                             label.isprintable() else f"has {len(label)} characters",
                             f"give a label of at most {_LABEL_MAX} printable characters on one line, e.g. \"prz, quasi-static\"")
        if label.strip() in labels:   # a branch is found in the store by its label
            raise InputError(br.path("label"), label, f"repeats branch[{labels[label.strip()]}].label",
                             "give each branch its own label")
        labels[label.strip()] = i
        out.append(BranchSpec(
            label=label, state_law=law, a=a, b=at("b").number("b", above=a, fix="give b > a (velocity weakening)"),
            dc=at("dc").number("dc", above=0), v_lp=at("v_lp").number("v_lp", above=0, high=1e6),
            eta=br.number("eta", 0.0, low=0, high=MAX_ETA, fix=_ETA_FIX),
            damping=br.number("damping", 0.0, low=0, high=MAX_ETA, fix=_DAMPING_FIX),
            points=br.integer("points", 30, low=3, high=MAX_POINTS, fix=_POINTS_FIX),
            max_step=br.number("max_step", 0.5, above=0),
            kappa_min=br.number("kappa_min", 0.05, above=0),
            kappa_max=br.number("kappa_max", 20.0, above=1),
            **_v_lp_keys(br, at("v_lp").number("v_lp"))))
        if out[-1].kappa_min >= 1:   # accepted before, and a branch computed (issue 21 walk: kappa_min = 50)
            raise InputError(br.path("kappa_min"), out[-1].kappa_min, "is not below the Hopf point κ = 1, where "
                             "every branch starts", "give kappa_min in (0, 1), e.g. 0.4")
        check_damping(out[-1], out[-1].damping, br.path("damping"))
    total = sum(b.points for b in out)
    if total > MAX_TOTAL_POINTS:
        raise InputError("branch", f"{len(out)} branches", f"hold {total} points in all, more than {MAX_TOTAL_POINTS} "
                         "(a branch point is a periodic orbit: seconds each)",
                         f"give at most {MAX_TOTAL_POINTS} points summed over the branches, or run several workflows")
    hopf = root.table("hopf", _HOPF_KEYS, required=False) or Table({}, "hopf", _HOPF_KEYS)
    fix = "give a list of at most 100 numbers (the closed-form check takes every combination)"
    spec = StudySpec(name, description, tuple(out),
                     hopf.numbers("b_over_a", [1.1, 2.0, 10.0], above=1, high=1e3, most=MAX_HOPF_VALUES, fix=fix),
                     hopf.numbers("v_lp", [1e-3, 1.0, 1e3], above=0, high=1e6, most=MAX_HOPF_VALUES, fix=fix),
                     hopf.numbers("eta", [0.0, 1.0], low=0, high=MAX_ETA, most=MAX_HOPF_VALUES, fix=_ETA_FIX),
                     text, hopf.boolean("bautin", True))
    cases = len(spec.hopf_b_over_a) * len(spec.hopf_v_lp) * len(spec.hopf_eta)
    if cases > MAX_HOPF_CASES:
        raise InputError("hopf", f"{len(spec.hopf_b_over_a)} b_over_a × {len(spec.hopf_v_lp)} v_lp × "
                         f"{len(spec.hopf_eta)} eta", f"makes {cases} combinations for the closed-form check, more "
                         f"than {MAX_HOPF_CASES} (3 state laws each, ~30 ms a Hopf point)",
                         f"give lists whose lengths multiply to at most {MAX_HOPF_CASES}")
    return spec


def check_damping(branch: BranchSpec, damping: float, argument: str) -> None:
    """Refuse a radiation damping that leaves ``branch`` no Hopf point (ηV_lp ≥ b − a: steady sliding is
    stable for every k; hopf.hopf_point's test), before any work: found there, it came after the closed-form
    sweep had printed, and named ``--damping`` for a workflow's key."""
    if damping * branch.v_lp >= branch.b - branch.a:
        raise InputError(argument, damping, f"gives ηV_lp = {damping * branch.v_lp:g} >= b - a = "
                         f"{branch.b - branch.a:g} for branch '{branch.label}': steady sliding is stable for "
                         "every k and there is no Hopf point to continue from",
                         f"give damping < (b - a)/V_lp = {(branch.b - branch.a) / branch.v_lp:g}")


def _v_lp_keys(br, v_lp: float) -> dict:
    """The keys of a branch in V_lp (``parameter = "v_lp"``), checked."""
    parameter = br.string("parameter", "kappa")
    if parameter not in _PARAMETERS:
        raise InputError(br.path("parameter"), parameter, "is not a continuation parameter",
                         f"use one of {', '.join(_PARAMETERS)}")
    if parameter == "kappa":
        extra = [key for key in ("start_point", "v_lp_min", "v_lp_max") if br.has(key)]
        if extra:
            raise InputError(br.path(extra[0]), br.raw(extra[0]), "is only for a branch in V_lp",
                             'add parameter = "v_lp", or remove the key')
        return {}
    lo = br.number("v_lp_min", 1e-6, above=0)
    hi = br.number("v_lp_max", 1e6, above=lo)
    if not lo < v_lp < hi:
        raise InputError(br.path("v_lp"), v_lp, f"is not inside [v_lp_min, v_lp_max] = [{lo:g}, {hi:g}]",
                         "start the branch inside its range")
    return {"parameter": parameter, "v_lp_min": lo, "v_lp_max": hi,
            "start_point": br.integer("start_point", 1, low=0, high=MAX_POINTS)}


def _closed_form_sweep(spec: StudySpec, echo) -> list:
    from .hopf import hopf_point

    rows = []
    a, dc = 0.01, 0.01
    for law in ("aging", "slip", "prz"):
        for eta in spec.hopf_eta:
            dk = dw = 0.0
            n = 0
            for ratio in spec.hopf_b_over_a:
                for v in spec.hopf_v_lp:
                    mass = None if eta == 0 else eta * a * dc / v ** 2
                    h = hopf_point(a=a, b=ratio * a, dc=dc, state_law=law, v_lp=v, mass=mass, dps=30,
                                   lyapunov=False)
                    dk = max(dk, h.rel_dev_k_c)
                    dw = max(dw, h.rel_dev_omega_c)
                    n += 1
            rows.append({"state_law": law, "eta": eta, "cases": n, "max_rel_dev_k_c": dk, "max_rel_dev_omega_c": dw})
            echo(f"  closed forms: {law:5s} eta={eta:g}: {n} cases, max rel dev k_c {dk:.1e}, omega_c {dw:.1e} "
                 "(30 digits)")
    return rows


def _bautin(law: str, a=0.01, b=0.015, dc=0.01, v=1.0):
    """η = M V²/(a Dc) where l1 changes sign (a Bautin point), or NaN if l1 keeps its sign on [1e-3, 3]."""
    import mpmath as mp

    from .hopf import hopf_point

    def l1(log_eta):
        eta = math.exp(float(log_eta))
        return hopf_point(a=a, b=b, dc=dc, state_law=law, v_lp=v, mass=eta * a * dc / v ** 2,
                          dps=30).lyapunov_coefficient

    grid = [math.log(x) for x in (1e-3, 1e-2, 0.1, 1.0, 3.0)]
    vals = [l1(g) for g in grid]
    for g0, g1, v0, v1 in zip(grid, grid[1:], vals, vals[1:]):
        if v0 * v1 < 0:
            with mp.workdps(20):
                root = mp.findroot(l1, (g0, g1), solver="anderson", tol=1e-14)
            return math.exp(float(root))
    return math.nan


def bautin_line(bautin: dict) -> str:
    """The Bautin points as one readable line: per state law η = M V_lp²/(a Dc) (dimensionless) where the
    first Lyapunov coefficient l1 changes sign, at _bautin's a = 0.01, b = 0.015, Dc = 0.01, V_lp = 1."""
    if not bautin:
        return "  Bautin points: not computed ([hopf] bautin = false)"
    cells = [f"{law} {eta:.6g}" if math.isfinite(eta) else f"{law} none (l1 keeps its sign for η in [1e-3, 3])"
             for law, eta in bautin.items()]
    return ("  Bautin points (l1 = 0) at η = M V_lp²/(a Dc) (dimensionless; a = 0.01, b = 0.015, Dc = 0.01, "
            "V_lp = 1): " + ", ".join(cells))


def run_study(path, out_dir=None, echo=print, damping=None) -> dict:
    """Run the workflow at ``path``; write ``<out>/branches.zarr``, ``REPORT.md`` and the figure.

    ``damping`` (``continue --damping``), when given, replaces every branch's radiation damping.
    """
    import dataclasses
    import pathlib

    from .continuation import continue_cycles, continue_in_v_lp, period_by_simulation
    from .hopf import lyapunov_by_simulation
    from .spec import SliderSpec

    spec = load_study(path)
    if damping is not None:
        spec = dataclasses.replace(spec, branches=tuple(dataclasses.replace(b, damping=damping)
                                                        for b in spec.branches))
    # Not the committed reference (results/<name>): a user's run must leave the checkout clean.
    out = pathlib.Path(out_dir or f"results/local/{spec.name}")
    t_start = time.perf_counter()
    echo(f"study {spec.name}: {len(spec.branches)} branches")
    sweep = _closed_form_sweep(spec, echo)
    bautin = {law: _bautin(law) for law in ("aging", "slip", "prz")} if spec.bautin else {}
    echo(bautin_line(bautin))
    results = []
    for br in spec.branches:
        t0 = time.perf_counter()
        if br.parameter == "kappa":
            branch = continue_cycles(a=br.a, b=br.b, dc=br.dc, state_law=br.state_law, v_lp=br.v_lp, mass=br.mass,
                                     damping=br.damping, points=br.points, max_step=br.max_step, kappa_range=(br.kappa_min, br.kappa_max))
        else:
            start = continue_cycles(a=br.a, b=br.b, dc=br.dc, state_law=br.state_law, v_lp=br.v_lp, mass=br.mass,
                                    damping=br.damping, points=max(br.start_point + 1, 2), max_step=br.max_step,
                                    kappa_range=(br.kappa_min, br.kappa_max))
            if br.start_point >= len(start.points):
                raise InputError(f"{br.label}: start_point", br.start_point,
                                 f"is beyond the {len(start.points)} points of the branch in κ ({start.meta['stop']})",
                                 "give a smaller start_point")
            branch = continue_in_v_lp(start, br.start_point, points=br.points, max_step=br.max_step,
                                      v_lp_range=(br.v_lp_min, br.v_lp_max))
        # Second turn in double where the cycle is at most mildly unstable; where a multiplier exceeds 10
        # the first turn's rounding is amplified that much before the second, so the check runs in real128.
        checks = [abs(period_by_simulation(branch, i, "double" if max(abs(z) for z in p.multipliers) < 10
                                           else "quad") / p.period - 1) for i, p in enumerate(branch.points)]
        quad_idx = sorted(set(range(0, len(branch.points), 10)) | set(branch.folds))
        quad = {i: abs(period_by_simulation(branch, i, "quad") / branch.points[i].period - 1) for i in quad_idx}
        hs = SliderSpec(a=br.a, b=br.b, dc=br.dc, state_law=br.state_law, k=branch.hopf.k_c, mass=br.mass,
                        damping=br.damping)
        l1_sim = lyapunov_by_simulation(hs, branch.hopf, br.v_lp, 5e-3)
        results.append({"spec": br, "branch": branch, "period_check": checks, "period_check_quad": quad,
                        "l1_simulation": l1_sim, "seconds": time.perf_counter() - t0})
        folds = (f"folds at points {', '.join(str(i) for i in branch.folds)}" if branch.folds else
                 "no fold")   # (was Python's "folds at []")
        echo(f"  {br.label}: {len(branch.points)} points, {folds}, "
             f"{branch.hopf.criticality} (l1 {branch.hopf.lyapunov_coefficient:.4g}, simulated {l1_sim:.4g}), "
             f"max period check {max(checks):.1e}, {branch.meta['stop']}, {time.perf_counter() - t0:.1f} s")
    fates = _quasi_static_fates(spec)
    # the two-parameter diagram starts its fold curves at the Bautin points: computed when they are
    diagram = None
    if spec.bautin:
        from .diagram import compute

        diagram = compute(results, bautin, echo)
    from .report import write_report, write_store

    # the directories this run creates, deepest first: an interrupt while writing removes them again, as
    # the interrupt message says nothing new was left (Ctrl-C during the write left an empty --out, or one
    # with only the store, walk 6); a directory that was there before is never removed
    created = [d for d in (out, *out.absolute().parents) if not d.exists()]
    out.mkdir(parents=True, exist_ok=True)
    try:
        write_store(out / "branches.zarr", spec, results)
        write_report(out, spec, sweep, bautin, results, fates, time.perf_counter() - t_start,
                     workflow=str(path), diagram=diagram)
    except BaseException:
        if created:
            shutil.rmtree(created[0], ignore_errors=True)   # --out itself: all in it is this run's
            for d in created[1:]:
                try:
                    d.rmdir()   # only if empty
                except OSError:
                    break
        raise
    echo(f"wrote {out}/branches.zarr, {out}/REPORT.md in {time.perf_counter() - t_start:.0f} s")
    return {"sweep": sweep, "bautin": bautin, "branches": results, "fates": fates, "diagram": diagram}


def _quasi_static_fates(spec: StudySpec) -> list:
    """Below k_c the quasi-static slider has no bounded cycle: a small perturbation grows until V blows up."""
    from .simulate import rate_state

    rows = []
    for law in ("aging", "slip", "prz"):
        c = 2.0 if law == "prz" else 1.0
        k_c = (0.015 - 0.01) / 0.01
        period = 2 * math.pi / (math.sqrt(0.5) * 100)
        for kappa in (0.9, 0.99):
            r = rate_state(a=0.01, b=0.015, dc=0.01, state_law=law, k=kappa * k_c, v_lp=1.0,
                           t=[0.0, 400 * period], v0=1.0, theta0=[c * 0.01 * math.exp(0.01)])
            top = max(r.extrema[:, 1]) if len(r.extrema) else math.nan
            rows.append({"state_law": law, "kappa": kappa, "status": r.status, "ln_v_max": float(top),
                         "ln_v_stop": float(r.meta.get("ln_v_stop", math.nan)), "message": r.message})
    return rows
