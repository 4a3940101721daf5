"""Plain-Python conversion of the DG solver's per-tick inputs (no compiled code: editing this file
keeps the kernel cache, dg/cache.py)."""

import numpy as np


def motion_floats(position, velocity):
    """set_end_motion's (x, y, z, vx, vy, vz) as Python floats. Arrays of shape (3,) and flat
    sequences of three skip numpy's conversion (~1 us against ~3 us a call, every node tick);
    anything else goes through np.array(..., float).reshape(3) and its errors."""
    return _three_floats(position) + _three_floats(velocity)


def _three_floats(x):
    if isinstance(x, np.ndarray):
        if x.shape == (3,):
            a, b, c = x.tolist()
            return float(a), float(b), float(c)
    else:
        try:
            a, b, c = x
            return float(a), float(b), float(c)
        except (TypeError, ValueError):
            pass
    return tuple(np.array(x, dtype=float).reshape(3).tolist())
