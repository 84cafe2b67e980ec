"""The report of a user's store: what the store holds, read from its model's declaration.

``bifurcation report --store S`` writes this (``bifurcation reproduce`` writes the paper's report,
``render.write_report``). For each store: its model (equation, source), its laws (each with its
equation), its axes (range, points, units), the statuses, and for each law the slip Δ against each
axis (one figure per law), the transition from stick-slip to creep along each axis where the grid
crosses it (the labels either side and the jump of Δ, its finite-grid rounding), and, for the single
block, the ν → 0 extrapolation at every ν_f whose series along ν is long enough and the
recurrence-time fit at every such ν_f below 1/2. The paper's claims table is added only where the
stores hold both of the paper's laws (piecewise-linear and Carlson–Langer). Nothing is computed for
a law the stores do not hold, and the laws the user wrote are the ones named.
"""

from __future__ import annotations

import contextvars
import math
from pathlib import Path

import numpy as np

from . import figures as F
from .document import Figure, Heading, Items, Paragraph, Section, Table, to_html, to_markdown
from ..errors import shown_path

__all__ = ["MIN_SERIES", "block_section", "note", "single_block_section", "write_store_report"]

#: Where ``note`` sends what the report is doing: ``write_store_report``'s ``progress`` while it runs.
_PROGRESS = contextvars.ContextVar("bifurcation_report_progress", default=None)


def note(text: str) -> None:
    """Tell the caller of ``write_store_report`` what the report is doing (a model's ``report`` hook calls
    it before a long step, e.g. a Clauset fit of 10^5 sizes; the CLI prints it on stderr)."""
    sink = _PROGRESS.get()
    if sink is not None:
        sink(text)

#: Finished points along ν (at ν ≤ 1e-6) that an extrapolation or a recurrence-time fit needs: the
#: expansions have up to 6 terms, fitted over three windows.
MIN_SERIES = 12
_MAX_LINES = 6          # curves per panel
_MAX_ROWS = 12          # transition rows per (law, axis)
_PAPER_LAWS = ("piecewise-linear", "carlson-langer")


def _labels(ds, dim) -> list:
    return [v.item() if hasattr(v, "item") else v for v in np.asarray(ds[dim].values)]


def _pick(n: int, k: int) -> list[int]:
    """At most ``k`` indices spread evenly over ``range(n)``, both ends included."""
    if n <= k:
        return list(range(n))
    return sorted({round(i * (n - 1) / (k - 1)) for i in range(k)})


def _fmt_value(x) -> str:
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def _figure_law(ds, model, law_index: int, law: str):
    """Δ against each axis of ``model`` for one law: one panel per axis, one line per label of the
    next axis; the other axes at their middle label (said in the panel title)."""
    from ..engine.result import Status

    axes = model.axes
    fig, panels = F._figure(4.6 * len(axes), 3.6, ncols=len(axes))
    good = (int(Status.STICK_SLIP), int(Status.CREEP))
    sub = ds.isel({model.labels.name: law_index})
    delta, status, done = (np.asarray(sub[v].values) for v in ("delta", "status", "done"))
    notes = []
    for k, axis in enumerate(axes):
        ax = panels[0][k]
        x = np.asarray(sub[axis.name].values, dtype=float)
        if len(axes) > 1:
            line_axis = axes[(k + 1) % len(axes)]
            line_dim = [a.name for a in axes].index(line_axis.name)
        else:
            line_axis, line_dim = None, None
        fixed = {}
        for j, other in enumerate(axes):
            if j != k and other is not line_axis:
                fixed[j] = len(sub[other.name]) // 2
        lines = _pick(len(sub[line_axis.name]), _MAX_LINES) if line_axis is not None else [None]
        drawn = False
        for li in lines:
            index = []
            for j in range(len(axes)):
                if j == k:
                    index.append(slice(None))
                elif j == line_dim:
                    index.append(li)
                else:
                    index.append(fixed[j])
            d, s, ok = delta[tuple(index)], status[tuple(index)], done[tuple(index)]
            keep = ok & np.isin(s, good) & np.isfinite(d) & (d > 0)
            label = (f"{line_axis.symbol} = {_fmt_value(_labels(sub, line_axis.name)[li])}"
                     if line_axis is not None else None)
            ax.plot(x[keep], d[keep], ".-", lw=1.0, ms=3, label=label)
            drawn |= bool(keep.any())
        ax.set_xlabel(f"{axis.symbol} ({axis.name})")
        ax.set_ylabel("Δ")
        if axis.scale == "log":
            ax.set_xscale("log")
        if drawn:
            ax.set_yscale("log")
        else:   # a log axis of nothing: a ValueError traceback for a store no point of which is done (walk 6)
            ax.text(0.5, 0.5, "no finished point here", transform=ax.transAxes, ha="center", va="center")
        title = f"Δ vs {axis.symbol}"
        at = ", ".join(f"{axes[j].symbol} = {_fmt_value(_labels(sub, axes[j].name)[i])}" for j, i in fixed.items())
        if at:
            title += f" at {at}"
            notes.append(at)
        ax.set_title(title, fontsize=9)
        if line_axis is not None:
            ax.legend(fontsize=7)
    fig.suptitle(f"{law}", fontsize=10)
    return fig, notes


def _transitions(ds, model, law_index: int) -> list[list[str]]:
    """Rows (axis, where, between, Δ either side) where status turns stick-slip ↔ creep along an axis."""
    from ..engine.result import Status

    sub = ds.isel({model.labels.name: law_index})
    status, delta, done = (np.asarray(sub[v].values) for v in ("status", "delta", "done"))
    axes = model.axes
    rows = []
    for k, axis in enumerate(axes):
        labels = _labels(sub, axis.name)
        found = []
        others = [range(len(sub[a.name])) if j != k else [slice(None)] for j, a in enumerate(axes)]
        for index in np.ndindex(*[len(o) for o in others]):
            idx = tuple(slice(None) if j == k else index[j] for j in range(len(axes)))
            s, d, ok = status[idx], delta[idx], done[idx]
            for i in range(len(labels) - 1):
                if not (ok[i] and ok[i + 1]):
                    continue
                pair = {int(s[i]), int(s[i + 1])}
                if pair == {int(Status.STICK_SLIP), int(Status.CREEP)}:
                    at = ", ".join(f"{a.symbol} = {_fmt_value(_labels(sub, a.name)[index[j]])}"
                                   for j, a in enumerate(axes) if j != k)
                    found.append([axis.symbol, at or "—",
                                  f"{_fmt_value(labels[i])} ({_status(s[i])}) → {_fmt_value(labels[i + 1])} "
                                  f"({_status(s[i + 1])})", f"{d[i]:.6g} → {d[i + 1]:.6g}"])
        rows += [found[i] for i in _pick(len(found), _MAX_ROWS)]
    return rows


def _status(code) -> str:
    from ..engine.result import Status

    return str(Status(int(code)))


def _single_block_fits(ds, law: str):
    """Extrapolations and recurrence-time fits at every ν_f whose series along ν allows it."""
    from ..analysis import extrapolate_delta, fit_period
    from ..analysis._data import series_along_nu
    from ..analysis.period_fit import R_MAX
    from ..errors import InputError
    from ..theory import alpha, omega

    extrapolations, fits, skipped, not_applicable = [], [], [], []
    for nu_f in _labels(ds, "nu_f"):
        try:
            s = series_along_nu(ds, law, nu_f)
        except InputError:
            continue
        small = int(np.count_nonzero(s.x <= 1e-6))
        if small < MIN_SERIES:
            continue
        if 0 < nu_f < 0.5 and (alpha(nu_f) - omega(nu_f)) ** 2 >= R_MAX:
            not_applicable.append(nu_f)   # one sentence for all of them, not a column of noise
            continue
        try:
            extrapolations.append(extrapolate_delta(ds, law, nu_f))
        except (InputError, ValueError, np.linalg.LinAlgError) as exc:
            skipped.append(f"extrapolation at ν_f = {nu_f:g}: {exc}")
        if 0 < nu_f < 0.5:
            try:
                fits.append(fit_period(ds, law, nu_f))
            except (InputError, ValueError, np.linalg.LinAlgError) as exc:
                skipped.append(f"recurrence-time fit at ν_f = {nu_f:g}: {exc}")
    return extrapolations, fits, skipped, not_applicable


def _being_written(ds) -> str:
    """A sentence when the store is still being written (a submit holds its lock), or when points are missing:
    the report is then a snapshot of the points done so far, not the study (issue 21: `export` and `report`
    of a store being written read as complete)."""
    from ..store.lock import holder

    path = ds.attrs.get("store_path")
    done = np.asarray(ds["done"].values) if "done" in ds else None
    counts = f"{int(done.sum())} of {done.size} points done" if done is not None else "points still missing"
    found = holder(path) if path else None
    if found is not None:
        return (f"**Still being written** by {found.describe()} when this report was made ({counts}): it shows "
                "the points done so far, not the complete study; make the report again when the submit has ended.")
    if done is not None and not done.all():
        return (f"**Incomplete**: {counts}; the points not done are missing from every table and figure "
                f"(submit the same workflow again to compute them).")
    return ""


def _store_section(ds, out: Path, figures: list, stem: str) -> Section:
    """One store's section: what every store has, then the model's own blocks (its ``report`` hook)."""
    from ..models import get_model
    from ..outcome import Status
    from ..store.layout import store_model

    model = get_model(store_model(ds.attrs))
    a = ds.attrs
    laws = _labels(ds, model.labels.name)
    b: list = [Paragraph(f"Model {model.name}: {model.title}. {model.description}. Source: {model.source}.")]
    being = _being_written(ds)
    if being:
        b.insert(0, Paragraph(being))
    describe = model.hook("describe_label")
    label = model.labels.name   # the first column holds the store's labels: laws, or rate-state's branches
    rows = []
    for law in laws if describe is not None else ():   # (branches of cycles: labels, not equations)
        try:
            spec = describe(law)
            rows.append([law, spec.equation, spec.source])
        except Exception as exc:  # noqa: BLE001 — a label this version cannot read is still listed
            rows.append([law, "(cannot be read by this version)", str(exc)])
    if rows:
        b.append(Table([label, "equation", "source"], rows))
    b.append(Table(["axis", "symbol", "from", "to", "points", "units", "spacing"],
                   [[ax.name, ax.symbol, _fmt_value(ax.shown(_labels(ds, ax.name)[0])),
                     _fmt_value(ax.shown(_labels(ds, ax.name)[-1])),
                     str(ds.sizes[ax.name]), ax.units, ax.scale] for ax in model.axes]))
    status = np.asarray(ds["status"].values)
    statuses = (Status.NOT_COMPUTED, *(s for s in model.statuses if int(s) != int(Status.NOT_COMPUTED)))
    b.append(Paragraph("Points per status:"))
    b.append(Table([label, *(str(s) for s in statuses)],
                   [[law, *(str(int(np.count_nonzero(status[i] == int(s)))) for s in statuses)]
                    for i, law in enumerate(laws)]))
    own = model.hook("report")
    if own is not None:
        b += own(ds, model, out, figures, stem)
    return Section(f"Store {a.get('store_path', '(in memory)')}: study {a.get('title', '?')!r}", b)


def block_section(ds, model, out: Path, figures: list, stem: str) -> list:
    """The ``report`` hook of a block model (single and damped block): per law, slip Δ against each
    axis and the stick-slip ↔ creep transitions along them."""
    return _slip_blocks(ds, model, out, figures, stem, fits=False)


def single_block_section(ds, model, out: Path, figures: list, stem: str) -> list:
    """The single block's ``report`` hook: ``block_section`` and, per law, the ν → 0 extrapolations
    and recurrence-time fits its theory allows."""
    return _slip_blocks(ds, model, out, figures, stem, fits=True)


def _slip_blocks(ds, model, out: Path, figures: list, stem: str, *, fits: bool) -> list:
    from .render import _fmt

    laws = _labels(ds, model.labels.name)
    per_law = []   # (title, blocks): each law's blocks are filled below, then made a section
    for i, law in enumerate(laws):
        b: list = []
        per_law.append((f"Law {law}", b))
        fig, _ = _figure_law(ds, model, i, law)
        name = f"{stem}_law{i}_delta.png"
        F.save(fig, out / name)
        figures.append(out / name)
        b.append(Figure(name, f"Slip Δ of {law} against each axis of the store ({model.name}); only finished "
                              "stick-slip and creep points are drawn."))
        transitions = _transitions(ds, model, i)
        if transitions:
            b.append(Paragraph("Transition between stick-slip and creep along each axis (the grid's neighbouring "
                               "labels either side: the finite-grid rounding of the transition):"))
            b.append(Table(["along", "at", "between", "Δ either side"], transitions))
        else:
            b.append(Paragraph("No neighbouring points of this law change between stick-slip and creep on this grid."))
        if not fits:
            b.append(Paragraph(f"The ν → 0 extrapolation and the recurrence-time fit use the single block's theory; "
                               f"they are not made for model {model.name}."))
            continue
        extrapolations, fitted, skipped, not_applicable = _single_block_fits(ds, law)
        if extrapolations:
            b.append(Paragraph("Δ(ν → 0) extrapolated from the finite-ν points at every ν_f whose series along ν "
                               f"allows it ({MIN_SERIES}+ points at ν ≤ 1e-6), against the direct limit (the "
                               "engine's ν = 0 orbit; 0 in creep):"))
            b.append(Table(["ν_f", "regime", "points", "extrapolated Δ0", "uncertainty", "direct Δ0", "consistent"],
                           [[f"{e.nu_f:g}", e.regime, str(e.nu.size), f"{e.delta0_extrapolated:.8g}",
                             f"{e.uncertainty:.1e}", f"{e.delta0_direct:.12g}", "yes" if e.consistent else "NO"]
                            for e in extrapolations]))
        else:
            b.append(Paragraph(f"No ν → 0 extrapolation: no ν_f of this store has {MIN_SERIES} finished points "
                               "along ν at ν ≤ 1e-6."))
        if fitted:
            b.append(Paragraph("Recurrence time T − Δ0/ν = (α − ω) ln(1/ν) + C0 + K ν^−(α−ω)² + … at every such "
                               "ν_f below 1/2 (the fitted ln coefficient against α − ω):"))
            b.append(Table(["ν_f", "ln coefficient (fit)", "α − ω", "rel. dev.", "C0", "K", "terms", "max |residual|"],
                           [[f"{f.nu_f:g}", f"{f.log_coefficient:.8f} ± {f.log_coefficient_uncertainty:.0e}",
                             f"{f.log_coefficient_expected:.8f}", f"{f.relative_deviation:+.1e}", _fmt(f.C0),
                             _fmt(f.K), str(len(f.model)), f"{f.residual_max:.1e}"] for f in fitted]))
        if not_applicable:
            where = (f"ν_f = {not_applicable[0]:g}" if len(not_applicable) == 1 else
                     f"ν_f = {not_applicable[0]:g} … {not_applicable[-1]:g} ({len(not_applicable)} labels)")
            b.append(Paragraph(f"The stick-slip extrapolation and the recurrence-time fit do not apply at {where}: "
                               "there r = (α − ω)² ≥ 1/2 (ν_f ≥ √2/3 ≈ 0.4714), the term ν^(1−2r) grows as ν → 0 "
                               "and the expansion's terms crowd together as ν_f → 1/2; at ν_f = 1/2 itself the "
                               "critical expansion in ε applies (the row above, where the store holds it)."))
        _fit_figures(b, figures, out, f"{stem}_law{i}", law, extrapolations, fitted)
        if skipped:
            b.append(Items(skipped))
    return [Section(title, b, level=3) for title, b in per_law]


#: Recurrence-time series drawn per law (evenly spread over the fitted ν_f): more is unreadable.
_MAX_FITS_DRAWN = 4


def _fit_figures(b: list, figures: list, out: Path, stem: str, law: str, extrapolations, fits) -> None:
    """The figures of the fits, as the paper's report draws them: Δ at ν_f = 1/2 against ε with the
    extrapolation, and T − Δ0/ν against ν with the fitted expansion and its residuals."""
    critical = [e for e in extrapolations if e.regime == "critical"]
    if critical:
        name = f"{stem}_critical.png"
        F.save(F.figure_critical({law: critical[0]}), out / name)
        figures.append(out / name)
        b.append(Figure(name, f"{law} at ν_f = 1/2: Δ against ε = 1/W(1/(2eν)) (≈ 1/ln(1/ν)), the polynomial "
                              "fit in ε, its extrapolation to ε = 0 and the direct ν → 0 limit."))
    if fits:
        drawn = [fits[i] for i in _pick(len(fits), _MAX_FITS_DRAWN)]
        name = f"{stem}_period.png"
        F.save(F.figure_period(drawn), out / name)
        figures.append(out / name)
        b.append(Figure(name, f"{law}: T − Δ0/ν against ν at ν_f = "
                              f"{', '.join(f'{f.nu_f:g}' for f in drawn)} with the fitted expansion (solid) "
                              "and (α − ω) ln(1/ν) alone (dashed); below, the residuals over the data error "
                              "(±1 shaded; these move on another CPU: the data error is the rounding)."))


def _holds_paper_laws(stores) -> bool:
    from ..analysis._data import _law_index, _single_block

    return all(any(_single_block(ds) and _law_index(ds, law) is not None for ds in stores) for law in _PAPER_LAWS)


def write_store_report(sources, out, *, progress=None) -> dict:
    """Report what the stores ``sources`` (paths or Datasets) hold into directory ``out``.

    Returns ``{"markdown": …, "html": …, "figures": [...]}``. ``progress(text)``, if given, is told what
    the report is doing (which store, and the long steps of a model's section: ``note``).
    """
    token = _PROGRESS.set(progress)
    try:
        return _write_store_report(sources, out)
    finally:
        _PROGRESS.reset(token)


def _write_store_report(sources, out) -> dict:
    from .. import __version__
    from ..analysis import claims_table, load_stores
    from ..models import get_model
    from ..store.layout import store_model
    from .render import _versions, paper_claims_table

    sources = list(sources) if isinstance(sources, (list, tuple)) else [sources]
    stores = []
    for s in sources:
        stores.extend(load_stores(s) if isinstance(s, (str, Path)) else [s])
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    figures: list = []
    titles = ", ".join(repr(ds.attrs.get("title", "?")) for ds in stores)
    notes = [get_model(store_model(ds.attrs)).units_note for ds in stores]
    units = "units: " + ("; ".join(dict.fromkeys(n for n in notes if n))
                         or "those the model declares on its axes and outputs")
    blocks: list = [Heading(f"Study report: {titles}", 1),
                    Paragraph(f"Every number below is read from the stores or computed from them by this package; "
                              f"{units}.")]
    for k, ds in enumerate(stores):
        note(f"store {k + 1} of {len(stores)} ({shown_path(ds.attrs.get('store_path', 'in memory'))}, model "
             f"{store_model(ds.attrs)}): reading it and drawing its section")
        blocks.append(_store_section(ds, out, figures, f"store{k}"))
    if _holds_paper_laws(stores):
        blocks.append(Section("The paper's claims (the stores hold its two laws)",
                              [paper_claims_table(claims_table(stores))]))
    prov = [f"bifurcation {__version__}; " + ", ".join(f"{p} {v}" for p, v in _versions().items())]
    for ds in stores:
        a = ds.attrs
        prov.append(f"store {shown_path(a.get('store_path', '(in memory)'))}: model {a.get('model', 'single-block')}, workflow "
                    f"sha256 {str(a.get('workflow_sha256', '?'))[:16]}, precision {a.get('precision', '?')}, "
                    f"{math.prod(ds['status'].shape)} points, written by bifurcation {a.get('version_bifurcation', '?')}")
    blocks.append(Section("Provenance", [Items(prov)]))
    note("writing REPORT.md and report.html")
    md, page = out / "REPORT.md", out / "report.html"
    md.write_text(to_markdown(blocks), encoding="utf-8")
    page.write_text(to_html(blocks, out), encoding="utf-8")
    return {"markdown": md, "html": page, "figures": figures}
