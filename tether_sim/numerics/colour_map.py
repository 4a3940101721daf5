"""The tension colour map of the cable marker as one compiled loop (tether_sim/ros/convert.py,
``tension_colours``): blue (slack) through green to red, per output point.

The numpy statement of the map took ~11 array calls per marker, ~25 us per 41 points (2026-11-28,
load 3.6); this loop takes ~2 us. It does the same floating-point operations in the same order,
with numpy's rules for NaN (kept) and for equal arguments of ``np.maximum`` / ``np.minimum`` (the
second one is returned), so the colours are those of the numpy statement
(test/numerics/test_colour_map.py holds the two together, compiled and with NUMBA_DISABLE_JIT=1).
"""

from tether_sim.numerics.jit import jit


@jit
def tension_rgba(tension, scale, out):
    """out[k] = (max(d, 0), 1 - |d|, max(-d, 0), 1) with d = 2 tension[k] / scale - 1 clipped to
    [-1, 1] (d = -1 when ``scale`` <= 0): ``tension`` (n,), ``out`` (n, 4)."""
    for k in range(tension.shape[0]):
        if scale > 0.0:
            d = tension[k] / scale
            d = d * 2.0
            d = d - 1.0
            d = d if (d > -1.0 or d != d) else -1.0  # np.maximum(d, -1.0)
            d = d if (d < 1.0 or d != d) else 1.0  # np.minimum(d, 1.0)
        else:
            d = -1.0
        out[k, 0] = d if (d > 0.0 or d != d) else 0.0
        out[k, 1] = 1.0 - abs(d)
        e = -d
        out[k, 2] = e if (e > 0.0 or e != e) else 0.0
        out[k, 3] = 1.0
