"""Line networks: validation of bad networks (clear errors naming the key)."""

import copy

import pytest

from tether_sim.errors import ConfigError
from tether_sim.network.spec import parse_network

CABLE = dict(length=100.0, EA=1.0e7, gamma0=2.0, density=5000.0, diameter=0.03, material="bilinear")
BASE = dict(
    points=dict(ship=dict(kind="prescribed", position=[0.0, 0.0, 0.0]),
                anchor=dict(kind="fixed", position=[10.0, 0.0, -120.0])),
    bodies=dict(cage=dict(mass=1000.0, density=5000.0)),
    lines={"main": {"from": "ship", "to": "cage", "to_attachment": [0.0, 0.0, 1.0], "cable": CABLE},
           "excursion": {"from": "cage", "to": "anchor", "cable": dict(CABLE, length=20.0)}},
)


def tree(**edits):
    t = copy.deepcopy(BASE)
    for path, value in edits.items():
        node = t
        keys = path.split("__")
        for k in keys[:-1]:
            node = node[k]
        if value is None:
            del node[keys[-1]]
        else:
            node[keys[-1]] = value
    return t


def test_good_network_parses():
    spec = parse_network(tree())
    assert set(spec.lines) == {"main", "excursion"}
    assert [e.kind for e in spec.lines["main"].ends] == ["point", "body"]
    assert spec.lines["main"].ends[1].attachment == (0.0, 0.0, 1.0)
    assert [e.line for e in spec.ends_on("cage")] == ["main", "excursion"]
    assert spec.lines["excursion"].config.cable.length == 20.0


@pytest.mark.parametrize("edits, key, words", [
    (dict(lines__excursion__to=None), "network.lines.excursion.to", "dangles"),
    (dict(lines__main__to="cgae"), "network.lines.main.to", "did you mean 'cage'"),
    (dict(lines__main__from="winchh"), "network.lines.main.from", "unknown point or body"),
    (dict(bodies__tms=dict(mass=10.0)), "network.bodies.tms", "no line ends on this body"),
    (dict(points__spare=dict(kind="fixed", position=[0, 0, -1])), "network.points.spare", "no line ends"),
    (dict(points__ship=dict(kind="moving", position=[0, 0, 0])), "network.points.ship.kind", "not one of"),
    (dict(lines__main__ship_end=dict(kind="fixed")), "network.lines.main.ship_end.kind", "set by the network"),
    (dict(lines__main__cable=dict(CABLE, lenght=3.0)), "network.lines.main", "unknown parameter 'cable.lenght'"),
    (dict(lines__main__from_attachment=[0, 0, 1]), "network.lines.main.from_attachment", "only an end on a body"),
    (dict(lines__main__to_attachment=[0, 1]), "network.lines.main.to_attachment", "3 finite numbers"),
    (dict(bodies__cage=dict(mass=-1.0)), "network.bodies.cage", "below the minimum"),
    (dict(bodies__cage=dict(mass=1.0, attachment=[0, 0, 1])), "network.bodies.cage.attachment", "one attachment per line end"),
    (dict(lines={}), "network.lines", "at least one line"),
    (dict(lines__excursion__from="free", lines__excursion__to="free"), "network.lines.excursion", "both ends free"),
    (dict(coupling_step=0.0), "network.coupling_step", "(0, 1]"),
    (dict(colour="red"), "network.colour", "unknown key"),
])
def test_bad_network_names_the_key(edits, key, words):
    with pytest.raises(ConfigError) as err:
        parse_network(tree(**edits))
    msg = str(err.value)
    assert key in msg and words in msg, msg
