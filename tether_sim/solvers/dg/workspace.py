"""The DG solver's arrays in two arenas, and the one compiled call per tick.

Every array the compiled code reads or writes (state, work arrays, operators, parameters, end
data, bodies, the end-tension ring, the implicit-damping arrays) is a view into one float64 arena
``F`` or one int64 arena ``I``, described by the slot table ``SLOTS`` (name, arena, rank) and the
int array ``spec`` (offset and shape of each slot). A compiled call then takes three arrays
instead of ~50: an njit call pays ~0.1-0.3 us per array argument to unbox it (measured
2026-11-23: 49 array arguments 4.4 us a call, the same 49 arrays as one tuple 5.8 us, the two
arenas and the spec 0.47 us), and ``bind`` rebuilds the views inside compiled code (inlined, without reference counting:
numerics/jit.py ``jit_inline``).

``SLOTS`` starts with the arguments of ``stepper.dg_advance`` after (nsteps, t0, dt), in order, so
the compiled tick calls ``dg_advance(nsteps, t0, dt, *bind(F, I, spec))``; the slots after
``N_STEP_SLOTS`` are the driver's own (full parameters, driven-end state and targets).
"""

import numpy as np

from tether_sim.numerics.jit import jit_inline

# (name, arena, rank). The first N_STEP_SLOTS are stepper.dg_advance's arguments, in its order.
SLOTS = (
    ("U", "f", 3), ("ra", "f", 1), ("prm_step", "f", 1), ("iprm_step", "i", 1), ("h", "f", 1),
    ("V", "f", 2), ("Pj", "f", 2), ("D", "f", 2), ("Lf", "f", 2), ("Tr", "f", 2), ("Iq", "f", 2),
    ("tab_eps", "f", 1), ("tab_T", "f", 1), ("cz", "f", 1), ("cx", "f", 1), ("cy", "f", 1),
    ("bc", "f", 2), ("vbc", "f", 2), ("wq", "f", 3), ("wm", "f", 3), ("tr", "f", 3), ("fl", "f", 2),
    ("rs", "f", 2), ("tmp", "f", 1), ("dU", "f", 3), ("dra", "f", 1), ("endf", "f", 2),
    ("bs", "f", 2), ("bp", "f", 2), ("dbs", "f", 2), ("bs0", "f", 2), ("U0", "f", 3), ("ra0", "f", 1),
    ("buf", "f", 2), ("cnt", "i", 1), ("out", "f", 1),
    ("idp", "i", 1), ("dprm", "f", 1), ("blk", "f", 5), ("bvec", "f", 2), ("wp", "f", 3), ("wd", "f", 3),
    ("band", "f", 2), ("vec", "f", 2), ("dtmp", "f", 5), ("fdamp", "f", 2),
    ("hw", "f", 1),
    # the driver's slots
    ("prm", "f", 1), ("iprm", "i", 1), ("ends", "f", 2), ("target", "f", 2), ("no_fdamp", "f", 2),
    ("drained", "i", 1), ("drain", "f", 2),
    # the output evaluation's inputs, kept for its reuse as the next tick's first stage (tick.py)
    ("fresh", "i", 1), ("snap", "f", 1), ("snap_i", "i", 1),
)
N_STEP_SLOTS = 47
SLOT = {name: k for k, (name, _, _) in enumerate(SLOTS)}
# slot indices of the driver's slots (compile-time constants)
X_PRM, X_IPRM, X_ENDS, X_TARGET, X_NO_FDAMP, X_DRAINED, X_DRAIN = (
    SLOT[n] for n in ("prm", "iprm", "ends", "target", "no_fdamp", "drained", "drain"))
X_FRESH, X_SNAP, X_SNAP_I = (SLOT[n] for n in ("fresh", "snap", "snap_i"))
_ALIGN = 8  # every view starts on a 64-byte boundary of its arena


class Workspace:
    """Owns the arenas; ``ws.<name>`` is the view of a slot (module docstring)."""

    def __init__(self, arrays):
        """arrays: {slot name: initial array} for every slot of SLOTS (copied into the arenas)."""
        missing = [n for n, _, _ in SLOTS if n not in arrays]
        if missing:
            raise ValueError(f"Workspace: no array for the slots {missing}")
        self.spec = np.zeros((len(SLOTS), 7), dtype=np.int64)
        size = {"f": 0, "i": 0}
        for k, (name, arena, rank) in enumerate(SLOTS):
            a = np.asarray(arrays[name])
            if a.ndim != rank:
                raise ValueError(f"Workspace: slot {name} needs rank {rank}, got shape {a.shape}")
            self.spec[k, 0] = size[arena]
            self.spec[k, 1] = rank
            self.spec[k, 2:2 + rank] = a.shape
            size[arena] += -(-a.size // _ALIGN) * _ALIGN
        self.F = np.zeros(max(size["f"], 1))
        self.I = np.zeros(max(size["i"], 1), dtype=np.int64)
        for k, (name, arena, rank) in enumerate(SLOTS):
            base = self.F if arena == "f" else self.I
            shape = tuple(int(d) for d in self.spec[k, 2:2 + rank])
            o = int(self.spec[k, 0])
            view = base[o:o + int(np.prod(shape))].reshape(shape)
            view[...] = arrays[name]
            setattr(self, name, view)


# ------------------------------------------------------------------------------ compiled views
@jit_inline
def _f1(F, S, k):
    o = S[k, 0]
    return F[o:o + S[k, 2]]


@jit_inline
def _f2(F, S, k):
    o = S[k, 0]
    return F[o:o + S[k, 2] * S[k, 3]].reshape((S[k, 2], S[k, 3]))


@jit_inline
def _f3(F, S, k):
    o = S[k, 0]
    return F[o:o + S[k, 2] * S[k, 3] * S[k, 4]].reshape((S[k, 2], S[k, 3], S[k, 4]))


@jit_inline
def _f5(F, S, k):
    o = S[k, 0]
    n = S[k, 2] * S[k, 3] * S[k, 4] * S[k, 5] * S[k, 6]
    return F[o:o + n].reshape((S[k, 2], S[k, 3], S[k, 4], S[k, 5], S[k, 6]))


@jit_inline
def bind(F, I, S):
    """The views of the first N_STEP_SLOTS slots (dg_advance's arguments), in SLOTS order."""
    return (_f3(F, S, 0), _f1(F, S, 1), _f1(F, S, 2), _f1(I, S, 3), _f1(F, S, 4),
            _f2(F, S, 5), _f2(F, S, 6), _f2(F, S, 7), _f2(F, S, 8), _f2(F, S, 9), _f2(F, S, 10),
            _f1(F, S, 11), _f1(F, S, 12), _f1(F, S, 13), _f1(F, S, 14), _f1(F, S, 15),
            _f2(F, S, 16), _f2(F, S, 17), _f3(F, S, 18), _f3(F, S, 19), _f3(F, S, 20), _f2(F, S, 21),
            _f2(F, S, 22), _f1(F, S, 23), _f3(F, S, 24), _f1(F, S, 25), _f2(F, S, 26),
            _f2(F, S, 27), _f2(F, S, 28), _f2(F, S, 29), _f2(F, S, 30), _f3(F, S, 31), _f1(F, S, 32),
            _f2(F, S, 33), _f1(I, S, 34), _f1(F, S, 35),
            _f1(I, S, 36), _f1(F, S, 37), _f5(F, S, 38), _f2(F, S, 39), _f3(F, S, 40), _f3(F, S, 41),
            _f2(F, S, 42), _f2(F, S, 43), _f5(F, S, 44), _f2(F, S, 45),
            _f1(F, S, 46))


@jit_inline
def bind_driver(F, I, S):
    """The views of the driver's slots: prm, iprm, ends, target, no_fdamp, drained, drain."""
    return (_f1(F, S, X_PRM), _f1(I, S, X_IPRM), _f2(F, S, X_ENDS), _f2(F, S, X_TARGET),
            _f2(F, S, X_NO_FDAMP), _f1(I, S, X_DRAINED), _f2(F, S, X_DRAIN))
