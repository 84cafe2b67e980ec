"""Weighted linear least squares with column scaling, covariance and residuals, and Lambert W.

The asymptotic models mix columns from ν^{-1} to ν^3 (ν down to 1e-15), so columns are scaled to unit
size before the solve; the standard errors come from the covariance, by the SVD of the scaled matrix.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LinearFit", "lambert_w", "linear_fit"]


@dataclass(frozen=True)
class LinearFit:
    """``coef`` of the columns, their ``stderr``, ``residuals`` (data − model, data units) and
    ``chi`` (residuals / errors); ``max_chi`` and ``reduced_chi2`` summarise them."""

    coef: np.ndarray
    stderr: np.ndarray
    residuals: np.ndarray
    chi: np.ndarray

    @property
    def max_chi(self) -> float:
        return float(np.max(np.abs(self.chi)))

    @property
    def reduced_chi2(self) -> float:
        dof = max(self.chi.size - self.coef.size, 1)
        return float(np.sum(self.chi ** 2) / dof)


def linear_fit(columns, y, errors=None) -> LinearFit:
    """Least squares ``y ≈ Σ coef_i columns_i`` with weights 1/errors (all ones if None).

    With ``errors`` given, ``stderr`` is the covariance error scaled up by √(reduced χ²) when that
    exceeds 1, so a model that does not fit the data to their precision reports a larger error, never
    a smaller one. Without errors the residual scatter sets the scale (scaled by √(reduced χ²) always).
    """
    A = np.column_stack([np.asarray(c, dtype=float) for c in columns])
    y = np.asarray(y, dtype=float)
    err = np.ones_like(y) if errors is None else np.asarray(errors, dtype=float)
    w = 1.0 / err
    Aw = A * w[:, None]
    scale = np.max(np.abs(Aw), axis=0)
    scale[scale == 0] = 1.0
    As = Aw / scale
    u, s, vt = np.linalg.svd(As, full_matrices=False)
    cut = s > s[0] * A.shape[0] * np.finfo(float).eps
    inv = np.where(cut, 1.0 / np.where(cut, s, 1.0), 0.0)
    coef_s = vt.T @ (inv * (u.T @ (y * w)))
    coef = coef_s / scale
    residuals = y - A @ coef
    chi = residuals * w
    cov_s = (vt.T * inv ** 2) @ vt
    cov = cov_s / np.outer(scale, scale)
    dof = max(y.size - A.shape[1], 1)
    reduced = float(np.sum(chi ** 2) / dof)
    factor = reduced if errors is None else max(1.0, reduced)
    cov = cov * factor
    return LinearFit(coef=coef, stderr=np.sqrt(np.abs(np.diag(cov))), residuals=residuals, chi=chi)


def lambert_w(z) -> np.ndarray:
    """Principal branch W(z) for real z ≥ 0 (w e^w = z), by Halley's iteration to rounding."""
    z = np.asarray(z, dtype=float)
    w = np.where(z > np.e, np.log(np.maximum(z, 1e-300)) - np.log(np.log(np.maximum(z, np.e))),
                 z / (1 + z) * (1 + 0.5 * np.log1p(z)))
    for _ in range(40):
        ew = np.exp(w)
        f = w * ew - z
        step = f / (ew * (w + 1) - (w + 2) * f / (2 * w + 2))
        w = w - step
        if np.all(np.abs(step) <= 4 * np.finfo(float).eps * np.maximum(np.abs(w), 1e-300)):
            break
    return w
