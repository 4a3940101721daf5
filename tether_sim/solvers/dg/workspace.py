"""The DG solver's arrays in two arenas, and the one compiled call per tick.

Every array the compiled code reads or writes (state, work arrays, operators, parameters, end
data, bodies, the end-tension ring, the implicit-damping arrays) is a view into one float64 arena
``F`` or one int64 arena ``I``, described by the slot table ``SLOTS`` (name, arena, rank, meaning)
and the int array ``spec`` (offset and shape of each slot). A compiled call then takes three arrays
instead of ~50: an njit call pays ~0.1-0.3 us per array argument to unbox it (measured
2026-11-23: 49 array arguments 4.4 us a call, the same 49 arrays as one tuple 5.8 us, the two
arenas and the spec 0.47 us).

``SLOTS`` is the only list of the slots. Each slot's index is a module constant ``X_<NAME>``
(generated below, as ``columns.define`` does for the columns; numba reads them as compile-time
constants), and ``bind(F, I, S)`` -- generated from ``SLOTS`` as well -- returns the views of all
slots as one tuple ``A`` in ``SLOTS`` order, inside compiled code (inlined, without reference counting:
numerics/jit.py ``jit_inline``). The kernels that take the workspace take ``A`` and read a slot by
its name: ``A[X_U]`` (a constant index into a tuple: resolved at compile time, no cost).

A view is made by ``_view_ir``, which writes the array structure from the arena's data pointer and the
spec directly: numba's slice-and-reshape calls a C helper per view that the compiler can neither
inline nor drop when the view is unused (binding all slots cost ~0.7 us a tick that way; the kernel of
a node tick with no substep went 3.3 -> 2.0 us at the 1730 m live mesh, BENCHMARKS.md "Fixed per-tick
work"). It checks nothing: the spec is Workspace's, which lays every slot inside its arena.
"""

import numpy as np
from numba import types
from numba.core import cgutils
from numba.core.imputils import impl_ret_borrowed
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array

from tether_sim.numerics.jit import jit_inline

# (name, arena, rank, meaning)
SLOTS = (
    # state and the stepper's parameters (implicit damping: zeta = zeta_b = 0 in these)
    ("U", "f", 3, "modal state [q, v] (N, P + 1, 6)"),
    ("ra", "f", 1, "anchor position r_a (3)"),
    ("prm_step", "f", 1, "float parameters the stages see (layout.py P_*)"),
    ("iprm_step", "i", 1, "int parameters the stages see (layout.py I_*)"),
    ("h", "f", 1, "element sizes (N)"),
    # element operators (numerics/operators.py)
    ("V", "f", 2, "Vandermonde: modes -> Gauss points"),
    ("Pj", "f", 2, "projection: Gauss points -> modes"),
    ("D", "f", 2, "modal derivative"),
    ("Lf", "f", 2, "lift of the traces"),
    ("Tr", "f", 2, "trace operator: modes -> element ends"),
    ("Iq", "f", 2, "integral of the modes at the Gauss points"),
    ("tab_eps", "f", 1, "strain column of a tabulated law"),
    ("tab_T", "f", 1, "tension column of a tabulated law"),
    ("cz", "f", 1, "current profile: depths"),
    ("cx", "f", 1, "current profile: x velocities"),
    ("cy", "f", 1, "current profile: y velocities"),
    # ends
    ("bc", "f", 2, "end data (2, layout.py B_*)"),
    ("vbc", "f", 2, "end kinematics at the stage time (2, 6)"),
    # work arrays of the right-hand side (layout.py W_*, M_*, T_*, F_*)
    ("wq", "f", 3, "Gauss-point work (N, Q, W_*)"),
    ("wm", "f", 3, "modal work (N, P + 1, M_*)"),
    ("trc", "f", 3, "trace work (N, 2, T_*)"),
    ("fl", "f", 2, "interface fluxes (N + 1, F_*)"),
    ("rs", "f", 2, "element start positions (N, 3)"),
    ("tmp", "f", 1, "scratch (soa.py)"),
    ("dU", "f", 3, "du/dt"),
    ("dra", "f", 1, "anchor velocity"),
    ("endf", "f", 2, "end loads (2, layout.py E_*)"),
    # bodies and the Runge-Kutta copies
    ("bs", "f", 2, "body states (2, 13)"),
    ("bp", "f", 2, "body parameters"),
    ("dbs", "f", 2, "body state rates"),
    ("bs0", "f", 2, "body states at the substep start"),
    ("U0", "f", 3, "state at the substep start"),
    ("ra0", "f", 1, "anchor at the substep start"),
    # end-tension ring and the stepper's result
    ("buf", "f", 2, "ring of (t, T_ship, T_vehicle) per substep"),
    ("cnt", "i", 1, "ring entries ever written"),
    ("out", "f", 1, "substeps done, status"),
    # implicit damping (implicit_damping.DampingWork)
    ("idp", "i", 1, "damping ints (mode first)"),
    ("dprm", "f", 1, "damping parameters"),
    ("blk", "f", 5, "block-tridiagonal blocks"),
    ("bvec", "f", 2, "block right-hand side"),
    ("wp", "f", 3, "damping point work"),
    ("wd", "f", 3, "damping modal work"),
    ("band", "f", 2, "banded matrix"),
    ("vec", "f", 2, "banded right-hand side"),
    ("dtmp", "f", 5, "damping scratch"),
    ("dwood", "f", 2, "low-rank update of the damping LU (damping_update.py)"),
    ("fdamp", "f", 2, "damping end forces and tensions (2, 4)"),
    ("hw", "f", 1, "element sizes / length (winch.py)"),
    # the driver's slots: full parameters, driven-end state and targets
    ("prm", "f", 1, "full float parameters (outputs)"),
    ("iprm", "i", 1, "full int parameters (outputs)"),
    ("ends", "f", 2, "driven ends' state at the solver time (2, tick.EN_*)"),
    ("target", "f", 2, "driven ends' targets (2, tick.TG_*)"),
    ("no_fdamp", "f", 2, "zero damping end forces (full evaluations)"),
    ("drained", "i", 1, "ring entries drained"),
    ("drain", "f", 2, "drained ring entries (3, cap)"),
    # the output evaluation's inputs, kept for its reuse as the next tick's first stage (tick.py)
    ("fresh", "i", 1, "kept evaluation valid, reuse count"),
    ("snap", "f", 1, "kept inputs (U, prm, bc, vbc, h)"),
    ("snap_i", "i", 1, "kept int parameters"),
    # bending multirate records carried from one stepper call to the next (stepper.py)
    ("bmr", "f", 1, "record count, record times, substeps since the last record, end time, end state"),
)


def _define(namespace):
    """X_<NAME> = index of every slot (names unique also in upper case)."""
    for k, (name, arena, rank, _) in enumerate(SLOTS):
        const = "X_" + name.upper()
        if const in namespace:
            raise ValueError(f"slot {name}: {const} is defined twice")
        if arena not in ("f", "i") or rank not in (1, 2, 3, 5):
            raise ValueError(f"slot {name}: arena {arena!r}, rank {rank} not supported")
        namespace[const] = k


_define(globals())
N_SLOTS = len(SLOTS)
_ALIGN = 8  # every view starts on a 64-byte boundary of its arena


class Workspace:
    """Owns the arenas; ``ws.<name>`` is the view of a slot (module docstring)."""

    def __init__(self, arrays):
        """arrays: {slot name: initial array} for every slot of SLOTS (copied into the arenas)."""
        missing = [n for n, _, _, _ in SLOTS if n not in arrays]
        if missing:
            raise ValueError(f"Workspace: no array for the slots {missing}")
        self.spec = np.zeros((len(SLOTS), 7), dtype=np.int64)
        size = {"f": 0, "i": 0}
        for k, (name, arena, rank, _) in enumerate(SLOTS):
            a = np.asarray(arrays[name])
            if a.ndim != rank:
                raise ValueError(f"Workspace: slot {name} needs rank {rank}, got shape {a.shape}")
            self.spec[k, 0] = size[arena]
            self.spec[k, 1] = rank
            self.spec[k, 2:2 + rank] = a.shape
            size[arena] += -(-a.size // _ALIGN) * _ALIGN
        self.F = np.zeros(max(size["f"], 1))
        self.I = np.zeros(max(size["i"], 1), dtype=np.int64)
        for k, (name, arena, rank, _) in enumerate(SLOTS):
            base = self.F if arena == "f" else self.I
            shape = tuple(int(d) for d in self.spec[k, 2:2 + rank])
            o = int(self.spec[k, 0])
            view = base[o:o + int(np.prod(shape))].reshape(shape)
            view[...] = arrays[name]
            setattr(self, name, view)


# ------------------------------------------------------------------------------ compiled views
def _view(arena, o, shape):
    """arena[o:o + prod(shape)] as a C-contiguous array of that shape (a view, no copy); in compiled
    code _view_ir."""
    n = 1
    for d in shape:
        n *= d
    return arena[o:o + n].reshape(shape)


@intrinsic
def _view_ir(typingctx, arena, o, shape):
    """_view in compiled code without its checks: the view's array structure made directly from the
    arena's data pointer (no slice bounds, no size check, no call out of the function: numba's reshape
    calls a C helper per view, ~12 ns, and cannot be dropped when the view is unused). The spec comes
    from Workspace, which lays every slot inside its arena."""
    if not (isinstance(arena, types.Array) and arena.ndim == 1 and arena.layout == "C"
            and isinstance(o, types.Integer) and isinstance(shape, types.UniTuple)
            and isinstance(shape.dtype, types.Integer)):
        return None
    retty = types.Array(arena.dtype, len(shape), "C")

    def codegen(context, builder, sig, args):
        ary = make_array(sig.args[0])(context, builder, args[0])
        dims = [context.cast(builder, d, sig.args[2].dtype, types.intp) for d in cgutils.unpack_tuple(builder, args[2])]
        itemsize = context.get_constant(types.intp, context.get_abi_sizeof(context.get_data_type(arena.dtype)))
        strides = [itemsize]
        for d in dims[:0:-1]:
            strides.insert(0, builder.mul(strides[0], d))
        offset = context.cast(builder, args[1], sig.args[1], types.intp)
        out = make_array(retty)(context, builder)
        populate_array(out, data=builder.gep(ary.data, [offset]), shape=dims, strides=strides, itemsize=itemsize,
                       meminfo=ary.meminfo, parent=ary.parent)
        return impl_ret_borrowed(context, builder, retty, out._getvalue())

    return retty(arena, o, shape), codegen


class _ViewIntrinsic(type(_view_ir)):
    """The intrinsic, callable from Python as _view (plain-Python callers of the binding: tests, py_func)."""

    def __call__(self, arena, o, shape):
        return _view(arena, o, shape)


_view_ir.__class__ = _ViewIntrinsic


@jit_inline
def _f1(F, S, k):
    return _view_ir(F, S[k, 0], (S[k, 2],))


@jit_inline
def _f2(F, S, k):
    return _view_ir(F, S[k, 0], (S[k, 2], S[k, 3]))


@jit_inline
def _f3(F, S, k):
    return _view_ir(F, S[k, 0], (S[k, 2], S[k, 3], S[k, 4]))


@jit_inline
def _f5(F, S, k):
    return _view_ir(F, S[k, 0], (S[k, 2], S[k, 3], S[k, 4], S[k, 5], S[k, 6]))


@jit_inline
def flat(F, S, k):
    """The slot k of the float arena as one flat array (its elements in C order)."""
    n = 1
    for d in range(S[k, 1]):
        n *= S[k, 2 + d]
    return _view_ir(F, S[k, 0], (n,))


def _bind_source(slots=SLOTS):
    """Source of bind: the views of every slot, in the order of slots (each by its rank and arena)."""
    views = ", ".join(f"_f{rank}({'F' if arena == 'f' else 'I'}, S, {k})" for k, (_, arena, rank, _) in enumerate(slots))
    return f"def bind(F, I, S):\n    return ({views},)\n"


_ns = {"_f1": _f1, "_f2": _f2, "_f3": _f3, "_f5": _f5}
exec(compile(_bind_source(), __file__, "exec"), _ns)  # this file's name: numba caches its callers
bind = jit_inline(_ns["bind"])
bind.__doc__ = "The views of all slots as one tuple A, in SLOTS order (A[X_<NAME>] is a slot's view)."


def views(ws):
    """The same tuple in Python (ws.<name> in SLOTS order): what bind returns, for calls from Python."""
    return tuple(getattr(ws, name) for name, _, _, _ in SLOTS)
