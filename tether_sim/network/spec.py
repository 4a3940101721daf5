"""A line network from a nested mapping (the ``network`` section of a parameter file), validated.

Layout (every name is free except ``free``, which marks a free line end)::

    network:
      environment: {...}                  # shared by every line and body (environment.* keys)
      coupling_step: 0.005                # s, upper bound of the body-line coupling step
      points:
        ship:   {kind: prescribed, position: [0, 0, 0]}     # driven (set_point_motion)
        anchor: {kind: fixed, position: [40, 0, -230]}
      bodies:
        cage: {mass: 4995, density: 8448, ...}               # body.* keys (RigidBodyProperties)
      lines:
        umbilical:
          from: ship                        # s = 0 end: a point, a body or free
          to: cage                          # s = L end
          to_attachment: [0, 0, 2.1]        # body frame, for an end on a body
          solver: dg                        # and the single-line keys cable.*, dg.*, hybrid.*, initial.*, snap.*
          winch: {enabled: true, end: ship} # a winch at this line's from (ship) or to (vehicle) end

A bad network raises :class:`ConfigError` naming the key: a line end naming nothing (dangling) or
an unknown point or body, a body without lines, a point without lines, an attachment on an end
that is not on a body, single-line keys that the network owns (ship_end, vehicle_end, body), a
winch on a free end. A line has at most one winch (its ``winch`` keys), so two winches on one line
end cannot be written; two lines ending on one point or body may each have one (two drums).
"""

import difflib
import math
from dataclasses import dataclass, replace
from functools import cached_property

from tether_sim.config import SimConfig
from tether_sim.errors import ConfigError
from tether_sim.io.params import flatten, from_flat
from tether_sim.physics.bodies import RigidBodyProperties
from tether_sim.physics.boundary import END_NAMES, EndCondition

POINT_KINDS = ("fixed", "prescribed")
FREE = "free"
END_KEYS = ("from", "to")  # s = 0 (the line's ship end), s = L (its vehicle end)
LINE_OWNED = ("ship_end", "vehicle_end", "body", "environment", "duration", "motion", "node", "waves")
_ATTACH = {"from": "from_attachment", "to": "to_attachment"}


@dataclass(frozen=True)
class PointSpec:
    name: str
    kind: str  # fixed | prescribed
    position: tuple


@dataclass(frozen=True)
class EndSpec:
    """Where one line end is: ``target`` is a point name, a body name or FREE."""

    line: str
    end: str  # "ship" (s = 0, key from) | "vehicle" (s = L, key to)
    target: str
    kind: str  # point | body | free
    attachment: tuple = (0.0, 0.0, 0.0)  # body frame (body ends)

    @property
    def row(self):
        """Its row in the line's end tables (0: s = 0, the ship end; 1: s = L)."""
        return END_NAMES.index(self.end)

    @property
    def key(self):
        return f"network.lines.{self.line}.{'from' if self.end == 'ship' else 'to'}"


@dataclass(frozen=True)
class LineSpec:
    name: str
    config: SimConfig  # its ship_end / vehicle_end are placeholders until the network sets them
    ends: tuple  # (EndSpec s = 0, EndSpec s = L)


@dataclass(frozen=True)
class BodySpec:
    name: str
    props: RigidBodyProperties


@dataclass(frozen=True)
class NetworkSpec:
    points: dict
    bodies: dict
    lines: dict
    coupling_step: float
    environment: object

    def ends_on(self, target):
        """Every EndSpec attached to the point or body ``target`` (a list, in line order)."""
        return list(self._ends_by_target.get(target, ()))

    def end_rows(self, target):
        """(line, row) of every line end on the point or body ``target`` (row: EndSpec.row), in line order."""
        return self._end_rows_by_target.get(target, ())

    @cached_property
    def _ends_by_target(self):
        # built once per spec (a spec does not change once built; frozen fields, so a cache is safe)
        table = {}
        for ln in self.lines.values():
            for e in ln.ends:
                table.setdefault(e.target, []).append(e)
        return {t: tuple(ends) for t, ends in table.items()}

    @cached_property
    def _end_rows_by_target(self):
        return {t: tuple((e.line, e.row) for e in ends) for t, ends in self._ends_by_target.items()}


def _mapping(value, key):
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise ConfigError(f"{key}: expected a mapping, got {value!r}")
    return value


def _vec3(value, key):
    if (not isinstance(value, (list, tuple)) or len(value) != 3
            or any(isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x) for x in value)):
        raise ConfigError(f"{key}: expected 3 finite numbers, got {value!r}")
    return tuple(float(x) for x in value)


def _unknown(name, options, key, what):
    close = difflib.get_close_matches(str(name), list(options), n=1, cutoff=0.6)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    known = ", ".join(sorted(options)) or "none defined"
    return ConfigError(f"{key}: unknown {what} {name!r}{hint}; known: {known}, or {FREE!r}")


def parse_network(tree: dict, where: str = "network") -> NetworkSpec:
    """Validate a nested ``network`` mapping (module docstring) into a :class:`NetworkSpec`."""
    tree = _mapping(tree, where)
    known = {"environment", "coupling_step", "points", "bodies", "lines"}
    for k in tree:
        if k not in known:
            raise ConfigError(f"{where}.{k}: unknown key (one of {', '.join(sorted(known))})")
    env_flat = {f"environment.{k}": v for k, v in flatten(_mapping(tree.get("environment"), f"{where}.environment")).items()}
    base = from_flat(env_flat, where=where)
    env = base.environment
    step = tree.get("coupling_step", 0.005)
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not (0.0 < step <= 1.0):
        raise ConfigError(f"{where}.coupling_step: expected a number in (0, 1] s, got {step!r}")

    points = {}
    for name, p in _mapping(tree.get("points"), f"{where}.points").items():
        key = f"{where}.points.{name}"
        p = _mapping(p, key)
        for k in p:
            if k not in ("kind", "position"):
                raise ConfigError(f"{key}.{k}: unknown key (kind, position)")
        kind = p.get("kind")
        if kind not in POINT_KINDS:
            raise ConfigError(f"{key}.kind: {kind!r} is not one of {', '.join(POINT_KINDS)}")
        if "position" not in p:
            raise ConfigError(f"{key}.position: missing")
        points[name] = PointSpec(name, kind, _vec3(p["position"], f"{key}.position"))

    bodies = {}
    for name, b in _mapping(tree.get("bodies"), f"{where}.bodies").items():
        key = f"{where}.bodies.{name}"
        if name in points:
            raise ConfigError(f"{key}: the name is already a point")
        if name == FREE:
            raise ConfigError(f"{key}: {FREE!r} is reserved for free line ends")
        b = _mapping(b, key)
        if "attachment" in b:
            raise ConfigError(f"{key}.attachment: a network body has one attachment per line end "
                              "(network.lines.<line>.from_attachment / to_attachment)")
        flat = {f"body.{k}": v for k, v in flatten(b).items()}
        props = from_flat(flat, where=key).body
        bodies[name] = BodySpec(name, replace(props, attachment=(0.0, 0.0, 0.0)))

    lines = {}
    raw_lines = _mapping(tree.get("lines"), f"{where}.lines")
    if not raw_lines:
        raise ConfigError(f"{where}.lines: a network needs at least one line")
    for name, ln in raw_lines.items():
        key = f"{where}.lines.{name}"
        ln = dict(_mapping(ln, key))
        ends = []
        for ek, end in zip(END_KEYS, END_NAMES):
            if ek not in ln:
                raise ConfigError(f"{key}.{ek}: missing: the line end dangles (name a point, a body or {FREE!r})")
            target = ln.pop(ek)
            attach = ln.pop(_ATTACH[ek], None)
            if target == FREE:
                kind = "free"
            elif target in points:
                kind = "point"
            elif target in bodies:
                kind = "body"
            else:
                raise _unknown(target, list(points) + list(bodies), f"{key}.{ek}", "point or body")
            if attach is not None and kind != "body":
                raise ConfigError(f"{key}.{_ATTACH[ek]}: only an end on a body has an attachment ({ek} is {target!r})")
            att = _vec3(attach, f"{key}.{_ATTACH[ek]}") if attach is not None else (0.0, 0.0, 0.0)
            ends.append(EndSpec(name, end, target, kind, att))
        if all(e.kind == "free" for e in ends):
            raise ConfigError(f"{key}: both ends free; a line needs at least one end on a point or a body")
        flat = flatten(ln)
        for k in flat:
            if k.split(".")[0] in LINE_OWNED:
                raise ConfigError(f"{key}.{k}: set by the network (ends: from/to; environment: "
                                  f"{where}.environment; bodies: {where}.bodies)")
        flat.update(env_flat)
        config = from_flat(flat, where=key)
        if config.winch.enabled:
            on = ends[0 if config.winch.end == "ship" else 1]
            if on.kind == "free":
                raise ConfigError(f"{key}.winch.end: {config.winch.end} is the line's "
                                  f"{'from' if on.end == 'ship' else 'to'} end, which is free; a winch sits on "
                                  "a point or a body (its sheave)")
        lines[name] = LineSpec(name, config, tuple(ends))

    spec = NetworkSpec(points, bodies, lines, float(step), env)
    for name in bodies:
        if not spec.ends_on(name):
            raise ConfigError(f"{where}.bodies.{name}: no line ends on this body (a body needs at least one line)")
    for name in points:
        if not spec.ends_on(name):
            raise ConfigError(f"{where}.points.{name}: no line ends on this point")
    return spec


def line_end_condition(end: EndSpec, spec: NetworkSpec, position) -> EndCondition:
    """The single-line end condition a network end becomes: a point keeps its kind, a body end is
    driven with the body's kinematics (prescribed), a free end is free."""
    if end.kind == "free":
        return EndCondition(kind="free", position=tuple(position))
    if end.kind == "point":
        return EndCondition(kind=spec.points[end.target].kind, position=tuple(position))
    return EndCondition(kind="prescribed", position=tuple(position))
