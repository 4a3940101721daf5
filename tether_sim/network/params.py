"""A network parameter file -> (NetworkSpec, node options); no rclpy.

A network file is an ordinary ROS 2 parameter file (``tether_sim: ros__parameters:``) whose
parameters hold a ``network`` section (tether_sim/network/spec.py: points, bodies, lines, each
line with its own single-line keys) and, beside it, only the node's own keys (``node.*``: rate,
frames, input handling). Everything a single line owns (cable, ends, solver, dg, hybrid, snap,
winch, initial) is written per line under ``network.lines.<line>``; the same key at the top level
is an error naming it, as is any key the single-line schema does not know.

The node reads the network section from the files directly (``--params-file``): its keys are not
declared as ROS parameters (their names depend on the line and body names), so a ``-p`` override
applies to the ``node.*`` keys only.
"""

from tether_sim.errors import ConfigError
from tether_sim.io.params import from_flat, read_param_file
from tether_sim.network.spec import parse_network

NETWORK_KEY = "network"
_NODE_KEYS = ("node.", "use_sim_time")


def is_network(flat: dict) -> bool:
    """The flat parameters of a file describe a network (any ``network.*`` key)."""
    return any(k == NETWORK_KEY or k.startswith(NETWORK_KEY + ".") for k in flat)


def file_is_network(path) -> bool:
    try:
        return is_network(read_param_file(path))
    except ConfigError:
        return False


def unflatten(flat: dict) -> dict:
    """{"a.b.c": v} -> {"a": {"b": {"c": v}}} (inverse of ``io.params.flatten``)."""
    tree = {}
    for name, value in flat.items():
        parts = name.split(".")
        node = tree
        for p in parts[:-1]:
            node = node.setdefault(p, {})
            if not isinstance(node, dict):
                raise ConfigError(f"{name}: {'.'.join(parts[:-1])} is both a value and a section")
        node[parts[-1]] = value
    return tree


def split_flat(flat: dict, where: str):
    """(network tree, node-key flat dict) of a network file's flat parameters; a key that is neither
    raises ConfigError naming it."""
    net, rest = {}, {}
    for k, v in flat.items():
        if k.startswith(NETWORK_KEY + "."):
            net[k[len(NETWORK_KEY) + 1:]] = v
        elif k.startswith(_NODE_KEYS):
            rest[k] = v
        else:
            raise ConfigError(f"{where}: {k}: not a key of a network file; a network file holds the network.* "
                              "section and node.* keys only (cable, ends, solver, dg, snap, winch ... are set per "
                              "line under network.lines.<line>, the environment under network.environment)")
    return unflatten(net), rest


def load_network(flat: dict, where: str = "parameters"):
    """(NetworkSpec, SimConfig holding the node options) of a network file's flat parameters."""
    tree, rest = split_flat(flat, where)
    rest.pop("use_sim_time", None)
    node_config = from_flat(rest, where=where)
    try:
        spec = parse_network(tree)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from exc
    return spec, node_config


def load_network_files(paths, overrides: dict | None = None):
    """(NetworkSpec, node SimConfig) of the network parameter files ``paths`` (later files win),
    with ``overrides`` (flat node.* keys, e.g. a command line's ``-p``) over them."""
    flat = {}
    for p in paths:
        flat.update(read_param_file(p))
    if overrides:
        flat.update(overrides)
    return load_network(flat, where=", ".join(str(p) for p in paths) or "parameters")


def network_key(name: str):
    """The schema key (``io.schema.Key``: kind, unit) that a network file's flat key stands for, or
    None: ``network.lines.<line>.<key>`` a single-line key, ``network.bodies.<body>.<key>`` a
    ``body.*`` key, ``network.environment.<key>`` an ``environment.*`` key, ``network.coupling_step``
    (s), ``network.points.<point>.position`` (m); ``node.*`` keys are schema keys themselves. The
    names of lines, bodies and points are not checked here (the network's parser does, naming the key)."""
    from tether_sim.io.schema import Key, key_map

    keys = key_map()
    parts = name.split(".")
    if name.startswith("node.") or parts[0] != NETWORK_KEY or len(parts) < 2:
        return keys.get(name) if name.startswith("node.") else None
    if parts[1] == "coupling_step" and len(parts) == 2:
        return Key(name, "float", 0.005, "s", "upper bound of the body-line coupling step", 0.0, 1.0, None, False)
    if parts[1] == "environment" and len(parts) == 3:
        return keys.get("environment." + parts[2])
    if parts[1] == "lines" and len(parts) >= 4:
        return keys.get(".".join(parts[3:]))
    if parts[1] == "bodies" and len(parts) == 4:
        return keys.get("body." + parts[3])
    if parts[1] == "points" and len(parts) == 4 and parts[3] == "position":
        return Key(name, "float_array", (0.0, 0.0, 0.0), "m", "position of a fixed or driven point", None, None, None,
                   False)
    return None
