"""Study files: a base parameter file, the parameters to vary, what to keep -> the list of cases.

A study file is YAML (documented with examples in docs/studies.md)::

    name: pe2020_sec62
    base: ../ropos_L{L:g}_paper.yaml  # parameter file, relative to this file; {var} fields per case
    vary:                             # one block, or a list of blocks crossed with each other
      grid: {L: [200, 500], f: [0.1, 0.2]}            # full factorial
      # zip: {a: [1, 2], f: [0.1, 0.2]}               # lists varied together
      # lhs: {n: 8, seed: 1, ranges: {a: [0.5, 3]}}   # Latin hypercube (or random:) samples
    seeds: [1, 2, 3]                  # replications: variable `seed` (e.g. phases(seed, 5))
    set:                              # every case: a value, or "= expression" of the variables
      motion.frequency: "= f"
      duration: "= 12 / f"
    units: {L: m, alpha: "1"}         # units of the study's own variables (f: Hz, from motion.frequency)
    keep: {mcap: false, events: true}

A variable whose name is a parameter key (``motion.amplitude``, ``duration``) sets that parameter;
other names are study variables, used in ``base`` and in ``set`` expressions, and kept as columns.
A study variable's unit is the one ``units`` gives it, or else that of the parameter it is set to
as it is (``motion.frequency: "= f"`` gives ``f`` Hz); the results table carries it (``var.f``).
"""

import itertools
import math
import string
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from tether_sim.errors import ConfigError
from tether_sim.io.schema import key_map
from tether_sim.studies.expressions import ExpressionError, evaluate, names_in

TOP_KEYS = ("name", "description", "base", "vary", "seeds", "set", "units", "keep")
BLOCK_KINDS = ("grid", "zip", "random", "lhs")
KEEP_DEFAULTS = {"mcap": False, "events": True}


MAX_CASES = 100_000  # cases in one study file (the product of its blocks), checked before they are expanded
MAX_FILE_BYTES = 1_000_000
EAGER_CASES = 1_000  # cases checked when the file is loaded (errors up front); the rest as they are run


class StudyError(ConfigError):
    """A study file is malformed; the message (one line) names the file and the entry."""


class _StudyKeys(dict):
    """The parameter keys a study may set: the schema's (``io.schema.key_map``) and a network
    file's (``network.lines.<line>.cable.length``, ``network.bodies.<body>.mass``: their kind and
    unit are those of the single-line key they stand for, :func:`tether_sim.network.params.network_key`)."""

    def _network(self, name):
        from tether_sim.network.params import network_key

        return network_key(name) if isinstance(name, str) and name.startswith("network.") else None

    def __contains__(self, name):
        return dict.__contains__(self, name) or self._network(name) is not None

    def __getitem__(self, name):
        if dict.__contains__(self, name):
            return dict.__getitem__(self, name)
        key = self._network(name)
        if key is None:
            raise KeyError(name)
        return key

    def get(self, name, default=None):
        return self[name] if name in self else default


def study_keys() -> dict:
    """Every key a study file may vary or set (:class:`_StudyKeys`)."""
    return _StudyKeys(key_map())


@dataclass(frozen=True)
class Case:
    """One case of a study: its variables (in declared order) and the parameters they give."""

    index: int
    variables: dict
    base: Path
    overrides: dict  # flat parameter key -> value, applied over the base file


@dataclass
class Study:
    name: str
    path: Path
    base: str
    blocks: list  # [(kind, {variable: values}), ...] already expanded to equal-length lists
    set: dict = field(default_factory=dict)
    keep: dict = field(default_factory=lambda: dict(KEEP_DEFAULTS))
    description: str = ""
    units: dict = field(default_factory=dict)  # study variable (not a parameter) -> unit ("1": a ratio)
    _cases: list = field(default=None, repr=False, compare=False)
    _paths: dict = field(default_factory=dict, repr=False, compare=False)  # base text -> resolved path

    @property
    def variables(self) -> list:
        return [name for _, block in self.blocks for name in block]

    def column_units(self) -> dict:
        """Units of the ``var.<name>`` result columns of the study's own variables."""
        return {f"var.{name}": unit for name, unit in self.units.items()}

    def n_cases(self) -> int:
        return math.prod(_length(block) for _, block in self.blocks)

    def cases(self) -> list:
        """Every case: the cross product of the blocks (the first block varies slowest); computed once."""
        if self._cases is None:
            self._cases = list(self.iter_cases())
        return self._cases

    def iter_cases(self):
        """The cases one at a time (a 10^5-case study starts at once; listing them all first took
        minutes). A case whose ``set`` expression or ``base`` fails raises StudyError."""
        for index, variables in self.iter_variables():
            yield self.case(index, variables)

    def iter_variables(self):
        """(index, variables) of every case, in order, without resolving them."""
        rows = [[{name: values[i] for name, values in block.items()} for i in range(_length(block))]
                for _, block in self.blocks]
        for index, combo in enumerate(itertools.product(*rows)):
            yield index, {k: v for part in combo for k, v in part.items()}

    def case(self, index, variables) -> Case:
        """The case of these variables: its parameters (the ``set`` expressions evaluated) and base file."""
        keys = study_keys()
        overrides = {k: _coerce(keys[k], v, self, k) for k, v in variables.items() if k in keys}
        for key, value in self.set.items():
            if isinstance(value, str) and value.lstrip().startswith("="):
                try:
                    value = evaluate(value.lstrip()[1:], variables)
                except ExpressionError as exc:
                    raise _err(self.path, f"set.{key}: {exc}") from None
            overrides[key] = _coerce(keys[key], value, self, key)
        try:
            base = self.base.format(**variables)
        except (ValueError, TypeError, KeyError, IndexError, AttributeError) as exc:
            raise _err(self.path, f"base {self.base!r}: {type(exc).__name__}: {exc}") from None
        path = self._paths.get(base)
        if path is None:
            path = self._paths[base] = (Path(base) if Path(base).is_absolute() else self.path.parent / base).resolve()
        return Case(index, variables, path, overrides)


def _length(block):
    return len(next(iter(block.values()))) if block else 1


def _coerce(key, value, study, name):
    """Values as the parameter loader wants them (numpy scalars -> Python, integral floats -> int)."""
    if isinstance(value, np.generic):
        value = value.item()
    if key.kind == "int" and isinstance(value, float):
        if not value.is_integer():
            raise _err(study.path, f"{name}: expected an integer, got {value!r}")
        value = int(value)
    if isinstance(value, tuple):
        value = list(value)
    return value


def _err(path, msg):
    """One line: the file, the entry, the problem (long values shortened)."""
    text = " ".join(str(msg).split())
    if len(text) > 400:
        text = text[:400] + "..."
    return StudyError(f"{path}: {text}")


def _values(path, where, values):
    if not isinstance(values, list) or not values:
        raise _err(path, f"{where}: expected a non-empty list of values, got {values!r}")
    return values


def _samples(path, kind, spec):
    """Random or Latin-hypercube samples of ``ranges`` ({name: [lo, hi] or [lo, hi, "log"]})."""
    where = f"vary.{kind}"
    if not isinstance(spec, dict) or set(spec) - {"n", "seed", "ranges"} or "ranges" not in spec:
        raise _err(path, f"{where}: expected {{n: N, seed: S, ranges: {{name: [low, high]}}}}")
    n, seed, ranges = spec.get("n"), spec.get("seed", 0), spec["ranges"]
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise _err(path, f"{where}.n: expected a positive integer, got {n!r}")
    if n > MAX_CASES:
        raise _err(path, f"{where}.n: {n} samples is above the limit of {MAX_CASES} cases per study")
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise _err(path, f"{where}.seed: expected an integer, got {seed!r}")
    if not isinstance(ranges, dict) or not ranges:
        raise _err(path, f"{where}.ranges: expected a mapping name -> [low, high]")
    rng = np.random.default_rng(seed)
    out = {}
    for name, r in ranges.items():
        log = isinstance(r, list) and len(r) == 3 and r[2] == "log"
        lo_hi = r[:2] if log else r
        if (not isinstance(lo_hi, list) or len(lo_hi) != 2 or not all(isinstance(x, (int, float)) for x in lo_hi)
                or not lo_hi[0] < lo_hi[1] or (log and lo_hi[0] <= 0)):
            raise _err(path, f"{where}.ranges.{name}: expected [low, high] (or [low, high, log]) with low < high, got {r!r}")
        if kind == "lhs":  # one sample in each of n equal strata, strata shuffled per variable
            u = (rng.permutation(n) + rng.uniform(0.0, 1.0, n)) / n
        else:
            u = rng.uniform(0.0, 1.0, n)
        lo, hi = (math.log(lo_hi[0]), math.log(lo_hi[1])) if log else (float(lo_hi[0]), float(lo_hi[1]))
        x = lo + u * (hi - lo)
        out[name] = [float(v) for v in (np.exp(x) if log else x)]
    return out


def _blocks(path, vary, seeds):
    raw = vary if isinstance(vary, list) else ([vary] if vary else [])
    blocks = []
    for i, item in enumerate(raw):
        if not isinstance(item, dict) or len(item) == 0:
            raise _err(path, f"vary[{i}]: expected a mapping with one of {', '.join(BLOCK_KINDS)}")
        for kind, spec in item.items():
            if kind not in BLOCK_KINDS:
                raise _err(path, f"vary: unknown block {kind!r} (one of {', '.join(BLOCK_KINDS)})")
            if kind in ("random", "lhs"):
                blocks.append((kind, _samples(path, kind, spec)))
                continue
            if not isinstance(spec, dict) or not spec:
                raise _err(path, f"vary.{kind}: expected a mapping name -> list of values")
            block = {name: _values(path, f"vary.{kind}.{name}", v) for name, v in spec.items()}
            if kind == "zip" and len({len(v) for v in block.values()}) > 1:
                raise _err(path, "vary.zip: the lists must have equal lengths, got "
                           + ", ".join(f"{k}: {len(v)}" for k, v in block.items()))
            if kind == "grid":  # full factorial within the block
                _check_count(path, f"vary.{kind}", math.prod(len(v) for v in block.values()))
                names = list(block)
                combos = list(itertools.product(*block.values()))
                block = {name: [c[j] for c in combos] for j, name in enumerate(names)}
            blocks.append((kind, block))
    if seeds is not None:
        if isinstance(seeds, int) and not isinstance(seeds, bool) and seeds > 0:
            _check_count(path, "seeds", seeds)
            seeds = list(range(seeds))
        if not isinstance(seeds, list) or not seeds or not all(isinstance(s, int) and not isinstance(s, bool) for s in seeds):
            raise _err(path, f"seeds: expected a list of integers or a positive count, got {seeds!r}")
        blocks.append(("seeds", {"seed": seeds}))
    _check_count(path, "vary", math.prod(_length(b) for _, b in blocks))
    return blocks


def _units(path, declared, names, settings, keys) -> dict:
    """Units of the study's own variables: ``units:`` of the file, else the unit of a parameter the
    variable is set to as it is (``key: "= name"``); a declared unit that contradicts it is an error."""
    declared = {} if declared is None else declared
    if not isinstance(declared, dict):
        raise _err(path, f"units: expected a mapping study variable -> unit, got {declared!r}")
    for name, unit in declared.items():
        if name in keys:
            raise _err(path, f"units.{name}: a parameter has its own unit ({keys[name].unit or 'none'}); units "
                       "are for the study's own variables")
        if name not in names:
            raise _err(path, f"units.{name}: not a study variable (variables: {', '.join(map(str, names))})")
        if not isinstance(unit, str) or not unit.strip():
            raise _err(path, f"units.{name}: expected a unit as text (\"m\", \"Hz\", \"1\" for a ratio), got {unit!r}")
    units = {name: unit.strip() for name, unit in declared.items()}
    inferred = {}
    for key, value in settings.items():
        bare = value.strip().lstrip("=").strip() if isinstance(value, str) and value.strip().startswith("=") else None
        if bare in names and bare not in keys and keys[key].unit:
            inferred.setdefault(bare, set()).add((key, keys[key].unit))
    for name, found in inferred.items():
        found_units = {u for _, u in found}
        if name in units:
            if units[name] not in found_units or len(found_units) > 1:
                key, unit = next((k, u) for k, u in sorted(found) if u != units[name])
                raise _err(path, f"units.{name}: {units[name]!r}, but set.{key} = {name} gives it the unit of {key} "
                           f"({unit!r})")
        elif len(found_units) == 1:  # (a variable set to parameters of different units: none, unless declared)
            units[name] = found_units.pop()
    return units


def _check_count(path, where, n):
    if n > MAX_CASES:
        raise _err(path, f"{where}: {n} cases is above the limit of {MAX_CASES} cases per study file "
                   "(split the study into several files)")


def load_study(path) -> Study:
    """Read and check a study file (every case is expanded once here, so errors show up front)."""
    path = Path(path).resolve()
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise _err(path, f"{size} bytes is above the limit of {MAX_FILE_BYTES} bytes for a study file")
        doc = yaml.safe_load(path.read_bytes().decode("utf-8"))
    except OSError as exc:
        raise _err(path, f"cannot read study file ({exc})") from None
    except UnicodeDecodeError as exc:
        raise _err(path, f"not a text file (UTF-8): byte {exc.start} cannot be decoded") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(exc, "problem", None) or exc
        raise _err(path, f"malformed YAML{where}: {problem}") from None
    except RecursionError:
        raise _err(path, "malformed YAML: nested too deeply") from None
    if not isinstance(doc, dict):
        raise _err(path, "expected a mapping at the top level")
    unknown = set(doc) - set(TOP_KEYS)
    if unknown:
        raise _err(path, f"unknown entries {sorted(unknown)} (allowed: {', '.join(TOP_KEYS)})")
    if not isinstance(doc.get("base"), str):
        raise _err(path, "base: the parameter file of the study (a path relative to this file) is required")
    blocks = _blocks(path, doc.get("vary"), doc.get("seeds"))
    keys = study_keys()
    names = [n for _, b in blocks for n in b]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise _err(path, f"variables varied twice: {sorted(dupes)}")
    for n in names:
        if not isinstance(n, str) or (n not in keys and not n.isidentifier()):
            raise _err(path, f"vary: {n!r} is neither a parameter key nor a plain name")
    settings = doc.get("set") or {}
    if not isinstance(settings, dict):
        raise _err(path, "set: expected a mapping parameter key -> value")
    used = set()
    for key, value in settings.items():
        if not isinstance(key, str) or key not in keys:
            raise _err(path, f"set: unknown parameter {key!r}")
        if key in names:
            raise _err(path, f"set: {key!r} is also varied")
        if isinstance(value, str) and value.lstrip().startswith("="):
            try:
                used |= names_in(value.lstrip()[1:])
            except ExpressionError as exc:
                raise _err(path, f"set.{key}: {exc}") from None
    try:
        fields_ = {f for _, f, _, _ in string.Formatter().parse(doc["base"]) if f is not None}
    except ValueError as exc:
        raise _err(path, f"base {doc['base']!r}: {exc}") from None
    if not fields_ <= set(names):
        raise _err(path, f"base: fields {sorted(fields_ - set(names))} are not study variables")
    used |= fields_
    unused = [n for n in names if n not in keys and n not in used]
    if unused:
        raise _err(path, f"variables {unused} are neither parameters nor used in base or set")
    units = _units(path, doc.get("units"), names, settings, keys)
    keep = dict(KEEP_DEFAULTS)
    if not isinstance(doc.get("keep") or {}, dict) or not all(isinstance(v, bool) for v in (doc.get("keep") or {}).values()):
        raise _err(path, f"keep: expected a mapping of {', '.join(KEEP_DEFAULTS)} to true or false")
    extra = set(doc.get("keep") or {}) - set(KEEP_DEFAULTS)
    if extra:
        raise _err(path, f"keep: unknown entries {sorted(extra)} (allowed: {', '.join(KEEP_DEFAULTS)})")
    keep.update(doc.get("keep") or {})
    study = Study(str(doc.get("name") or path.stem), path, doc["base"], blocks, settings, keep,
                  str(doc.get("description") or ""), units)
    for _ in itertools.islice(study.iter_cases(), EAGER_CASES):  # expression and base errors now, not in a worker
        pass
    return study
