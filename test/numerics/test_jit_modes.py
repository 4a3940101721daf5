"""The compile modes of numerics/jit.py: ``jit`` and ``jit_inline`` kernels run without numba's reference
counting, ``jit_alloc`` functions with it.

What that asks of an uncounted kernel (jit.py): it allocates nothing, returns no array, and calls no
``jit_alloc`` function (the counted functions sit above the uncounted ones, never below). numba
refuses an allocation at compile time; a returned array or a counted callee would instead unbalance
the counts silently (an array freed early or never), so these tests check the sources (the
compiled signatures cannot be checked from the on-disk cache: a cached entry point does not
compile its callees).
"""

import ast
import os
from pathlib import Path

import pytest

import tether_sim

PKG = Path(tether_sim.__file__).resolve().parent
ALLOCATING = {"empty", "zeros", "ones", "array", "empty_like", "zeros_like", "ones_like", "full", "full_like",
              "arange", "linspace", "copy", "concatenate", "dot", "outer", "sort", "argsort", "unique", "stack",
              "hstack", "vstack", "ascontiguousarray", "asarray", "cross", "cumsum", "diff", "interp"}
JIT_OFF = os.environ.get("NUMBA_DISABLE_JIT", "0") == "1"


def _decorated(path):
    """(function node, decorator names) of every top-level function of a module."""
    tree = ast.parse(path.read_text())
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            yield node, {ast.unparse(d) for d in node.decorator_list}


def _module(path):
    return ".".join(("tether_sim",) + path.relative_to(PKG).with_suffix("").parts)


def _kernels():
    """{(path, name): node} of the functions decorated @jit; {module: set of @jit_alloc names}."""
    plain, counted = {}, {}
    for path in sorted(PKG.rglob("*.py")):
        for node, decos in _decorated(path):
            if "jit" in decos or ("jit_inline" in decos and not path.name == "workspace.py"):
                plain[(path, node.name)] = node  # the arena binding (workspace.py) returns views by design
            if "jit_alloc" in decos:
                counted.setdefault(_module(path), set()).add(node.name)
    return plain, counted


def _counted_names(path, counted):
    """The names under which a module sees @jit_alloc functions (its own and those it imports)."""
    names = set(counted.get(_module(path), ()))
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.ImportFrom) and node.module in counted:
            names |= {a.asname or a.name for a in node.names if a.name in counted[node.module]}
    return names


def test_jit_kernels_allocate_nothing_and_call_no_counted_function():
    plain, counted = _kernels()
    assert len(plain) > 100, "the scan found the kernels"
    bad = []
    for (path, name), node in plain.items():
        seen_counted = _counted_names(path, counted)
        for n in ast.walk(node):
            what = None
            if isinstance(n, (ast.List, ast.ListComp, ast.Dict, ast.DictComp, ast.Set, ast.SetComp)):
                what = type(n).__name__
            elif isinstance(n, ast.Call):
                f = n.func
                if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id in ("np", "numpy") \
                        and f.attr in ALLOCATING:
                    what = f"np.{f.attr}"
                elif isinstance(f, ast.Attribute) and f.attr in ("copy", "astype"):
                    what = f".{f.attr}()"
                elif isinstance(f, ast.Name) and f.id in seen_counted:
                    what = f"calls jit_alloc {f.id}"
            if what:
                bad.append(f"{path.relative_to(PKG)}:{getattr(n, 'lineno', node.lineno)} {name}: {what}")
    assert not bad, "jit kernels (no reference counting) that allocate or call a counted function:\n" + "\n".join(bad)


def _array_names(node):
    """Names a function uses as arrays: subscripted with a slice or reshaped, or made so."""
    arrays = set()
    for n in ast.walk(node):
        if isinstance(n, ast.Subscript) and isinstance(n.value, ast.Name):
            arrays.add(n.value.id)
        if isinstance(n, ast.Assign) and _array_valued(n.value, arrays):
            arrays |= {t.id for t in n.targets if isinstance(t, ast.Name)}
    return arrays


def _array_valued(expr, arrays):
    """Whether expr may be an array: an array name, a slice of one, a reshape/ravel/.T of one."""
    if isinstance(expr, ast.Name):
        return expr.id in arrays
    if isinstance(expr, ast.Subscript):
        sl = expr.slice.elts if isinstance(expr.slice, ast.Tuple) else [expr.slice]
        return any(isinstance(x, ast.Slice) for x in sl) or isinstance(expr.slice, ast.Slice)
    if isinstance(expr, ast.Attribute) and expr.attr in ("T", "flat"):
        return True
    if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Attribute) and expr.func.attr in ("reshape", "ravel"):
        return True
    if isinstance(expr, ast.Tuple):
        return any(_array_valued(e, arrays) for e in expr.elts)
    return False


def test_jit_kernels_return_no_array():
    """A counted caller (jit_alloc) would release a reference to a returned array that the
    uncounted kernel never took."""
    plain, _ = _kernels()
    bad = []
    for (path, name), node in plain.items():
        arrays = _array_names(node)
        for n in ast.walk(node):
            if isinstance(n, ast.Return) and n.value is not None and _array_valued(n.value, arrays):
                bad.append(f"{path.relative_to(PKG)}:{n.lineno} {name}: return {ast.unparse(n.value)}")
    assert not bad, "jit kernels returning an array:\n" + "\n".join(bad)


def test_return_rule_catches_array_returns():
    """The rule above flags what it must (a parameter used as an array, its slice, a reshape)."""
    src = ("def f(a, t):\n    x = a[1:3]\n    return x\n"
           "def g(a, t):\n    a[0] = t\n    return a\n"
           "def h(a, t):\n    return a.reshape(4)\n"
           "def k(a, t):\n    a[0] = 1.0\n    return t, a[0]\n")
    flagged = {}
    for node in ast.parse(src).body:
        arrays = _array_names(node)
        flagged[node.name] = any(isinstance(n, ast.Return) and _array_valued(n.value, arrays) for n in ast.walk(node))
    assert flagged == {"f": True, "g": True, "h": True, "k": False}


@pytest.mark.skipif(JIT_OFF, reason="compile options only exist with the JIT on")
def test_dg_tick_runs_uncounted():
    """The whole DG tick is uncounted: the right-hand side, the stepper, the tick entries, and the
    arena binding, which is inlined into them (jit_inline) because an uncounted function may not
    return the views it makes."""
    from tether_sim.solvers.dg import kernels, stepper, tick, workspace
    for f in (kernels.dg_rhs, stepper.dg_advance, tick.dg_tick, tick.node_tick, tick.drain_now):
        assert f.targetoptions.get("_nrt") is False, f
    for f in (workspace.bind, workspace._f1, workspace._f3):
        assert f.targetoptions.get("_nrt") is False and f.targetoptions.get("inline") == "always", f
