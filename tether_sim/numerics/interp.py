"""Piecewise-linear interpolation of many columns at the same points, each column's numbers those np.interp gives.

One compiled pass finds each point's interval once and applies it to every column, where np.interp per column
searches again and pays a call per column (a hybrid node's state() interpolated twelve columns that way)."""

import numpy as np

from tether_sim.numerics.jit import jit


@jit
def interp_columns(x, xp, F, out):
    """out[i, k] = np.interp(x[i], xp, F[:, k]), bit for bit, for increasing ``xp`` (K,), ``F`` (K, m), ``out`` (n, m).

    numpy's rule, operation for operation: the interval is the last ``j`` with ``xp[j] <= x`` (at a repeated grid value
    the later node); a point on a grid value takes that node's value, one at or beyond the last grid value the last
    value, one before the first the first value, a NaN point NaN; inside an interval ``slope * (x - xp[j]) + F[j]``
    with ``slope = (F[j + 1] - F[j]) / (xp[j + 1] - xp[j])``, where that is NaN ``slope * (x - xp[j + 1]) + F[j + 1]``,
    and then ``F[j]`` if both ends are equal. A one-point grid gives its value everywhere (NaN points included)."""
    K = xp.shape[0]
    m = F.shape[1]
    for i in range(x.shape[0]):
        xv = x[i]
        if K == 1:
            for k in range(m):
                out[i, k] = F[0, k]
            continue
        if np.isnan(xv):
            for k in range(m):
                out[i, k] = xv
            continue
        if xv > xp[K - 1]:
            j = K - 1
        elif xv < xp[0]:
            j = 0
        else:  # the last j with xp[j] <= xv
            lo, hi = 0, K
            while lo < hi:
                mid = lo + ((hi - lo) >> 1)
                if xv >= xp[mid]:
                    lo = mid + 1
                else:
                    hi = mid
            j = lo - 1
        if j == K - 1 or xp[j] == xv or xv < xp[0]:
            for k in range(m):
                out[i, k] = F[j, k]
            continue
        width = xp[j + 1] - xp[j]
        d0 = xv - xp[j]
        d1 = xv - xp[j + 1]
        for k in range(m):
            f0 = F[j, k]
            f1 = F[j + 1, k]
            slope = (f1 - f0) / width
            r = slope * d0 + f0
            if np.isnan(r):
                r = slope * d1 + f1
                if np.isnan(r) and f0 == f1:
                    r = f0
            out[i, k] = r
