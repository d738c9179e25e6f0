"""Shared test helpers: where the real sketches are, and small geometric builders."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"
DATA = Path(os.environ.get("SKETCHSIMP_DATA", ROOT.parent / "shared" / "data"))


def rough_inputs() -> list[Path]:
    """Every rough .scap under the shared data folder (not the clean references)."""
    if not DATA.is_dir():
        return []
    return sorted(p for p in DATA.rglob("*.scap") if p.name != "full_fit.scap")


def require_data() -> list[Path]:
    files = rough_inputs()
    if not files:
        pytest.skip(f"real sketches not found at {DATA} (set SKETCHSIMP_DATA to use them)")
    return files


def circle(cx: float, cy: float, r: float, n: int = 128, start: float = 0.0) -> np.ndarray:
    """A closed polyline (first point repeated last)."""
    t = start + np.linspace(0, 2 * np.pi, n + 1)
    return np.stack([cx + r * np.cos(t), cy + r * np.sin(t)], axis=1)


def square(x0: float, y0: float, size: float) -> np.ndarray:
    return np.array([[x0, y0], [x0 + size, y0], [x0 + size, y0 + size], [x0, y0 + size],
                     [x0, y0]], dtype=float)
