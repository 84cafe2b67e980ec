"""Models beyond the single block of the paper (minimal package; the model registry lands here)."""

from __future__ import annotations

__all__: list[str] = []
