"""A rate-state study: a TOML workflow → Hopf table, branches of cycles, a Zarr store, a report.

``bifurcation continue workflows/rate-state.toml`` runs it. The workflow (see the shipped file for
every key) is validated into frozen specs before anything is computed or written; a bad key or value
is one ``InputError`` line naming it.

Output directory ``<out>``: ``--out``, default ``results/local/<study name>`` (ignored by git).
Store (``<out>/branches.zarr``, Zarr v3 through xarray, written once at the end so an interrupted run
leaves no half store): dimensions ``branch`` (labels in the attribute ``branch_labels``) × ``point`` (padded with NaN,
``status`` 0 = no point),
variables ``kappa``, ``k``, ``period``, ``period_check`` (relative difference to the direct-simulation
period), ``ln_v_max``, ``ln_v_min``, ``slip``, ``multiplier_max`` (largest |Floquet multiplier|),
``status`` (1 ok, 2 no-convergence) and per-branch ``k_c``, ``omega_c``, ``lyapunov_coefficient``,
``mass``, ``fold_kappa``; attributes hold the workflow text, the criticality per branch and the
stop reason of each continuation.
"""

from __future__ import annotations

import math
import time
import tomllib
from dataclasses import dataclass


from ...errors import InputError

__all__ = ["BranchSpec", "MAX_POINTS", "StudySpec", "load_study", "run_study"]

_SLIDER_KEYS = {"a", "b", "dc", "v_lp"}
_BRANCH_KEYS = {"label", "state_law", "eta", "damping", "points", "max_step", "kappa_min", "kappa_max", "parameter",
                "start_point", "v_lp_min", "v_lp_max", *_SLIDER_KEYS}
_PARAMETERS = ("kappa", "v_lp")
_HOPF_KEYS = {"b_over_a", "v_lp", "eta", "bautin"}


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


def _unknown(table: str, got, allowed) -> None:
    extra = sorted(set(got) - set(allowed))
    if extra:
        raise InputError(f"{table}.{extra[0]}", got[extra[0]], "is not a known key",
                         f"use one of {', '.join(sorted(allowed))}")


def _num(key, value, lo=None, integer=False):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(key, value, "is not a finite number", "give a number")
    if lo is not None and not value > lo:
        raise InputError(key, value, f"must be > {lo:g}", f"give a value above {lo:g}")
    if integer and int(value) != value:
        raise InputError(key, value, "is not an integer", "give a whole number")
    return int(value) if integer else float(value)


#: Bounds of a study's size: each branch point is a periodic orbit solved and checked by simulation
#: (seconds), so 10^3 points on a branch are already an hour; the closed-form check takes every
#: combination of the [hopf] lists.
MAX_POINTS = 1000
MAX_BRANCHES = 100
MAX_HOPF_VALUES = 100
MAX_ETA = 1e3


def _bounded(key, value, meaning: str, fix: str) -> float:
    """A coefficient in [0, MAX_ETA]: ``meaning`` says what 0 means, ``fix`` what to write."""
    value = _num(key, value)
    if not 0 <= value <= MAX_ETA:
        raise InputError(key, value, f"must be in [0, {MAX_ETA:g}] ({meaning})", fix)
    return value


def _eta(key, value) -> float:
    """η = M V_lp²/(a Dc) ≥ 0 (0: quasi-static)."""
    return _bounded(key, value, "η = M V_lp²/(a Dc); 0 is quasi-static",
                    "give eta >= 0, e.g. 0.1, or 0 for the quasi-static slider")


def _damping(key, value) -> float:
    """Radiation damping ETA ≥ 0, friction per unit slip rate (docs/rate-state.md, "Radiation damping")."""
    return _bounded(key, value, "friction per unit slip rate; 0 is none",
                    "give damping >= 0, e.g. 0.002, or 0 for no radiation damping")


def _points(key, value) -> int:
    value = _num(key, value, 2, integer=True)
    if value > MAX_POINTS:
        raise InputError(key, value, f"is more than {MAX_POINTS} points on one branch",
                         "give at most 1000 (a branch point is a periodic orbit: seconds each), or a larger "
                         "max_step to cover the branch with fewer points")
    return value


def load_study(path) -> StudySpec:
    """Read and validate a rate-state workflow (one ``InputError`` line on the first problem)."""
    from .laws import resolve_state_law

    from ...workflow._toml import other_command, read_workflow_text

    text = read_workflow_text(path, "WORKFLOW", "workflows/rate-state.toml")
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("WORKFLOW", str(path), f"is not valid TOML ({exc})", "fix the TOML syntax") from None
    except RecursionError:   # tables or arrays nested thousands deep
        raise InputError("WORKFLOW", str(path), "is nested too deeply", "see workflows/rate-state.toml") from None
    other_command(doc, "continue", "WORKFLOW", path)
    _unknown("workflow", doc, {"study", "slider", "branch", "hopf"})
    study = doc.get("study", {})
    _unknown("study", study, {"name", "description"})
    name = study.get("name")
    if not isinstance(name, str) or not name.replace("-", "").replace("_", "").isalnum():
        raise InputError("study.name", name, "is missing or not a plain name", "give e.g. name = \"rate-state\"")
    slider = doc.get("slider", {})
    _unknown("slider", slider, _SLIDER_KEYS)
    branches = doc.get("branch", [])
    if not isinstance(branches, list) or not branches:
        raise InputError("branch", branches, "is empty", "give at least one [[branch]] table")
    out = []
    if len(branches) > MAX_BRANCHES:
        raise InputError("branch", f"{len(branches)} tables", f"is more than {MAX_BRANCHES} branches",
                         "split the study into several workflows")
    for i, br in enumerate(branches):
        if not isinstance(br, dict):
            raise InputError(f"branch[{i}]", br, "is not a table", "write each branch as a [[branch]] table")
        _unknown(f"branch[{i}]", br, _BRANCH_KEYS)
        merged = {**slider, **br}

        def key_of(key, i=i, br=br):   # a value from [slider] is named there, not in the branch
            return f"branch[{i}].{key}" if key in br else f"slider.{key}"

        for key in ("a", "b", "dc", "v_lp"):
            if key not in merged:
                raise InputError(f"branch[{i}].{key}", None, "is missing", f"set {key} in [slider] or the branch")
        law = resolve_state_law(merged.get("state_law", ""), argument=f"branch[{i}].state_law").name
        a = _num(key_of("a"), merged["a"], 0)
        b = _num(key_of("b"), merged["b"], a)
        out.append(BranchSpec(
            label=str(merged.get("label", f"{law} {i}")), state_law=law, a=a, b=b,
            dc=_num(key_of("dc"), merged["dc"], 0), v_lp=_num(key_of("v_lp"), merged["v_lp"], 0),
            eta=_eta(f"branch[{i}].eta", merged.get("eta", 0.0)),
            damping=_damping(f"branch[{i}].damping", merged.get("damping", 0.0)),
            points=_points(f"branch[{i}].points", merged.get("points", 30)),
            max_step=_num(f"branch[{i}].max_step", merged.get("max_step", 0.5), 0),
            kappa_min=_num(f"branch[{i}].kappa_min", merged.get("kappa_min", 0.05), 0),
            kappa_max=_num(f"branch[{i}].kappa_max", merged.get("kappa_max", 20.0), 1),
            **_v_lp_keys(i, merged)))
    hopf = doc.get("hopf", {})
    _unknown("hopf", hopf, _HOPF_KEYS)

    def lst(key, default, lo, hi=None):
        v = hopf.get(key, default)
        if not isinstance(v, list) or not v:
            raise InputError(f"hopf.{key}", v, "is not a non-empty list", "give a list of numbers")
        if len(v) > MAX_HOPF_VALUES:
            raise InputError(f"hopf.{key}", f"{len(v)} values", f"is more than {MAX_HOPF_VALUES} values",
                             "give fewer values (the closed-form check takes every combination)")
        if key == "eta":
            return tuple(_eta(f"hopf.{key}", x) for x in v)
        out = tuple(_num(f"hopf.{key}", x, lo) for x in v)
        for x in out:
            if hi is not None and x > hi:
                raise InputError(f"hopf.{key}", x, f"is more than {hi:g}", f"give values in ({lo:g}, {hi:g}]")
        return out

    bautin = hopf.get("bautin", True)
    if not isinstance(bautin, bool):
        raise InputError("hopf.bautin", bautin, "is not true or false", "give bautin = true or false")
    return StudySpec(name, str(study.get("description", "")), tuple(out),
                     lst("b_over_a", [1.1, 2.0, 10.0], 1, 1e3), lst("v_lp", [1e-3, 1.0, 1e3], 0, 1e6),
                     lst("eta", [0.0, 1.0], None), text, bautin)


def _v_lp_keys(i: int, br: dict) -> dict:
    """The keys of a branch in V_lp (``parameter = "v_lp"``), checked."""
    parameter = br.get("parameter", "kappa")
    if parameter not in _PARAMETERS:
        raise InputError(f"branch[{i}].parameter", parameter, "is not a continuation parameter",
                         f"use one of {', '.join(_PARAMETERS)}")
    if parameter == "kappa":
        extra = sorted({"start_point", "v_lp_min", "v_lp_max"} & set(br))
        if extra:
            raise InputError(f"branch[{i}].{extra[0]}", br[extra[0]], "is only for a branch in V_lp",
                             'add parameter = "v_lp", or remove the key')
        return {}
    lo = _num(f"branch[{i}].v_lp_min", br.get("v_lp_min", 1e-6), 0)
    hi = _num(f"branch[{i}].v_lp_max", br.get("v_lp_max", 1e6), lo)
    if not lo < br["v_lp"] < hi:
        raise InputError(f"branch[{i}].v_lp", br["v_lp"], f"is not inside [v_lp_min, v_lp_max] = [{lo:g}, {hi:g}]",
                         "start the branch inside its range")
    return {"parameter": parameter, "v_lp_min": lo, "v_lp_max": hi,
            "start_point": _num(f"branch[{i}].start_point", br.get("start_point", 1), -1, integer=True)}


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
    echo(f"  Bautin points (l1 = 0) in eta: {bautin}")
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
        echo(f"  {br.label}: {len(branch.points)} points, folds at {list(branch.folds)}, "
             f"{branch.hopf.criticality} (l1 {branch.hopf.lyapunov_coefficient:.4g}, simulated {l1_sim:.4g}), "
             f"max period check {max(checks):.1e}, {branch.meta['stop']}, {time.perf_counter() - t0:.1f} s")
    fates = _quasi_static_fates(spec)
    # the two-parameter diagram starts its fold curves at the Bautin points: computed when they are
    diagram = None
    if spec.bautin:
        from .diagram import compute

        diagram = compute(results, bautin, echo)
    out.mkdir(parents=True, exist_ok=True)
    from .report import write_report, write_store

    write_store(out / "branches.zarr", spec, results)
    write_report(out, spec, sweep, bautin, results, fates, time.perf_counter() - t_start, workflow=str(path),
                 diagram=diagram)
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
                         "message": r.message})
    return rows
