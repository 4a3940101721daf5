"""Every SimConfig key as a declared ROS parameter, read back through ``io.params.from_flat``.

The schema (``tether_sim.io.schema``) is the single list of keys. Each is declared with a
``ParameterDescriptor``: description with the unit, numeric range, allowed choices, and
``read_only`` unless the key is live (``param(..., live=True)``; e.g. the snap thresholds).

rclpy alone ignores keys of a ``--params-file`` that the node never declares, and refuses an
integer written for a double (``EA: 45500000``). So the parameter overrides the node received are
first validated with ``io.params`` (unknown keys, wrong types and out-of-range values raise
:class:`ConfigError` naming the key and the file), then re-typed (int -> double) before declaring.
"""

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, SetParametersResult
from rclpy.exceptions import ParameterUninitializedException
from rclpy.parameter import Parameter

from tether_sim.errors import ConfigError
from tether_sim.io.params import check_values, from_flat, to_flat
from tether_sim.io.schema import all_keys, key_map

STANDARD_PARAMETERS = ("use_sim_time",)
_TYPES = {"float": Parameter.Type.DOUBLE, "int": Parameter.Type.INTEGER, "bool": Parameter.Type.BOOL,
          "str": Parameter.Type.STRING, "float_array": Parameter.Type.DOUBLE_ARRAY,
          "str_array": Parameter.Type.STRING_ARRAY}
_FLOAT_LIMIT = 1.0e308  # stands in for an open bound of a floating-point range


def descriptor(key) -> ParameterDescriptor:
    """ParameterDescriptor of one schema key (description + unit, range, choices, read_only)."""
    unit = f" [{key.unit}]" if key.unit else ""
    d = ParameterDescriptor(name=key.name, type=_TYPES[key.kind].value, description=key.doc + unit,
                            read_only=not key.live)
    notes = []
    if key.choices:
        notes.append("one of: " + ", ".join(key.choices))
    if key.kind == "float" and (key.min is not None or key.max is not None):
        lo = -_FLOAT_LIMIT if key.min is None else float(key.min)
        hi = _FLOAT_LIMIT if key.max is None else float(key.max)
        d.floating_point_range = [FloatingPointRange(from_value=lo, to_value=hi, step=0.0)]
    elif key.kind == "int" and (key.min is not None or key.max is not None):
        lo = -(2**63) if key.min is None else int(key.min)
        hi = 2**63 - 1 if key.max is None else int(key.max)
        d.integer_range = [IntegerRange(from_value=lo, to_value=hi, step=0)]
    if not key.live:
        notes.append("read-only at run time: restart the node with a changed parameter file")
    d.additional_constraints = "; ".join(notes)
    return d


def _as_parameter(key, value) -> Parameter:
    if key.kind in ("float_array", "str_array"):
        value = list(value)
    return Parameter(key.name, _TYPES[key.kind], value)


def declare_all(node, where: str = "parameters", cli_keys=()):
    """Validate the node's overrides, declare every key, return the SimConfig read back.

    ``where`` names the parameter file(s) in error messages; keys in ``cli_keys`` came from a
    command-line ``-p`` (which wins over the files) and are blamed on it. Raises ConfigError.
    """
    keys = key_map()
    overrides = node._parameter_overrides  # rclpy keeps --params-file / -p values here
    raw = {name: p.value for name, p in overrides.items() if name not in STANDARD_PARAMETERS}
    for name, value in raw.items():
        if value is None and name in keys and keys[name].kind.endswith("array"):
            raw[name] = ()  # an empty YAML list arrives untyped
    # each -p value on its own (type, range): it may only make sense with the file's keys
    # (-p dg.n_elements:=4 over a file with dg.resolution: manual)
    check_values({k: v for k, v in raw.items() if k in set(cli_keys)}, where="command-line -p override")
    config = from_flat(raw, where=where)  # names unknown / out-of-range keys and the file
    validated = to_flat(config)
    derived = [k for k, v in validated.items() if k not in raw and v != keys[k].default]  # dg.resolution auto
    for name in [*raw, *derived]:
        if keys[name].kind.endswith("array") and len(validated[name]) == 0:
            del overrides[name]  # rclpy types an empty list as a byte array
        else:
            overrides[name] = _as_parameter(keys[name], validated[name])
    for key in all_keys():
        d = descriptor(key)
        if key.kind.endswith("array") and (len(validated[key.name]) == 0 or len(key.default) == 0):
            node.declare_parameter(key.name, _TYPES[key.kind], d)  # empty (or empty default): by type, an override wins
        else:
            node.declare_parameter(key.name, _as_parameter(key, key.default).value, d)
    return read_config(node)


def read_config(node, base=None):
    """SimConfig from the node's current parameter values (via io.params.from_flat)."""
    flat = {}
    for key in all_keys():
        try:
            value = node.get_parameter(key.name).value
        except ParameterUninitializedException:
            value = ()
        flat[key.name] = () if value is None else value
    return from_flat(flat, where=f"node {node.get_fully_qualified_name()} parameters", base=base)


def check_live_change(parameters, current_config):
    """Validate a runtime parameter change: (SetParametersResult, new SimConfig or None).

    Non-live keys are refused with a reason; live keys are range-checked via io.params.
    """
    keys = key_map()
    flat = {}
    for p in parameters:
        if p.name in STANDARD_PARAMETERS:
            continue
        key = keys.get(p.name)
        if key is None:
            return SetParametersResult(successful=False, reason=f"unknown parameter {p.name!r}"), None
        if not key.live:
            return SetParametersResult(successful=False, reason=(
                f"{p.name} cannot change while running (it shapes the solver); "
                "restart the node with a changed parameter file")), None
        value = p.value
        if key.kind == "float" and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        flat[p.name] = value
    if not flat:
        return SetParametersResult(successful=True), None
    try:
        config = from_flat(flat, where="live parameter change", base=current_config)
    except ConfigError as exc:
        return SetParametersResult(successful=False, reason=str(exc)), None
    return SetParametersResult(successful=True), config
