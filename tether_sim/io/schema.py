"""The flat list of configuration keys, derived from the dataclass tree in ``tether_sim.config``.

``cable.EA`` is field ``EA`` of section ``cable``; top-level fields (``solver``, ``duration``) have
no dot. Each :class:`Key` carries type, unit, default, bounds, choices, description and liveness.
"""

from dataclasses import dataclass, fields, is_dataclass
from functools import lru_cache

from tether_sim.config import SimConfig


@dataclass(frozen=True)
class Key:
    """One configuration key."""

    name: str  # dotted name, e.g. "cable.EA"
    kind: str  # "float" | "int" | "bool" | "str" | "float_array" | "str_array"
    default: object
    unit: str
    doc: str
    min: object
    max: object
    choices: object
    live: bool


def _kind_of(default, annotation) -> str:
    if isinstance(default, bool):
        return "bool"
    if isinstance(default, int):
        return "int"
    if isinstance(default, float):
        return "float"
    if isinstance(default, str):
        return "str"
    if isinstance(default, tuple):
        if default and all(isinstance(x, str) for x in default):
            return "str_array"
        if not default and "str" in str(annotation):  # an empty tuple[str, ...]
            return "str_array"
        return "float_array"
    raise TypeError(f"unsupported parameter default {default!r} ({annotation})")


def _walk(instance, prefix, out):
    for f in fields(instance):
        value = getattr(instance, f.name)
        name = prefix + f.name
        if is_dataclass(value):
            _walk(value, name + ".", out)  # the instance: a section's default_factory may differ from its class defaults
            continue
        meta = f.metadata
        if "doc" not in meta:
            raise TypeError(f"field {name} lacks param() metadata")
        out.append(Key(name, _kind_of(value, f.type), value, meta["unit"], meta["doc"],
                       meta["min"], meta["max"], meta["choices"], meta["live"]))


@lru_cache(maxsize=None)
def all_keys() -> tuple:
    """Every key of :class:`SimConfig`, in declaration order."""
    out = []
    _walk(SimConfig(), "", out)
    return tuple(out)


def key_map() -> dict:
    """Dotted name -> :class:`Key`."""
    return {k.name: k for k in all_keys()}


def markdown_table() -> str:
    """The README's parameter reference, generated so it cannot go stale."""
    rows = ["| key | type | unit | default | range / choices | live | description |",
            "|---|---|---|---|---|---|---|"]
    for k in all_keys():
        if k.choices:
            rng = ", ".join(k.choices)
        elif k.min is not None or k.max is not None:
            rng = f"[{'' if k.min is None else k.min}, {'' if k.max is None else k.max}]"
        else:
            rng = ""
        default = list(k.default) if isinstance(k.default, tuple) else k.default
        rows.append(f"| `{k.name}` | {k.kind} | {k.unit} | `{default}` | {rng} | {'yes' if k.live else ''} | {k.doc} |")
    return "\n".join(rows)


