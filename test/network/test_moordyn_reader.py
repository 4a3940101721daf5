"""MoorDyn v2 input files (tether_sim/network/moordyn.py): MoorDyn's own test decks load or are refused by
name, the mapping keeps MoorDyn's loads per metre, and the static fairlead force of every deck with a
Vessel point matches pip moordyn's within 1 %.

The decks are MoorDyn's tests/Mooring/ (BSD-3, test/data/moordyn/SOURCE.md). Measured (2026-11-27,
``PYTHONPATH=. python benchmarks/studies/moordyn_decks.py``): WD0050 +0.25 %, WD0200 +0.02 %, WD0600
+0.03 %, lines.txt +0.14 %, local_euler/duplicated.txt +0.11 %, polyester/simple.txt +0.00 %.
Run time ~10 s (MoorDyn's initial-condition solves).
"""

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from benchmarks.studies import moordyn_decks as md
from tether_sim.errors import ConfigError
from tether_sim.network import moordyn as mdr
from tether_sim.network.params import load_network_files
from tether_sim.physics.hydrodynamics import net_weight_per_length

DECKS = md.DECKS

LOADS = {"BeamSimplySupported.txt", "WD0050_Chain.txt", "WD0200_Chain.txt", "WD0600_Chain.txt", "lines.txt",
         "local_euler/duplicated.txt", "polyester/simple.txt"}
# deck -> the words its refusal names (every other deck of MoorDyn's tests/Mooring/)
REFUSED = {
    "3D_seafloor/hanging_lines.txt": "SeafloorFile", "seafloor.txt": "SeafloorFile",
    "BeamCantilevered.txt": "rods", "BodiesAndRods.dat": "rods", "RodHanging.txt": "rods",
    "body_tests/pinnedBody.txt": "rods", "local_euler/complex_system.txt": "rods", "riser/riser.txt": "rods",
    "riser/riser_ic1.txt": "rods", "riser/riser_ic2.txt": "rods", "rod_tests/AddedMass.txt": "rods",
    "body_tests/bodyDrag.txt": "rotated body", "body_tests/rotatingBody.txt": "vortex-induced vibration",
    "viv/viv.txt": "vortex-induced vibration",
    "lifting.txt": "clump weight", "pendulum.txt": "clump weight", "time_schemes.txt": "clump weight",
    "local_euler/hanging.txt": "connection node", "tripod.txt": "connection node",
    "polyester/visco.txt": "viscoelastic", "syrope/exp_wc/line.txt": "Syrope",
    "syrope/linear_wc/line.txt": "Syrope", "syrope/quadratic_wc/line.txt": "Syrope",
    "lowe_and_langley_2006/line.txt": "WaveKin", "wave_surface/wave_surface.txt": "WaveKin",
    "wavekin_2/wavekin_2.txt": "WaveKin", "wavekin_2/wavekin_2_curr2.txt": "WaveKin",
    "wavekin_2/wavekin_2_curr5.txt": "WaveKin", "wavekin_2/wavekin_3.txt": "WaveKin",
    "wavekin_2/wavekin_3_curr2.txt": "WaveKin", "wavekin_2/wavekin_3_curr5.txt": "WaveKin",
    "wavekin_7/wavekin_7.txt": "WaveKin", "wavekin_current_1.txt": "WaveKin", "wavekin_wave_1.txt": "WaveKin",
    "wavekin_3/test_dynamic_currents.txt": "Currents", "wavekin_4/hanging_lines.txt": "Currents",
}


def _rel(f):
    return str(f.relative_to(DECKS))


def test_every_deck_is_accounted_for():
    assert {_rel(f) for f in md.deck_files()} == LOADS | set(REFUSED)


@pytest.mark.parametrize("name", sorted(LOADS))
def test_supported_decks_load(name):
    deck = mdr.read_deck(DECKS / name)
    spec = mdr.network_spec(deck)
    assert len(spec.lines) == len(deck.lines)


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_unsupported_decks_are_refused_by_name(name):
    with pytest.raises(ConfigError) as exc:
        mdr.network_spec(mdr.read_deck(DECKS / name))
    msg = str(exc.value)
    assert str(DECKS / name) in msg and REFUSED[name] in msg


def test_mapping_keeps_moordyns_loads_per_metre():
    """Wet weight (m - rho pi d^2/4) g, BA = -zeta (L/N) sqrt(EA m), axial drag on pi d, seabed
    damping cBot d as a ratio of 2 sqrt(kBot d m), end B at s = 0, the seabed at -WtrDpth."""
    deck = mdr.read_deck(DECKS / "WD0050_Chain.txt")
    spec = mdr.network_spec(deck)
    line = spec.lines["line1"]
    c, env = line.config.cable, spec.environment
    d, m = 0.252, 390.0
    w = net_weight_per_length(c, env)
    assert w == pytest.approx((m - 1025.0 * math.pi * d * d / 4) * 9.80665, rel=1e-12)
    assert c.damping == pytest.approx(1.0 * 410.0 / 41 * math.sqrt(1.674e9 * m), rel=1e-12)
    assert c.Cdt == pytest.approx(math.pi * 0.64) and c.Cdn == 1.37 and c.Cmn == 1.0 and c.Cmt == 0.0
    assert env.seabed and env.seabed_z == -50.0 and env.seabed_stiffness == 1e5 and env.seabed_friction == 0.5
    assert env.seabed_damping == pytest.approx(1e4 * d / (2 * math.sqrt(1e5 * d * m)), rel=1e-12)
    assert [e.target for e in line.ends] == ["point2", "point1"]  # the Vessel point at s = 0
    assert spec.points["point2"].kind == "prescribed" and spec.points["point1"].kind == "fixed"
    assert mdr.network_spec(deck, solver="hybrid").lines["line1"].config.hybrid.n_segments == 41
    dg = line.config.dg
    assert (dg.order, dg.n_elements) == (4, 11)


def _deck(tmp_path, line_types="chain 0.1 20 1e8 0 0 1.2 1 0.1 0", points=None, lines="1 chain 1 2 100 20 -",
          options="100 WtrDpth", bodies=None):
    points = points or ["1 Fixed 0 0 -100 0 0 0 0", "2 Vessel 60 0 0 0 0 0 0"]
    text = ["--------------------- MoorDyn Input File ------", "a test deck",
            "----------------------- LINE TYPES ---------", "Name Diam Mass EA BA EI Cd Ca CdAx CaAx",
            "(-) (m) (kg/m) (N) (Ns) (Nm2) (-) (-) (-) (-)", line_types]
    if bodies:
        text += ["---------------------- BODIES ----------", "ID Att X Y Z r p y M CG I V CdA Ca",
                 "(#) (-) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kgm2) (m3) (m2) (-)"] + bodies
    text += ["---------------------- POINTS ----------", "ID Type X Y Z M V CdA Ca",
             "(#) (-) (m) (m) (m) (kg) (m3) (m2) (-)"] + points
    text += ["---------------------- LINES -----------", "ID Type A B L N Out", "(#) (-) (#) (#) (m) (-) (-)", lines,
             "---------------------- OPTIONS ---------", options, "------------------- need this line ------"]
    path = tmp_path / "deck.txt"
    path.write_text("\n".join(text) + "\n")
    return path


@pytest.mark.parametrize("kwargs, words", [
    ({"options": "1 Currents"}, "Currents"),
    ({"options": "3 WeirdOption"}, "'WeirdOption' is not a MoorDyn v2 option"),
    ({"options": "2 StatDynFricScale"}, "StatDynFricScale"),
    ({"options": "0.3 mu_kT"}, "mu_kT"),
    ({"line_types": "chain 0.1 20 ea.dat 0 0 1.2 1 0.1 0"}, "tabulated EA"),
    ({"line_types": "chain 0.1 20 1e8 0 0 1.2 1 0.1 0 0.8"}, "lift coefficient"),
    ({"lines": "1 rope 1 2 100 20 -"}, "unknown line type 'rope'"),
    ({"lines": "1 chain R1A 2 100 20 -"}, "rod"),
    ({"lines": "1 chain 1 7 100 20 -"}, "no point 7"),
    ({"points": ["1 Fixed 0 0 -100 0 0 0 0", "2 Vessel 60 0 0 0 0 0 0", "3 Fixed 9 9 -100 0 0 0 0"]},
     "point 3: no line ends"),
    ({"points": ["1 Fixed 0 0 -100 0 0 0 0", "2 Vessel 60 0 0 0 0 1 2 0 0 0"]}, "applied point force"),
    ({"points": ["1 Fixed 0 0 -100 0 0 0 0", "3 Vessel 60 0 0 0 0 0 0"]}, "point IDs must run"),
    ({"points": ["1 Fixed 0 0 -100 0 0 0 0", "2 Buoy 60 0 0 0 0 0 0"]}, "unknown point type 'Buoy'"),
])
def test_refusals_name_the_feature_and_the_line(tmp_path, kwargs, words):
    path = _deck(tmp_path, **kwargs)
    with pytest.raises(ConfigError, match=r"deck\.txt") as exc:
        mdr.network_spec(mdr.read_deck(path))
    assert words in str(exc.value)


def test_free_end_and_body(tmp_path):
    """A line hanging from a Vessel point with a free body at its end (the body's CoG 1 m below its
    attachment): the static fairlead force is the wet weight of line and body, a closed form."""
    path = _deck(tmp_path, points=["1 Body1 0 0 1 0 0 0 0", "2 Vessel 0 0 0 0 0 0 0"],
                 bodies=["1 Free 0 0 -101 0 0 0 5000 0 2000 0.5 2.0|0 0.8"], options="300 WtrDpth")
    deck = mdr.read_deck(path)
    spec = mdr.network_spec(deck)
    body = spec.bodies["body1"].props
    assert body.density == 10000.0 and body.added_mass == pytest.approx((0.8 * 1025 * 0.5,) * 3)
    assert spec.lines["line1"].ends[1].attachment == (0.0, 0.0, 1.0)
    f = mdr.static_point_forces(spec)["point2"]
    g = 9.80665
    w_line = (20.0 - 1025.0 * math.pi * 0.01 / 4) * g * 100.0
    w_body = (5000.0 - 1025.0 * 0.5) * g
    assert f == pytest.approx([0.0, 0.0, -(w_line + w_body)], rel=1e-6, abs=1e-6)
    # a free massless end: the line alone
    path = _deck(tmp_path, points=["1 Free 0 0 -100 0 0 0 0", "2 Vessel 0 0 0 0 0 0 0"], options="300 WtrDpth")
    spec = mdr.network_spec(mdr.read_deck(path))
    assert spec.lines["line1"].ends[1].kind == "free"
    assert mdr.static_point_forces(spec)["point2"] == pytest.approx([0.0, 0.0, -w_line], rel=1e-6, abs=1e-6)


def test_converter_writes_a_network_file(tmp_path):
    out = tmp_path / "wd0200.yaml"
    assert mdr.main([str(DECKS / "WD0200_Chain.txt"), "--output", str(out)]) == 0
    spec, _ = load_network_files([out])
    assert spec.lines["line1"].config.solver == "dg" and spec.lines["line1"].config.cable.length == 760.0
    assert "fileIC" in out.read_text().splitlines()[5]  # the options read and not used are listed
    assert yaml.safe_load(out.read_text())
    bad = tmp_path / "bad.yaml"
    assert mdr.main([str(DECKS / "tripod.txt"), "--output", str(bad)]) == 2 and not bad.exists()


@pytest.mark.parametrize("name", sorted(LOADS))
def test_static_fairlead_force_matches_moordyn(name):
    deck = mdr.read_deck(DECKS / name)
    ours = md.our_static(deck)
    if not ours:
        pytest.skip(f"{name} has no Vessel point (no fairlead)")
    pytest.importorskip("moordyn")
    theirs = md.moordyn_static(DECKS / name)
    for num, f in ours.items():
        assert np.linalg.norm(f) == pytest.approx(np.linalg.norm(theirs[num]), rel=0.01), f"point {num}"
