"""Column tables: each column of a solver array named once, with its width, symbol, unit and meaning
(DG: dg/layout.py, dg/damping_layout.py; hybrid: hybrid/layout.py).

``define(namespace, array, rows, size_name)`` gives every row's name its offset (the running sum
of the widths before it) as a module constant in ``namespace`` (numba reads module-level ints as
compile-time constants), and the total width as ``size_name``. Adding a column is adding a row;
the offsets of the ones after it follow. ``TABLES`` keeps every table for the documentation
(``describe()`` prints them; docs/dg_solver.md "State and work columns", docs/hybrid_solver.md
"State and parameter columns").
"""

from dataclasses import dataclass


@dataclass(frozen=True)
class Column:
    name: str
    offset: int
    width: int
    symbol: str
    unit: str
    meaning: str


TABLES = {}


def define(namespace, array, rows, size_name):
    """rows: (name, width, symbol, unit, meaning); returns the Columns of ``array``."""
    cols, offset = [], 0
    for name, width, symbol, unit, meaning in rows:
        if name in namespace:
            raise ValueError(f"column {name} of {array} is named twice")
        namespace[name] = offset
        cols.append(Column(name, offset, width, symbol, unit, meaning))
        offset += width
    namespace[size_name] = offset
    TABLES[array] = tuple(cols)
    return TABLES[array]


def describe(arrays=None):
    """Markdown tables of the columns (all arrays, or the named ones)."""
    out = []
    for array, cols in TABLES.items():
        if arrays is not None and array not in arrays:
            continue
        out += [f"`{array}`", "", "| column | offset | width | symbol | unit | meaning |", "|---|---|---|---|---|---|"]
        out += [f"| {c.name} | {c.offset} | {c.width} | {c.symbol} | {c.unit} | {c.meaning} |" for c in cols]
        out.append("")
    return "\n".join(out)
