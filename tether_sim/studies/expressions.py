"""Arithmetic expressions of study variables (``"= 1 / f"``), evaluated on a whitelisted syntax tree.

Allowed: numbers, strings, names of study variables, ``+ - * / // % **``, unary ``+ -``, lists and
tuples, comparisons and ``a if c else b``, and calls of the functions in :data:`FUNCTIONS`. No
attribute access, subscripts or other names: a study file cannot run code.

Work and memory are bounded: an expression has at most :data:`MAX_CHARS` characters, :data:`MAX_NODES`
syntax nodes nested at most :data:`MAX_DEPTH` deep; an integer result has at most :data:`MAX_INT_BITS`
bits (``10**10**10`` is refused before it is computed); a string or list at most :data:`MAX_ITEMS`
items (``[0]*10**10``, ``linspace(0, 1, 1e9)`` are refused); ``%`` formats no strings.
"""

import ast
import functools
import math
import operator

import numpy as np


MAX_CHARS = 2000
MAX_NODES = 500
MAX_DEPTH = 40
MAX_INT_BITS = 4096  # about 1233 decimal digits
MAX_ITEMS = 100_000


class ExpressionError(ValueError):
    """An expression uses syntax or names it may not, or fails to evaluate."""


def _count(n, what):
    """``n`` as the item count of a sequence, refused above :data:`MAX_ITEMS`."""
    try:
        count = int(n)
    except (TypeError, ValueError, OverflowError):
        raise ExpressionError(f"{what}: expected a count, got {n!r}") from None
    if count > MAX_ITEMS:
        raise ExpressionError(f"{what}: {count} items is above the limit of {MAX_ITEMS}")
    return count


def phases(seed, n):
    """``n`` random phases in [0, 2 pi) drawn from ``numpy.random.default_rng(seed)`` (a sea-state
    realisation of a sum of sines: one seed, one set of phases, on every machine)."""
    rng = np.random.default_rng(int(seed))
    return [float(x) for x in rng.uniform(0.0, 2.0 * math.pi, _count(n, "phases"))]


def linspace(a, b, n):
    return [float(x) for x in np.linspace(float(a), float(b), _count(n, "linspace"))]


FUNCTIONS = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "log10": math.log10,
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "atan2": math.atan2,
    "abs": abs, "min": min, "max": max, "round": round, "int": int, "float": float,
    "phases": phases, "linspace": linspace,
}
CONSTANTS = {"pi": math.pi, "g": 9.81}

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg, ast.Not: operator.not_}
_COMPARE = {ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
            ast.Gt: operator.gt, ast.GtE: operator.ge}


def _power(a, b):
    """``a ** b``, refused when an integer result would exceed :data:`MAX_INT_BITS` bits."""
    if isinstance(a, int) and isinstance(b, int) and b > 1 and abs(a) > 1:
        bits = (abs(a).bit_length() - 1) * b
        if bits > MAX_INT_BITS:
            raise ExpressionError(f"{a!r} ** {b!r}: the result would have about {bits} bits, above the limit of "
                                  f"{MAX_INT_BITS}")
    return operator.pow(a, b)


def _times(a, b):
    """``a * b``, refused when it would repeat a string or list to more than :data:`MAX_ITEMS` items."""
    for seq, n in ((a, b), (b, a)):
        if isinstance(seq, (str, list)) and isinstance(n, int):
            if len(seq) * max(n, 0) > MAX_ITEMS:
                raise ExpressionError(f"a sequence of {len(seq)} repeated {n} times is above the limit of "
                                      f"{MAX_ITEMS} items")
    return operator.mul(a, b)


def _modulo(a, b):
    if isinstance(a, str):
        raise ExpressionError("'%' string formatting is not allowed in a study expression")
    return operator.mod(a, b)


_BINARY.update({ast.Pow: _power, ast.Mult: _times, ast.Mod: _modulo})


def _bounded(value):
    """A value within the limits (integers of at most MAX_INT_BITS bits, sequences of MAX_ITEMS)."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > MAX_INT_BITS:
        raise ExpressionError(f"an integer of {value.bit_length()} bits is above the limit of {MAX_INT_BITS}")
    if isinstance(value, (str, list)) and len(value) > MAX_ITEMS:
        raise ExpressionError(f"a sequence of {len(value)} items is above the limit of {MAX_ITEMS}")
    return value


def names_in(text: str) -> set:
    """Variable names an expression reads (functions and constants excluded)."""
    tree = _parse(text)
    called = {id(n.func) for n in ast.walk(tree) if isinstance(n, ast.Call)}
    return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and id(n) not in called} - set(CONSTANTS)


def evaluate(text: str, variables: dict):
    """Value of expression ``text`` with ``variables`` (name -> value)."""
    try:
        return _eval(_parse(text).body, variables)
    except ExpressionError:
        raise
    except (ArithmeticError, TypeError, ValueError, MemoryError, RecursionError) as exc:
        raise ExpressionError(f"expression {_short(text)}: {type(exc).__name__}: {exc}") from None


def _short(text, n=60):
    text = " ".join(str(text).split())
    return repr(text if len(text) <= n else text[:n] + "...")


@functools.lru_cache(maxsize=256)  # the same expression is evaluated for every case of a study
def _parse(text):
    if not isinstance(text, str):
        raise ExpressionError(f"expected an expression (text), got {type(text).__name__}")
    if len(text) > MAX_CHARS:
        raise ExpressionError(f"expression {_short(text)} has {len(text)} characters, above the limit of {MAX_CHARS}")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"expression {_short(text)}: {exc.msg}") from None
    except (RecursionError, MemoryError, ValueError) as exc:  # too deeply nested for the parser; NUL bytes
        raise ExpressionError(f"expression {_short(text)}: cannot be parsed ({type(exc).__name__})") from None
    nodes, depth, stack = 0, 0, [(tree.body, 1)]
    while stack:
        node, d = stack.pop()
        nodes, depth = nodes + 1, max(depth, d)
        if nodes > MAX_NODES:
            raise ExpressionError(f"expression {_short(text)} has more than {MAX_NODES} terms (the limit)")
        if depth > MAX_DEPTH:
            raise ExpressionError(f"expression {_short(text)} is nested more than {MAX_DEPTH} deep (the limit)")
        stack.extend((child, d + 1) for child in ast.iter_child_nodes(node))
    return tree


def _eval(node, env):
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float, str, bool)):
        return node.value
    if isinstance(node, ast.Name):
        if node.id in env:
            return env[node.id]
        if node.id in CONSTANTS:
            return CONSTANTS[node.id]
        raise ExpressionError(f"unknown name {node.id!r} (variables: {', '.join(sorted(env)) or 'none'})")
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        return _bounded(_BINARY[type(node.op)](_eval(node.left, env), _eval(node.right, env)))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_eval(node.operand, env))
    if isinstance(node, (ast.List, ast.Tuple)):
        return [_eval(e, env) for e in node.elts]
    if isinstance(node, ast.IfExp):
        return _eval(node.body, env) if _eval(node.test, env) else _eval(node.orelse, env)
    if isinstance(node, ast.Compare) and len(node.ops) == 1 and type(node.ops[0]) in _COMPARE:
        return _COMPARE[type(node.ops[0])](_eval(node.left, env), _eval(node.comparators[0], env))
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS
            and not node.keywords):
        return _bounded(FUNCTIONS[node.func.id](*(_eval(a, env) for a in node.args)))
    raise ExpressionError(f"not allowed in a study expression: {_short(ast.unparse(node))}")
