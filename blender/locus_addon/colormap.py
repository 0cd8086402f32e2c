"""Values to vertex colours: a perceptually ordered ramp (dark blue -> teal -> yellow).

Pure NumPy (no bpy), so the Blender tests can check the colours a value gets.
Control points approximate the viridis ramp; NaN (no value) is mid grey.
"""
import numpy as np

_STOPS = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
_RGB = np.array([[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551],
                 [0.369, 0.789, 0.383], [0.993, 0.906, 0.144]])


def ramp(t):
    """RGBA (n, 4) float32 for values t in [0, 1] (clamped; NaN grey)."""
    t = np.asarray(t, np.float64)
    bad = ~np.isfinite(t)
    t = np.clip(np.where(bad, 0.0, t), 0.0, 1.0)
    rgba = np.ones((len(t), 4), np.float32)
    for c in range(3):
        rgba[:, c] = np.interp(t, _STOPS, _RGB[:, c])
    rgba[bad, :3] = 0.5
    return rgba


def normalized(values, low_pct=2.0, high_pct=98.0):
    """values scaled to [0, 1] between two percentiles of the finite ones (robust to outliers)."""
    v = np.asarray(values, np.float64)
    finite = v[np.isfinite(v)]
    if finite.size == 0:
        return np.full(v.shape, np.nan)
    lo, hi = np.percentile(finite, [low_pct, high_pct])
    return (v - lo) / (hi - lo) if hi > lo else np.zeros_like(v)
