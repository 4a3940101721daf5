"""Parameter metadata carried on dataclass fields: the single source of every configuration key.

Every configuration dataclass declares its fields with :func:`param`; ``io.schema`` walks the
dataclasses to produce the flat key list (``cable.EA``, ``dg.order``...) that the YAML loader,
the ROS node's ``declare_parameter`` calls and the README's parameter table all use.

Field types are restricted to what ROS parameters can hold: ``float``, ``int``, ``bool``, ``str``,
``tuple[float, ...]`` (double array) and ``tuple[str, ...]`` (string array).
"""

from dataclasses import MISSING, field


def param(default=MISSING, *, unit="", doc, min=None, max=None, choices=None, live=False):
    """A dataclass field with its unit, one-line description, bounds and whether it may change live.

    ``min``/``max`` are inclusive bounds (``None``: unbounded); ``choices`` lists allowed strings;
    ``live`` marks keys a running node accepts at run time (others are refused with a reason).
    """
    meta = {"unit": unit, "doc": doc, "min": min, "max": max, "choices": choices, "live": live}
    if isinstance(default, (list, tuple)):
        value = tuple(default)
        return field(default_factory=lambda: value, metadata=meta)
    return field(default=default, metadata=meta)
