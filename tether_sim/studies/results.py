"""The results of a study: a crash-safe journal, turned into Parquet and CSV tables (pyarrow).

Folder layout (``RESULTS/``):

``cases.jsonl``      one JSON line per finished case, appended (and fsync'ed) as each one finishes:
                     the journal, so a study killed half-way loses no finished case
``results.parquet``  one row per case (the last journal line of each key), ordered by case index
``results.csv``      the same table as CSV (list values as JSON text)
``events.jsonl``, ``events.parquet``  every snap event of every case (``keep: events``)
``mcap/``            per-case MCAP files (``keep: mcap``)

A case's key is in the results once it has a row; ``status`` is ``ok`` or ``failed`` (with ``error``).
"""

import json
import math
import os
from pathlib import Path

import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

TABLE = "results.parquet"


class ResultStore:
    """Append finished cases; read back what is done; write the tables."""

    def __init__(self, out_dir, units=None):
        self.dir = Path(out_dir)
        self.units = dict(units or {})  # column -> unit of the study's own variables (Study.column_units)
        self.journal = self.dir / "cases.jsonl"
        self.events_journal = self.dir / "events.jsonl"

    def load(self) -> dict:
        """key -> row of every case already in the results (journal, else the Parquet table)."""
        rows = {}
        if self.journal.is_file():
            for line in self.journal.read_text().splitlines():
                line = line.strip()
                if not line:
                    continue
                try:
                    row = json.loads(line)
                except json.JSONDecodeError:
                    continue  # a line cut by a kill: that case runs again
                rows[row["key"]] = row
        elif (self.dir / TABLE).is_file():
            rows = {r["key"]: r for r in pq.read_table(self.dir / TABLE).to_pylist()}
        return rows

    def append(self, result: dict) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)
        _append_lines(self.journal, [result["row"]])
        if result.get("events"):
            run = f"{result['row'].get('worker', '')}/{result['row'].get('finished_utc', '')}"
            _append_lines(self.events_journal, [{**e, "run": run} for e in result["events"]])

    def write_tables(self) -> Path:
        """results.parquet / results.csv (and events.parquet) from the journal; returns the Parquet path."""
        self.dir.mkdir(parents=True, exist_ok=True)
        rows = sorted(self.load().values(), key=lambda r: (r.get("index", 0), r["key"]))
        table = to_table(rows, self.units)
        _atomic(self.dir / TABLE, lambda p: pq.write_table(table, p))
        _atomic(self.dir / "results.csv", lambda p: pacsv.write_csv(_csv_ready(table), p))
        if self.events_journal.is_file():
            keys = {r["key"] for r in rows}
            events = [json.loads(x) for x in self.events_journal.read_text().splitlines() if x.strip()]
            events = _last_run_events(events, keys)
            _atomic(self.dir / "events.parquet", lambda p: pq.write_table(to_table(events, self.units), p))
        return self.dir / TABLE


def _last_run_events(events, keys):
    """Events of each key's last run only (a retried case appended a second set)."""
    last = {}
    for e in events:
        if e["key"] in keys:
            last.setdefault(e["key"], {}).setdefault(e.get("run", ""), []).append(e)
    out = []
    for key, runs in last.items():
        out.extend(runs[list(runs)[-1]])
    return out


def _append_lines(path, rows):
    text = "".join(json.dumps(r, allow_nan=True) + "\n" for r in rows)
    with open(path, "a", encoding="utf-8") as fh:
        fh.write(text)
        fh.flush()
        os.fsync(fh.fileno())


def _atomic(path, write):
    tmp = path.with_name(path.name + ".tmp")
    write(str(tmp))
    os.replace(tmp, path)


# unit of a column by the end of its name (the columns name their unit: docs/studies.md)
UNIT_SUFFIXES = (("_Nm2", "N m^2"), ("_Hz", "Hz"), ("_N", "N"), ("_m", "m"), ("_s", "s"))
DIMENSIONLESS = {"daf", "rtf", "dg_cfl"}  # ratios: unit "1"


def column_unit(name: str, units=None):
    """The unit of a result column ("1" for a ratio), or None (identity, counts, text, a study
    variable without one). A study variable (``var.<name>``) that names a parameter has that
    parameter's unit; the study's own variables have the unit ``units`` (column -> unit, from
    Study.column_units) gives them."""
    if name.startswith("var."):
        from tether_sim.studies.spec import study_keys

        key = study_keys().get(name[4:])
        return (key.unit or None) if key is not None else (units or {}).get(name)
    if name in DIMENSIONLESS or name.endswith("_daf"):
        return "1"
    for suffix, unit in UNIT_SUFFIXES:
        if name.endswith(suffix):
            return unit
    return None


def to_table(rows: list, units=None) -> pa.Table:
    """Rows (dicts, maybe with different columns) -> a table with the union of the columns; each
    column with a unit carries it as Parquet field metadata ``unit`` (:func:`column_unit`; ``units``:
    those of the study's own variables)."""
    columns = []
    for r in rows:
        columns.extend(k for k in r if k not in columns)
    data = {c: [r.get(c) for r in rows] for c in columns}
    arrays = {}
    for c, values in data.items():
        try:
            arrays[c] = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed kinds (e.g. number and text): keep as text
            arrays[c] = pa.array([None if v is None else json.dumps(v) if not isinstance(v, str) else v
                                  for v in values])
    if not arrays:
        return pa.table({})
    fields = []
    for c, a in arrays.items():
        unit = column_unit(c, units)
        fields.append(pa.field(c, a.type, metadata={"unit": unit} if unit else None))
    return pa.Table.from_arrays(list(arrays.values()), schema=pa.schema(fields))


def _csv_ready(table):
    cols = {}
    for name in table.column_names:
        col = table[name]
        if pa.types.is_list(col.type) or pa.types.is_struct(col.type):
            col = pa.array([None if v is None else json.dumps(v) for v in col.to_pylist()], pa.string())
        cols[name] = col
    return pa.table(cols)


def read_units(path) -> dict:
    """column -> unit of a results folder or Parquet file (the field metadata ``unit``)."""
    path = Path(path)
    if path.is_dir():
        path = path / TABLE
    return {f.name: f.metadata[b"unit"].decode() for f in pq.read_schema(path) if f.metadata and b"unit" in f.metadata}


def read_results(path) -> list:
    """Rows of a results folder or Parquet file."""
    path = Path(path)
    if path.is_dir():
        path = path / TABLE
    return pq.read_table(path).to_pylist()


def same_physics(rows_a, rows_b, ignore) -> list:
    """Differences between two result tables (by key), ignoring the columns ``ignore``; [] if equal."""
    a = {r["key"]: r for r in rows_a}
    b = {r["key"]: r for r in rows_b}
    diffs = []
    if set(a) != set(b):
        diffs.append(f"keys differ: {sorted(set(a) ^ set(b))}")
    for key in sorted(set(a) & set(b)):
        for col in sorted((set(a[key]) | set(b[key])) - set(ignore)):
            x, y = a[key].get(col), b[key].get(col)
            both_nan = isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y)
            if x != y and not both_nan:
                diffs.append(f"{key} {col}: {x!r} != {y!r}")
    return diffs
