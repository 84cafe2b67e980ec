"""Benchmarks (``bifurcation bench``), side by side in one run and reported as ratios, never asserted:
the engine against its baselines (``engine``: scipy DOP853, naive heyoka) and the Dask pipeline
against the in-memory engine (``pipeline``). The store's fault injection (``store_faults``) and the
memory of a streamed query (``query_memory``) are scripts run as ``python -m bifurcation.bench.NAME``;
their last results are in results/bench/."""

from .engine import run_bench

__all__ = ["run_bench"]
