"""Parameter files -> validated, typed :class:`tether_sim.config.SimConfig` (no rclpy).

Files use the ROS 2 layout (``<node or /**>: ros__parameters: {...}``, nested sections allowed) so
``--ros-args --params-file`` takes them unchanged. Unknown keys, wrong types and out-of-range
values raise :class:`ConfigError` naming the key and the file.
"""

import difflib
import math
import re
from dataclasses import fields, is_dataclass, replace
from pathlib import Path

import yaml

from tether_sim.config import SimConfig
from tether_sim.errors import ConfigError
from tether_sim.io.schema import key_map
from tether_sim.physics.constitutive import TensionLaw
from tether_sim.solvers.resolution import implicit_damping_refusal, resolve
from tether_sim.solvers.work import check_work

NODE_SECTION_NAMES = ("tether_sim", "/tether_sim", "/**")
AREA_LIMIT = 2.0  # largest material cross-section gamma0 / density, in units of cable.diameter^2 (cross_check)


class _Loader(yaml.SafeLoader):
    """SafeLoader that also reads YAML 1.2 floats such as ``45.5e6`` (PyYAML's 1.1 rules see a string)."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)?(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789."),
)


def flatten(tree: dict, prefix: str = "") -> dict:
    """Nested dict -> {"a.b.c": value}."""
    flat = {}
    for k, v in tree.items():
        name = f"{prefix}{k}"
        if isinstance(v, dict):
            flat.update(flatten(v, name + "."))
        else:
            flat[name] = v
    return flat


def _parameters_of(document, where: str) -> dict:
    if not isinstance(document, dict):
        raise ConfigError(f"{where}: expected a mapping at the top level")
    merged = {}
    found = False
    for node_name, body in document.items():
        if node_name not in NODE_SECTION_NAMES and not str(node_name).endswith("tether_sim"):
            continue
        if not isinstance(body, dict) or "ros__parameters" not in body:
            raise ConfigError(f"{where}: section {node_name!r} has no 'ros__parameters' mapping")
        params = body["ros__parameters"] or {}
        if not isinstance(params, dict):
            raise ConfigError(f"{where}: {node_name}.ros__parameters must be a mapping")
        merged.update(flatten(params))
        found = True
    if not found:
        raise ConfigError(f"{where}: no 'tether_sim' (or '/**') section with ros__parameters")
    return merged


def read_param_file(path) -> dict:
    """Flat {key: value} of the tether_sim section(s) of a ROS 2 parameter YAML file."""
    path = Path(path)
    try:
        document = yaml.load(path.read_text(), Loader=_Loader)
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read parameter file ({exc})") from exc
    except yaml.YAMLError as exc:
        raise ConfigError(f"{path}: malformed YAML ({exc})") from exc
    return _parameters_of(document, str(path))


def _check_value(key, value, where):
    name = f"{where}: {key.name}"
    if key.kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"{name}: expected a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise ConfigError(f"{name}: must be finite, got {value!r}")
    elif key.kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{name}: expected an integer, got {value!r}")
    elif key.kind == "bool":
        if not isinstance(value, bool):
            raise ConfigError(f"{name}: expected true or false, got {value!r}")
    elif key.kind == "str":
        if not isinstance(value, str):
            raise ConfigError(f"{name}: expected a string, got {value!r}")
    elif key.kind in ("float_array", "str_array"):
        if not isinstance(value, (list, tuple)):
            raise ConfigError(f"{name}: expected a list, got {value!r}")
        items = []
        for x in value:
            if isinstance(x, str) and key.kind == "str_array":
                items.append(x)
            elif not isinstance(x, bool) and isinstance(x, (int, float)) and key.kind == "float_array":
                if not math.isfinite(float(x)):
                    raise ConfigError(f"{name}: array entries must be finite, got {x!r}")
                items.append(float(x))
            else:
                raise ConfigError(f"{name}: bad array entry {x!r}")
        value = tuple(items)
        if key.default and len(key.default) in (2, 3, 4) and len(value) != len(key.default):
            raise ConfigError(f"{name}: expected {len(key.default)} values, got {len(value)}")
    if key.min is not None and key.kind in ("float", "int") and value < key.min:
        raise ConfigError(f"{name}: {value} is below the minimum {key.min} {key.unit}".rstrip())
    if key.max is not None and key.kind in ("float", "int") and value > key.max:
        raise ConfigError(f"{name}: {value} is above the maximum {key.max} {key.unit}".rstrip())
    if key.choices and value not in key.choices:
        raise ConfigError(f"{name}: {value!r} is not one of {', '.join(key.choices)}")
    return value


def check_values(flat: dict, where: str) -> dict:
    """Each value of ``flat`` checked on its own (name, type, range), without resolving the whole
    configuration (a command-line override that only makes sense with the file's other keys)."""
    return _checked(flat, where)


def _checked(flat: dict, where: str) -> dict:
    keys = key_map()
    checked = {}
    for name, value in flat.items():
        if name in ("use_sim_time",):
            continue  # standard ROS parameter, handled by the node
        if name not in keys:
            close = difflib.get_close_matches(str(name), keys, n=1, cutoff=0.7)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ConfigError(f"{where}: unknown parameter {name!r}{hint}")
        checked[name] = _check_value(keys[name], value, where)
    return checked


def from_flat(flat: dict, where: str = "parameters", base: SimConfig | None = None) -> SimConfig:
    """Validate a flat {dotted key: value} mapping and apply it over ``base`` (default values)."""
    checked = _checked(flat, where)
    config = resolve(_apply(base or SimConfig(), checked), given=checked)  # dg.resolution auto: N, P, cfl by the rule
    return cross_check(config, where)


def cross_check(config: SimConfig, where: str = "parameters") -> SimConfig:
    """Checks of related keys, each inside its own documented range but not together (ConfigError)."""
    snap = config.snap
    # slack begins below slack_fraction x static and ends above retension_fraction x static: with the
    # second at or below the first there is no hysteresis, and a tension that hovers about the threshold
    # makes slack periods, and "snaps", of nothing
    if snap.slack_threshold == 0.0 and snap.retension_fraction <= snap.slack_fraction:
        raise ConfigError(f"{where}: snap.retension_fraction = {snap.retension_fraction:g} must be above "
                          f"snap.slack_fraction = {snap.slack_fraction:g} (slack begins below slack_fraction x static "
                          "tension and ends above retension_fraction x static)")
    # EA = 0 is the hybrid solver's inextensible rod [GP]; the DG solver's time step and tension come from
    # the axial wave speed sqrt(EA / gamma0) [PE2020 Eq. 22]
    if config.solver == "dg" and config.cable.EA <= 0.0:
        raise ConfigError(f"{where}: cable.EA = {config.cable.EA:g} N: the dg solver needs an axial stiffness > 0 "
                          "(EA = 0, an inextensible cable, is for solver: hybrid)")
    # the material cross-section A = gamma0 / density [PE2020 Eq. 14] sets the buoyancy (and the hybrid rod's
    # rotary inertia): a solid section inside the diameter has A <= pi d^2 / 4 = 0.79 d^2 (a square section
    # d^2); far above it is a unit slip (density in g/cm^3: A 470 d^2 on ROPOS; at the range end 0.001 kg/m^3
    # the hybrid solver's first Newton step failed)
    cab = config.cable
    area = cab.gamma0 / cab.density
    if area > AREA_LIMIT * cab.diameter ** 2:
        raise ConfigError(f"{where}: cable.gamma0 / cable.density = {cab.gamma0:g} / {cab.density:g} = {area:.3g} m^2 "
                          f"material cross-section, above {AREA_LIMIT:g} x cable.diameter^2 = {AREA_LIMIT * cab.diameter ** 2:.3g} "
                          "m^2 (a solid section inside the diameter has at most 0.79 d^2): check the units of cable.density "
                          "(kg/m^3) and cable.diameter (m)")
    opt = config.dg
    if config.solver == "dg" and len(opt.element_lengths) not in (0, opt.n_elements):
        raise ConfigError(f"{where}: dg.element_lengths has {len(opt.element_lengths)} weights, dg.n_elements = "
                          f"{opt.n_elements}: give one positive weight per element (or none: uniform)")
    if config.solver == "dg" and any(w <= 0.0 for w in opt.element_lengths):
        raise ConfigError(f"{where}: dg.element_lengths: every weight must be > 0, got {list(opt.element_lengths)}")
    try:
        TensionLaw(config.cable)
    except ValueError as exc:  # the tabulated law: its points, checked together
        raise ConfigError(f"{where}: {exc}") from exc
    # implicit damping where slack phases reach the compression cap of a cable with bending: measured wrong
    reason = implicit_damping_refusal(config)
    if reason:
        raise ConfigError(f"{where}: {reason}")
    # inside its range every key may still make a run that never ends (a substep of 1e-8 s): refused here
    check_work(config, where)
    return config


class ParamFileOverlay:
    """A parameter file read and checked once, then many sets of overrides over it (the cases of a study):
    ``overlay(overrides)`` is ``load_config(path, overrides)`` without reading the file again."""

    def __init__(self, path, flat: dict | None = None):
        """``flat``: the file's flat parameters when already read (read_param_file), else read here."""
        self.path = Path(path)
        self.checked = _checked(read_param_file(self.path) if flat is None else dict(flat), str(self.path))
        self.unresolved = _apply(SimConfig(), self.checked)

    def __call__(self, overrides: dict | None = None) -> SimConfig:
        extra = _checked(overrides or {}, str(self.path))
        return cross_check(resolve(_apply(self.unresolved, extra), given={**self.checked, **extra}), str(self.path))


def _apply(obj, checked: dict):
    """``obj`` with the dotted keys of ``checked`` (relative to ``obj``) replaced; one pass over the keys."""
    nested, changes = {}, {}
    for name, value in checked.items():
        head, dot, rest = name.partition(".")
        if dot:
            nested.setdefault(head, {})[rest] = value
        else:
            changes[head] = value
    names = {f.name for f in fields(obj)}
    changes = {k: v for k, v in changes.items() if k in names and not is_dataclass(getattr(obj, k))}
    for head, sub in nested.items():
        if head in names and is_dataclass(getattr(obj, head)):
            changes[head] = _apply(getattr(obj, head), sub)
    return replace(obj, **changes) if changes else obj


def load_config(path, overrides: dict | None = None) -> SimConfig:
    """Read a parameter file (plus optional flat overrides) into a validated SimConfig."""
    flat = read_param_file(path)
    if overrides:
        flat.update(overrides)
    return from_flat(flat, where=str(path))


def _flat_paths(obj, prefix=()):
    out = []
    for f in fields(obj):
        value = getattr(obj, f.name)
        out.extend(_flat_paths(value, prefix + (f.name,)) if is_dataclass(value) else [prefix + (f.name,)])
    return out


_FLAT_PATHS = []  # [(dotted name, (attribute, ...)), ...] of SimConfig (a fixed tree of dataclasses)


def to_flat(config: SimConfig) -> dict:
    """SimConfig -> flat {dotted key: value} (the inverse of :func:`from_flat`)."""
    if not _FLAT_PATHS:
        _FLAT_PATHS.extend((".".join(p), p) for p in _flat_paths(SimConfig()))
    out = {}
    for name, path in _FLAT_PATHS:
        value = config
        for attr in path:
            value = getattr(value, attr)
        out[name] = value
    return out
