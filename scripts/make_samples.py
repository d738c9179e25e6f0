"""Regenerate the bundled rough sample sketches in ``samples/`` (deterministic).

Each intended curve is drawn with 2-4 hesitant, overlapping strokes that wander a few
pixels off it and over- or under-shoot its ends, the way a rough pencil pass looks. The
cluster id of every stroke is the intended curve it depicts, so tests can count them.

    python scripts/make_samples.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from core import Sketch, Stroke, write_sketch  # noqa: E402


def polyline(*pts: tuple[float, float]) -> np.ndarray:
    return np.array(pts, dtype=float)


def ellipse(cx: float, cy: float, rx: float, ry: float, a0: float = 0.0,
            a1: float = 2 * np.pi, n: int = 200) -> np.ndarray:
    t = np.linspace(a0, a1, n)
    return np.stack([cx + rx * np.cos(t), cy + ry * np.sin(t)], axis=1)


def _at(curve: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points and unit normals at arc-length fractions s (extrapolated outside [0, 1])."""
    seg = np.diff(curve, axis=0)
    cum = np.concatenate([[0], np.cumsum(np.hypot(*seg.T))])
    u = s * cum[-1]
    i = np.clip(np.searchsorted(cum, u) - 1, 0, len(seg) - 1)
    tangent = seg[i] / np.hypot(*seg[i].T)[:, None]
    pts = curve[i] + tangent * (u - cum[i])[:, None]
    return pts, np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)


def rough_strokes(curve: np.ndarray, cluster: int, rng: np.random.Generator,
                  wobble: float = 1.8, spacing: float = 4.0) -> list[Stroke]:
    length = float(np.hypot(*np.diff(curve, axis=0).T).sum())
    closed = np.allclose(curve[0], curve[-1])
    strokes = []
    for _ in range(rng.integers(2, 5)):
        if closed:
            s0 = rng.uniform(0, 1)
            s = np.linspace(s0, s0 + rng.uniform(0.6, 1.05), 200) % 1.0
        else:
            a, b = rng.uniform(-0.06, 0.12), rng.uniform(0.88, 1.06)
            s = np.linspace(a, b, 200)
        pts, normal = _at(curve, s)
        phase, freq = rng.uniform(0, 2 * np.pi), rng.uniform(0.5, 2.0)
        offset = (rng.normal(0, wobble * 0.6)
                  + wobble * 0.5 * np.sin(phase + freq * np.pi * np.linspace(0, 1, len(s))))
        pts = pts + normal * offset[:, None]
        n = max(3, int(length * (s.max() - s.min()) / spacing))
        keep = np.linspace(0, len(pts) - 1, n).astype(int)
        strokes.append(Stroke(pts[keep], width=np.full(n, 1.5), cluster=cluster))
    return strokes


SAMPLES = {
    "house": [
        polyline((100, 350), (300, 350)), polyline((300, 350), (300, 200)),
        polyline((300, 200), (100, 200)), polyline((100, 200), (100, 350)),
        polyline((90, 205), (200, 100)), polyline((200, 100), (310, 205)),
        polyline((170, 350), (170, 270), (220, 270), (220, 350)),
    ],
    "cup": [
        ellipse(200, 120, 90, 25), polyline((110, 120), (125, 330)),
        polyline((290, 120), (275, 330)), ellipse(200, 330, 75, 18, 0, np.pi),
        ellipse(282, 220, 55, 60, -np.pi / 2, np.pi / 2),
    ],
    "fish": [
        ellipse(200, 200, 130, 70, 0.25, 2 * np.pi - 0.25),
        polyline((326, 169), (390, 130), (380, 200), (390, 270), (326, 231)),
        ellipse(130, 185, 9, 9), ellipse(220, 200, 40, 50, -1.2, 1.2),
    ],
}


def main() -> None:
    out = ROOT / "samples"
    out.mkdir(exist_ok=True)
    for k, (name, curves) in enumerate(SAMPLES.items()):
        rng = np.random.default_rng(1000 + k)
        strokes = [s for i, c in enumerate(curves) for s in rough_strokes(c, i, rng)]
        for i, s in enumerate(strokes):
            s.source_id = i
        sketch = Sketch(strokes, 400.0, 400.0)
        write_sketch(sketch, out / f"{name}.scap")
        print(f"samples/{name}.scap: {len(strokes)} strokes, {len(curves)} intended curves")
    write_sketch(Sketch([s for s in strokes], 400.0, 400.0), out / "fish.svg")


if __name__ == "__main__":
    main()
