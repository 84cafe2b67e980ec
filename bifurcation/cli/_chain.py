"""``bifurcation chain``: the event catalog of a Burridge–Knopoff chain (docs/chain.md)."""

from __future__ import annotations

import click

from ..errors import InputError
from ._common import echo_json, examples, number

__all__ = ["COMMANDS"]


def _u0(ctx, param, value):
    if value is None:
        return None
    try:
        return [float(x) for x in value.split(",")]
    except ValueError:
        raise click.BadParameter(f"{value!r} is not a comma-separated list of numbers; give e.g. 0,-0.1,0.05",
                                 param_hint="--u0") from None


@click.command("chain", epilog=examples(
    'bifurcation chain --law carlson-langer --n 8 --ell 1 --nu 1e-3 --nu-f 0.3 --amplitude 0.1 --seed 1 --events 10'))
@click.option("--law", required=True, help="Law name (see `bifurcation laws`) or formula in x.")
@click.option("--n", "n", required=True, type=int, help="Number of blocks N ≥ 1.")
@click.option("--ell", required=True, callback=number("--ell", "1"), help="Coupling ℓ ≥ 0.")
@click.option("--nu", required=True, callback=number("--nu", "1e-6"), help="Pulling speed ν > 0.")
@click.option("--nu-f", "nu_f", required=True, callback=number("--nu-f", "0.3"), help="Friction velocity ν_f > 0.")
@click.option("--ends", default="free", show_default=True, help="Boundary condition: free or periodic.")
@click.option("--u0", callback=_u0, help="Initial displacements u_1,...,u_N (comma-separated).")
@click.option("--amplitude", callback=number("--amplitude", "0.1"), help="Random start: amplitude A ≥ 0.")
@click.option("--seed", type=int, help="Random start: seed of numpy's default_rng.")
@click.option("--events", required=True, type=int, help="Number of events K ≥ 1.")
@click.option("--precision", type=click.Choice(["double", "quad"]), default="double", show_default=True)
@click.option("--engine", type=click.Choice(["exact", "compiled"]), default="exact", show_default=True,
              help="exact: heyoka Taylor (the reference); compiled: numba DOP853, events located the same way.")
@click.option("--verify", callback=number("--verify", "0.01"), default="0",
              help="Compiled engine: re-run this fraction of events exactly and print the largest difference.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (keys = the field names).")
def chain_cmd(law, n, ell, nu, nu_f, ends, u0, amplitude, seed, events, precision, engine, verify, as_json) -> None:
    """The first K events of a chain of N blocks: t_start, hypocentre, n_blocks, potency, duration,
    max_velocity per event, and the final state."""
    from ..models.chain import CATALOG_FIELDS, chain
    from ..models.chain._validate import check_size

    check_size(n, ell, ends)   # the chain first (N, ℓ, ends), then its start
    if u0 is None and amplitude is None:
        raise InputError("--amplitude", None, "is missing", "give --u0 a,b,c or --amplitude A --seed S")

    r = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, u0=u0, amplitude=amplitude, seed=seed,
              events=events, precision=precision, engine=engine, verify=verify)
    if as_json:
        echo_json(r.to_json())
    else:
        click.echo(f"{'event':>6s} " + " ".join(f"{k:>22s}" for k in CATALOG_FIELDS))
        for i in range(r.events):
            cells = [f"{r[k][i]:22d}" if k in ("hypocentre", "n_blocks") else f"{r[k][i]:22.15g}"
                     for k in CATALOG_FIELDS]
            click.echo(f"{i:6d} " + " ".join(cells))
        click.echo(f"status {r.status}; t = {r.t:.17g}" + (f"; {r.message}" if r.message else ""))
        if r.verification is not None:
            v = r.verification
            click.echo(f"verify: {v['checked']} events re-run exactly (every {v['every']}th); largest relative "
                       f"difference {v['largest_any']:.2e} (" + ", ".join(f"{k} {x:.1e}" for k, x in v['largest'].items())
                       + f"); hypocentre or size differ in {len(v['mismatched'])}")
    if r.status != 1:
        raise SystemExit(1)


COMMANDS = [chain_cmd]
