"""Arithmetic expressions of study variables (``"= 1 / f"``), evaluated on a whitelisted syntax tree.

Allowed: numbers, strings, names of study variables, ``+ - * / // % **``, unary ``+ -``, lists and
tuples, comparisons and ``a if c else b``, and calls of the functions in :data:`FUNCTIONS`. No
attribute access, subscripts or other names: a study file cannot run code.
"""

import ast
import math
import operator

import numpy as np


def phases(seed, n):
    """``n`` random phases in [0, 2 pi) drawn from ``numpy.random.default_rng(seed)`` (a sea-state
    realisation of a sum of sines: one seed, one set of phases, on every machine)."""
    rng = np.random.default_rng(int(seed))
    return [float(x) for x in rng.uniform(0.0, 2.0 * math.pi, int(n))]


def linspace(a, b, n):
    return [float(x) for x in np.linspace(float(a), float(b), int(n))]


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


class ExpressionError(ValueError):
    """An expression uses syntax or names it may not, or fails to evaluate."""


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
    except (ArithmeticError, TypeError, ValueError) as exc:
        raise ExpressionError(f"expression {text!r}: {type(exc).__name__}: {exc}") from None


def _parse(text):
    try:
        return ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"expression {text!r}: {exc.msg}") from None


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
        return _BINARY[type(node.op)](_eval(node.left, env), _eval(node.right, env))
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
        return FUNCTIONS[node.func.id](*(_eval(a, env) for a in node.args))
    raise ExpressionError(f"not allowed in a study expression: {ast.unparse(node)!r}")
