"""Benchmarks (``bifurcation bench``), side by side in one run and reported as ratios, never asserted:
the engine against its baselines (``engine``: scipy DOP853, naive heyoka) and the Dask pipeline
against the in-memory engine (``pipeline``)."""

from .engine import run_bench

__all__ = ["run_bench"]
