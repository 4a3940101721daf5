"""MoorDyn v2 input files -> a line-network parameter file (``network`` section, docs/moordyn.md).

    python -m tether_sim.network.moordyn DECK.txt --output DECK.yaml [--solver dg|hybrid]

The subset of the MoorDyn v2 format (MoorDyn's docs/inputs.rst; sections found by a ``---`` line
holding the section's name, as MoorDyn's own reader does) that maps onto the line network of
tether_sim/network/spec.py:

- LINE TYPES (10 columns): diameter d, mass per metre, EA, BA (N s, or -zeta: a damping ratio of
  MoorDyn's segment, BA = zeta (L / NumSegs) sqrt(EA m)), EI, Cd, Ca, CdAx, CaAx, all scalars. Our
  cable gets d, gamma0 = m, density = m / (pi d^2 / 4) (so weight and buoyancy are MoorDyn's),
  Cdn = Cd, Cmn = Ca, Cdt = pi CdAx (MoorDyn's axial drag acts on the area pi d, ours on d),
  Cmt = CaAx, material bilinear (MoorDyn's segments carry no compression).
- POINTS: Fixed/Anchor -> a fixed point; Vessel/Coupled/Fairlead -> a prescribed point (driven);
  Free with no mass, volume, drag area or force on exactly one line -> that line's free end;
  BodyN -> an attachment on body N.
- LINES: one network line per row, end B -> ``from`` (s = 0), end A -> ``to`` (s = L): MoorDyn's
  lines run from the anchor (A) to the fairlead (B), ours from the ship end (s = 0).
- BODIES: Free bodies, upright (zero roll, pitch, yaw), with a volume -> network bodies: mass,
  density M / V, CoG r + rCG, inertia, translational drag areas CdA (drag coefficient 1),
  added mass Ca rho V per axis.
- OPTIONS read: g/gravity, rho/WtrDnsty, WtrDpth (the seabed; as in MoorDyn at least as deep as
  the lowest point), kBot/kb (seabed stiffness), cBot/cb (seabed damping, as a ratio of critical
  per line type), FrictionCoefficient (our seabed friction, Coulomb, isotropic as MoorDyn v2's).
  Read and not used: MoorDyn's own numerics and output (dtM, CFL, tScheme, the IC generator
  options, FricDamp, writeLog, output switches): they set how MoorDyn integrates, not the physics.

Everything else is refused by name (:class:`ConfigError` "FILE:LINE: ..."): rods, failures,
bodies that are fixed, coupled, pinned or tilted, point masses and buoys, connection nodes joining
lines, nonlinear or viscoelastic EA, tabulated EI or BA, VIV lift, waves and currents (WaveKin,
Currents), 3-D seafloors, StatDynFricScale != 1, MoorDyn-F's axial/transverse friction options
and any option MoorDyn does not know.
"""

import argparse
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from tether_sim.errors import ConfigError

FIXED_WORDS = ("ANCHOR", "FIXED", "FIX")
COUPLED_WORDS = ("FAIRLEAD", "VESSEL", "VES", "COUPLED", "CPLD")
FREE_WORDS = ("POINT", "CONNECT", "CON", "FREE")

# section name -> the words of its header (MoorDyn2.cpp's findStartOfSection lists); the order
# matters only where one header could hold two names
SECTIONS = (
    ("line_types", ("LINE DICTIONARY", "LINE TYPES")),
    ("rod_types", ("ROD DICTIONARY", "ROD TYPES")),
    ("bodies", ("BODIES", "BODY LIST", "BODY PROPERTIES")),
    ("rods", ("RODS", "ROD LIST", "ROD PROPERTIES")),
    ("points", ("POINTS", "POINT LIST", "POINT PROPERTIES", "CONNECTION PROPERTIES", "NODE PROPERTIES")),
    ("lines", ("LINES", "LINE LIST", "LINE PROPERTIES")),
    ("options", ("OPTIONS",)),
    ("outputs", ("OUTPUT",)),
    ("failure", ("FAILURE",)),
    ("syrope", ("SYROPE IC",)),
    ("external", ("EXTERNAL",)),
    ("control", ("CONTROL",)),
)
REFUSED_SECTIONS = {
    "rod_types": "rods (ROD TYPES) are not supported",
    "rods": "rods (RODS) are not supported",
    "failure": "line failures (FAILURE) are not supported",
    "syrope": "the Syrope rope model (SYROPE IC) is not supported",
    "external": "external loads (EXTERNAL LOADS) are not supported",
    "control": "MoorDyn's control section (CONTROL) is not supported",
}
# options: lower-case name -> (canonical name, meaning); the physics ones are mapped
OPTIONS_MAPPED = {
    "g": "g", "gravity": "g",
    "rho": "WtrDnsty", "wtrdnsty": "WtrDnsty",
    "wtrdpth": "WtrDpth",
    "kbot": "kBot", "kb": "kBot",
    "cbot": "cBot", "cb": "cBot",
    "frictioncoefficient": "FrictionCoefficient",
    "statdynfricscale": "StatDynFricScale",
    "wavekin": "WaveKin",
    "currents": "Currents",
}
# MoorDyn's own integration, initial-condition generator and output: no physics of the line
OPTIONS_IGNORED = ("dtm", "dt", "cfl", "tscheme", "dtic", "icdt", "tmaxic", "ictmax", "cdscaleic", "icdfac",
                   "threshic", "icthresh", "gendynamicic", "icgendynamic", "fileic", "icfile", "writelog",
                   "writeunits", "dtout", "disableoutput", "disableouttime", "fricdamp", "unifycurrentgrid",
                   "dtwave")
OPTIONS_REFUSED = {
    "seafloorfile": "a 3-D seafloor (SeafloorFile) is not supported: our seabed is the plane z = -WtrDpth",
    "mu_kt": "MoorDyn-F's transverse/axial friction options are not supported: use FrictionCoefficient",
    "mu_ka": "MoorDyn-F's transverse/axial friction options are not supported: use FrictionCoefficient",
    "mu_st": "MoorDyn-F's static friction options are not supported: use FrictionCoefficient",
    "mu_sa": "MoorDyn-F's static friction options are not supported: use FrictionCoefficient",
    "mc": "MoorDyn-F's static/dynamic friction ratio (MC) is not supported",
    "cv": "MoorDyn-F's friction damping (CV) is not supported",
}
MOORDYN_DEFAULTS = {"g": 9.80665, "WtrDnsty": 1025.0, "WtrDpth": 0.0, "kBot": 3.0e6, "cBot": 3.0e5,
                    "FrictionCoefficient": 0.0, "StatDynFricScale": 1.0, "WaveKin": 0.0, "Currents": 0.0}


@dataclass(frozen=True)
class LineType:
    name: str
    diameter: float
    mass: float  # kg/m in air
    EA: float
    BA: float  # N s, or < 0: -zeta
    EI: float
    Cd: float
    Ca: float
    CdAx: float
    CaAx: float
    lineno: int


@dataclass(frozen=True)
class DeckPoint:
    number: int
    kind: str  # fixed | coupled | free | body
    body: int  # body number for kind body, else 0
    position: tuple  # world frame, or body frame (relative to the body's reference point)
    mass: float
    volume: float
    force: tuple
    CdA: float
    Ca: float
    lineno: int


@dataclass(frozen=True)
class DeckLine:
    number: int
    line_type: str
    end_a: int  # point numbers
    end_b: int
    length: float
    n_segments: int
    lineno: int


@dataclass(frozen=True)
class DeckBody:
    number: int
    kind: str
    pose: tuple  # x, y, z (m), roll, pitch, yaw (deg) of the reference point
    mass: float
    cg: tuple  # reference point -> CoG, body frame
    inertia: tuple
    volume: float
    CdA: tuple  # 6
    Ca: tuple  # 3
    lineno: int


@dataclass
class Deck:
    path: str
    line_types: dict = field(default_factory=dict)
    points: list = field(default_factory=list)
    lines: list = field(default_factory=list)
    bodies: list = field(default_factory=list)
    options: dict = field(default_factory=dict)  # canonical name -> float
    ignored_options: list = field(default_factory=list)  # names as written

    def option(self, name):
        return self.options.get(name, MOORDYN_DEFAULTS[name])

    def point(self, number):
        return self.points[number - 1]


def _err(deck_path, lineno, msg):
    return ConfigError(f"{deck_path}:{lineno}: {msg}")


def _number(tok, what, where):
    try:
        value = float(tok)
    except ValueError:
        raise ConfigError(f"{where}: {what}: {tok!r} is not a number") from None
    if not math.isfinite(value):
        raise ConfigError(f"{where}: {what}: {tok!r} is not finite")
    return value


def _line_number_value(tok, what, where, kind):
    """A LINE TYPES column that MoorDyn also accepts as a curve (a file name) or bar-separated list."""
    if "|" in tok:
        raise ConfigError(f"{where}: {what}: {tok!r}: a bar-separated {kind} (viscoelastic or "
                          "load-dependent model) is not supported")
    try:
        return _number(tok, what, where)
    except ConfigError:
        raise ConfigError(f"{where}: {what}: {tok!r}: a tabulated {kind} (curve file) is not "
                          "supported, only a constant") from None


def _split_word(word):
    """'Body12' -> ('BODY', 12); 'Fixed' -> ('FIXED', None); '3' -> ('', 3); 'R1A' -> ('R', 1) + tail."""
    m = re.fullmatch(r"([A-Za-z]*)(\d*)([A-Za-z]*)", word)
    if not m:
        return word.upper(), None, ""
    return m.group(1).upper(), (int(m.group(2)) if m.group(2) else None), m.group(3).upper()


def _section_of(header):
    up = header.upper()
    for name, words in SECTIONS:
        if any(w in up for w in words):
            return name
    return None


def read_deck(path) -> Deck:
    """Parse a MoorDyn v2 input file into a :class:`Deck`; a feature outside the subset (module
    docstring) raises ConfigError naming the file, the line and the feature."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read MoorDyn input file ({exc})") from exc
    lines = text.splitlines()
    deck = Deck(str(path))
    section, skip, seen_keyword = None, 0, False
    for i, raw in enumerate(lines):
        lineno = i + 1
        if "---" in raw:
            section = _section_of(raw)
            if section is None and seen_keyword:
                section = "end" if "NEED THIS LINE" in raw.upper() else "unknown:" + raw.strip("- \t")
            seen_keyword = seen_keyword or section is not None
            skip = 0 if section in (None, "options", "outputs", "end") or str(section).startswith("unknown") else 2
            continue
        if section is None or section == "end":
            continue  # title block, or after the end marker
        if skip:
            skip -= 1
            continue
        tokens = raw.split()
        if not tokens:
            continue
        where = f"{path}:{lineno}"
        if section.startswith("unknown:"):
            raise _err(path, lineno, f"section {section[8:]!r} is not a MoorDyn v2 section this reader knows")
        if section in REFUSED_SECTIONS:
            raise _err(path, lineno, REFUSED_SECTIONS[section])
        if section == "line_types":
            _read_line_type(deck, tokens, where, lineno)
        elif section == "points":
            _read_point(deck, tokens, where, lineno)
        elif section == "lines":
            _read_line(deck, tokens, where, lineno)
        elif section == "bodies":
            _read_body(deck, tokens, where, lineno)
        elif section == "options":
            _read_option(deck, tokens, where)
        # outputs: MoorDyn's output channels, nothing of the model
    if not deck.lines:
        raise ConfigError(f"{path}: no LINES section with lines (is this a MoorDyn v2 input file?)")
    _check_deck(deck)
    return deck


def _read_line_type(deck, tok, where, lineno):
    if len(tok) < 10:
        raise ConfigError(f"{where}: a line type needs 10 columns (Name Diam Mass/m EA BA EI Cd Ca CdAx CaAx), "
                          f"got {len(tok)}")
    name = tok[0]
    if len(tok) > 10 and _number(tok[10], f"line type {name!r} lift coefficient Cl", where) != 0.0:
        raise ConfigError(f"{where}: line type {name!r}: vortex-induced vibration (lift coefficient Cl, "
                          "column 11) is not supported")
    what = f"line type {name!r}"
    if tok[3].upper().startswith("SYROPE"):
        raise ConfigError(f"{where}: {what}: the Syrope rope model is not supported")
    EA = _line_number_value(tok[3], f"{what} EA", where, "EA")
    BA = _line_number_value(tok[4], f"{what} BA/-zeta", where, "BA")
    EI = _line_number_value(tok[5], f"{what} EI", where, "EI")
    vals = [_number(t, f"{what} column {k + 1}", where) for k, t in ((1, tok[1]), (2, tok[2]), (6, tok[6]),
                                                                      (7, tok[7]), (8, tok[8]), (9, tok[9]))]
    d, m, Cd, Ca, CdAx, CaAx = vals
    if d <= 0.0 or m <= 0.0 or EA <= 0.0:
        raise ConfigError(f"{where}: {what}: diameter, mass per metre and EA must be positive")
    if name in deck.line_types:
        raise ConfigError(f"{where}: line type {name!r} defined twice")
    deck.line_types[name] = LineType(name, d, m, EA, BA, EI, Cd, Ca, CdAx, CaAx, lineno)


def _read_point(deck, tok, where, lineno):
    if len(tok) < 9:
        raise ConfigError(f"{where}: a point needs 9 columns (ID Type X Y Z Mass Volume CdA Ca), got {len(tok)}")
    number = int(_number(tok[0], "point ID", where))
    if number != len(deck.points) + 1:
        raise ConfigError(f"{where}: point IDs must run 1, 2, 3, ... (got {number})")
    word, num, _ = _split_word(tok[1])
    if word in FIXED_WORDS:
        kind, body = "fixed", 0
    elif word in COUPLED_WORDS:
        kind, body = "coupled", 0
    elif word in FREE_WORDS:
        kind, body = "free", 0
    elif word == "BODY":
        if not num:
            raise ConfigError(f"{where}: point {number}: 'Body' without a body number")
        kind, body = "body", num
    else:
        raise ConfigError(f"{where}: point {number}: unknown point type {tok[1]!r}")
    pos = tuple(_number(t, f"point {number} position", where) for t in tok[2:5])
    mass = _number(tok[5], f"point {number} Mass", where)
    vol = _number(tok[6], f"point {number} Volume", where)
    if len(tok) >= 12:
        force = tuple(_number(t, f"point {number} force", where) for t in tok[7:10])
        CdA, Ca = (_number(tok[10], f"point {number} CdA", where), _number(tok[11], f"point {number} Ca", where))
    else:
        force = (0.0, 0.0, 0.0)
        CdA, Ca = (_number(tok[7], f"point {number} CdA", where), _number(tok[8], f"point {number} Ca", where))
    deck.points.append(DeckPoint(number, kind, body, pos, mass, vol, force, CdA, Ca, lineno))


def _read_line(deck, tok, where, lineno):
    if len(tok) < 6:
        raise ConfigError(f"{where}: a line needs the columns ID LineType AttachA AttachB UnstrLen NumSegs")
    number = int(_number(tok[0], "line ID", where))
    if number != len(deck.lines) + 1:
        raise ConfigError(f"{where}: line IDs must run 1, 2, 3, ... (got {number})")
    if tok[1] not in deck.line_types:
        raise ConfigError(f"{where}: line {number}: unknown line type {tok[1]!r} "
                          f"(known: {', '.join(deck.line_types) or 'none'})")
    ends = []
    for col in (2, 3):
        word, num, tail = _split_word(tok[col])
        if word in ("R", "ROD"):
            raise ConfigError(f"{where}: line {number}: an end on a rod ({tok[col]}) is not supported")
        if word not in ("", "C", "CON", "P", "POINT") or num is None or tail:
            raise ConfigError(f"{where}: line {number}: end {tok[col]!r} is not a point number")
        if not 1 <= num <= len(deck.points):
            raise ConfigError(f"{where}: line {number}: there is no point {num}")
        ends.append(num)
    length = _number(tok[4], f"line {number} UnstrLen", where)
    nseg = int(_number(tok[5], f"line {number} NumSegs", where))
    if length <= 0.0 or nseg < 1:
        raise ConfigError(f"{where}: line {number}: UnstrLen and NumSegs must be positive")
    deck.lines.append(DeckLine(number, tok[1], ends[0], ends[1], length, nseg, lineno))


def _bar_list(tok, counts, what, where):
    vals = [_number(t, what, where) for t in tok.split("|")]
    if len(vals) not in counts:
        raise ConfigError(f"{where}: {what}: {len(vals)} values, expected {' or '.join(map(str, counts))}")
    return vals


def _read_body(deck, tok, where, lineno):
    if len(tok) < 14:
        raise ConfigError(f"{where}: a body needs 14 columns (ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG I Volume "
                          f"CdA Ca), got {len(tok)}")
    number = int(_number(tok[0], "body ID", where))
    if number != len(deck.bodies) + 1:
        raise ConfigError(f"{where}: body IDs must run 1, 2, 3, ... (got {number})")
    word, _, _ = _split_word(tok[1])
    kind = ("fixed" if word in FIXED_WORDS else "coupled" if word in ("VESSEL", "VES", "COUPLED", "CPLD")
            else "pinned" if word in ("VESSELPINNED", "VESPIN", "CPLDPIN", "COUPLEDPINNED") else "free")
    what = f"body {number}"
    pose = tuple(_number(t, f"{what} pose", where) for t in tok[2:8])
    mass = _number(tok[8], f"{what} Mass", where)
    cg = _bar_list(tok[9], (1, 3), f"{what} CG", where)
    cg = (0.0, 0.0, cg[0]) if len(cg) == 1 else tuple(cg)
    inertia = _bar_list(tok[10], (1, 3), f"{what} I", where)
    inertia = tuple(inertia * 3) if len(inertia) == 1 else tuple(inertia)
    volume = _number(tok[11], f"{what} Volume", where)
    cda = _bar_list(tok[12], (1, 2, 3, 6), f"{what} CdA", where)
    cda = {1: lambda c: c * 6, 2: lambda c: [c[0]] * 3 + [c[1]] * 3, 3: lambda c: c + c, 6: lambda c: c}[len(cda)](cda)
    ca = _bar_list(tok[13], (1, 3), f"{what} Ca", where)
    ca = tuple(ca * 3) if len(ca) == 1 else tuple(ca)
    deck.bodies.append(DeckBody(number, kind, pose, mass, cg, inertia, volume, tuple(cda), ca, lineno))


def _read_option(deck, tok, where):
    if len(tok) < 2:
        return  # MoorDyn ignores such a line too
    value, name = tok[0], tok[1]
    low = name.lower()
    if low in OPTIONS_REFUSED:
        raise ConfigError(f"{where}: option {name}: {OPTIONS_REFUSED[low]}")
    if low in OPTIONS_IGNORED:
        deck.ignored_options.append(name)
        return
    if low not in OPTIONS_MAPPED:
        raise ConfigError(f"{where}: option {name!r} is not a MoorDyn v2 option this reader knows")
    canon = OPTIONS_MAPPED[low]
    deck.options[canon] = _number(value, f"option {name}", where)


def _check_deck(deck):
    p = deck.path
    if deck.option("WaveKin") != 0.0:
        raise ConfigError(f"{p}: option WaveKin = {deck.option('WaveKin'):g}: MoorDyn's wave kinematics are not "
                          "supported (waves: our waves.* keys)")
    if deck.option("Currents") != 0.0:
        raise ConfigError(f"{p}: option Currents = {deck.option('Currents'):g}: MoorDyn's current input files "
                          "are not supported (currents: our environment.current_* keys)")
    if deck.option("StatDynFricScale") != 1.0:
        raise ConfigError(f"{p}: option StatDynFricScale = {deck.option('StatDynFricScale'):g}: a static friction "
                          "different from the dynamic one is not supported")
    for b in deck.bodies:
        where = f"{p}:{b.lineno}: body {b.number}"
        if b.kind != "free":
            raise ConfigError(f"{where}: a {b.kind} body is not supported (only free bodies)")
        if any(a != 0.0 for a in b.pose[3:]):
            raise ConfigError(f"{where}: an initially rotated body (roll, pitch, yaw != 0) is not supported")
        if any(c != 0.0 for c in b.CdA[3:]):
            raise ConfigError(f"{where}: rotational drag (CdA about the axes) is not supported")
        if b.volume <= 0.0 or b.mass <= 0.0:
            raise ConfigError(f"{where}: a body needs a positive mass and volume (ours have a density)")
        if min(b.inertia) <= 0.0:
            raise ConfigError(f"{where}: a body needs positive moments of inertia")
    ends = {}
    for ln in deck.lines:
        for end in (ln.end_a, ln.end_b):
            ends.setdefault(end, []).append(ln.number)
    for pt in deck.points:
        where = f"{p}:{pt.lineno}: point {pt.number}"
        if any(f != 0.0 for f in pt.force):
            raise ConfigError(f"{where}: an applied point force is not supported")
        if pt.kind == "body" and pt.body > len(deck.bodies):
            raise ConfigError(f"{where}: there is no body {pt.body}")
        if pt.kind == "free":
            if pt.mass != 0.0 or pt.volume != 0.0 or pt.CdA != 0.0:
                raise ConfigError(f"{where}: a free point with mass, volume or drag area (a clump weight or "
                                  "buoy) is not supported")
            if len(ends.get(pt.number, [])) != 1:
                raise ConfigError(f"{where}: a free point joining {len(ends.get(pt.number, []))} line ends "
                                  "(a connection node) is not supported; a free point ends one line")
        elif pt.mass != 0.0 or pt.volume != 0.0 or pt.CdA != 0.0:
            raise ConfigError(f"{where}: mass, volume or drag area on a {pt.kind} point is not supported")
        if pt.kind != "free" and pt.number not in ends:
            raise ConfigError(f"{where}: no line ends on this point")
    for b in deck.bodies:
        if not any(pt.kind == "body" and pt.body == b.number for pt in deck.points):
            raise ConfigError(f"{p}:{b.lineno}: body {b.number}: no point (and so no line) on it")


def water_depth(deck):
    """MoorDyn's seabed depth: WtrDpth, deepened to the lowest fixed or coupled point below it."""
    depth = deck.option("WtrDpth")
    for pt in deck.points:
        if pt.kind != "body" and -pt.position[2] > depth:
            depth = -pt.position[2]
    return depth


def line_damping(lt: LineType, ln: DeckLine):
    """Axial material damping zeta (N s) of a line: BA, or for BA < 0 MoorDyn's
    -BA (L / NumSegs) sqrt(EA m) (a damping ratio of its segment)."""
    if lt.BA >= 0.0:
        return lt.BA
    return -lt.BA * ln.length / ln.n_segments * math.sqrt(lt.EA * lt.mass)


def seabed_damping_ratio(deck, lt: LineType):
    """cBot (Pa s/m, force per metre cBot d v) as a ratio of our critical 2 sqrt(kBot d gamma0)."""
    kb, cb = deck.option("kBot"), deck.option("cBot")
    if kb <= 0.0:
        return 0.0
    return cb * lt.diameter / (2.0 * math.sqrt(kb * lt.diameter * lt.mass))


def _name(kind, number):
    return f"{kind}{number}"


def to_network(deck: Deck, solver: str = "dg", dg_order: int = 4) -> dict:
    """The ``network`` mapping (tether_sim/network/spec.py) of a deck.

    Mesh: dg (the default): order ``dg_order`` and n_elements = ceil(NumSegs / order) (about NumSegs
    nodes along the line); hybrid: n_segments = NumSegs. The hybrid solver's initial relaxation does
    not converge on MoorDyn's chain decks with seabed friction (docs/moordyn.md)."""
    if solver not in ("hybrid", "dg"):
        raise ConfigError(f"solver: {solver!r} is not one of hybrid, dg")
    depth = water_depth(deck)
    used = sorted({ln.line_type for ln in deck.lines})
    ratios = {t: seabed_damping_ratio(deck, deck.line_types[t]) for t in used}
    ratio = ratios[used[0]]
    if any(abs(r - ratio) > 1e-9 * max(1.0, abs(ratio)) for r in ratios.values()):
        listed = ", ".join(f"{t}: {r:.4g}" for t, r in ratios.items())
        raise ConfigError(f"{deck.path}: option cBot: the line types' seabed damping ratios differ ({listed}); "
                          "our seabed damping is one ratio of critical per environment")
    env = {
        "g": deck.option("g"),
        "fluid_density": deck.option("WtrDnsty"),
        "seabed": True,
        "seabed_z": -depth,
        "seabed_stiffness": deck.option("kBot"),
        "seabed_damping": ratio,
        "seabed_friction": deck.option("FrictionCoefficient"),
        # MoorDyn v2 lines carry water only below z = 0 (no air loads above it)
        "free_surface": True,
        "air_density": 0.0,
        "air_Cdn": 0.0,
        "air_Cdt": 0.0,
    }
    points, bodies, lines = {}, {}, {}
    for pt in deck.points:
        if pt.kind in ("fixed", "coupled"):
            points[_name("point", pt.number)] = {"kind": "fixed" if pt.kind == "fixed" else "prescribed",
                                                 "position": [float(x) for x in pt.position]}
    rho = deck.option("WtrDnsty")
    for b in deck.bodies:
        cog = [b.pose[k] + b.cg[k] for k in range(3)]
        bodies[_name("body", b.number)] = {
            "mass": b.mass,
            "density": b.mass / b.volume,
            "added_mass": [c * rho * b.volume for c in b.Ca],
            "drag_coefficients": [1.0, 1.0, 1.0],
            "drag_areas": [float(c) for c in b.CdA[:3]],
            "inertia": [float(i) for i in b.inertia],
            "initial_position": [float(x) for x in cog],
        }
    for ln in deck.lines:
        lt = deck.line_types[ln.line_type]
        entry = {}
        for key, number in (("from", ln.end_b), ("to", ln.end_a)):
            pt = deck.point(number)
            if pt.kind == "free":
                entry[key] = "free"
            elif pt.kind == "body":
                b = deck.bodies[pt.body - 1]
                entry[key] = _name("body", pt.body)
                entry[f"{key}_attachment"] = [float(pt.position[k] - b.cg[k]) for k in range(3)]
            else:
                entry[key] = _name("point", number)
        entry["solver"] = solver
        entry["cable"] = {
            "length": ln.length,
            "EA": lt.EA,
            "gamma0": lt.mass,
            "diameter": lt.diameter,
            "density": lt.mass / (math.pi * lt.diameter ** 2 / 4.0),
            "EI": lt.EI,
            "damping": line_damping(lt, ln),
            "material": "bilinear",
            "Cdn": lt.Cd,
            "Cdt": math.pi * lt.CdAx,
            "Cmn": lt.Ca,
            "Cmt": lt.CaAx,
        }
        if solver == "hybrid":
            entry["hybrid"] = {"n_segments": max(2, ln.n_segments)}
        else:
            entry["dg"] = {"order": dg_order, "n_elements": max(1, math.ceil(ln.n_segments / dg_order))}
        lines[_name("line", ln.number)] = entry
    tree = {"environment": env, "points": points, "lines": lines}
    if bodies:
        tree["bodies"] = bodies
    return tree


def network_spec(deck: Deck, solver: str = "dg", overrides: dict | None = None):
    """The validated NetworkSpec of a deck (``overrides``: {line key path: value} merged into every
    line, e.g. {"hybrid": {"n_segments": 80}})."""
    from tether_sim.network.spec import parse_network

    tree = to_network(deck, solver)
    if overrides:
        for entry in tree["lines"].values():
            for k, v in overrides.items():
                if isinstance(v, dict):
                    entry.setdefault(k, {}).update(v)
                else:
                    entry[k] = v
    try:
        return parse_network(tree)
    except ConfigError as exc:
        raise ConfigError(f"{deck.path}: {exc}") from exc


def static_point_forces(spec):
    """{point name: net static force (3,) of the lines on it} for the fixed and prescribed points of a
    network (every line's static shape between its ends; bodies in their static equilibrium)."""
    import numpy as np

    from tether_sim.network.body import NetworkBody
    from tether_sim.network.statics import NetworkStatics, solve_network_statics

    bodies = {n: NetworkBody(n, b.props, spec.environment, [e.attachment for e in spec.ends_on(n)])
              for n, b in spec.bodies.items()}
    statics = solve_network_statics(spec, bodies)[0] if bodies else NetworkStatics(spec, bodies)
    states = {n: b.state.copy() for n, b in bodies.items()}
    out = {n: np.zeros(3) for n in spec.points}
    for name, (_, _, forces) in statics.shapes(states).items():
        for end, f in zip(spec.lines[name].ends, forces):
            if end.kind == "point":
                out[end.target] += f
    return out


def params_text(deck: Deck, solver: str = "dg") -> str:
    """A ROS 2 parameter file (network section) for the deck, with a header naming its source."""
    tree = {"/**/tether_sim": {"ros__parameters": {"network": to_network(deck, solver)}}}
    head = [f"# Converted from the MoorDyn v2 input file {Path(deck.path).name}",
            "#   python -m tether_sim.network.moordyn DECK --output FILE (docs/moordyn.md)",
            "# MoorDyn points -> points (Fixed: fixed, Vessel/Coupled: prescribed); line end B (the fairlead)",
            "# = from (s = 0), end A = to; seabed at z = -WtrDpth with kBot, cBot (as a ratio of critical)",
            "# and FrictionCoefficient."]
    if deck.ignored_options:
        head.append("# MoorDyn numerics/output options read and not used: " + ", ".join(deck.ignored_options))
    return "\n".join(head) + "\n" + yaml.safe_dump(tree, sort_keys=False, default_flow_style=None)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m tether_sim.network.moordyn",
                                 description="Convert a MoorDyn v2 input file to a line-network parameter file.")
    ap.add_argument("deck", help="MoorDyn v2 input file")
    ap.add_argument("--output", "-o", required=True, help="parameter file to write (YAML)")
    ap.add_argument("--solver", default="dg", choices=("dg", "hybrid"),
                    help="solver of every line (default dg; docs/moordyn.md)")
    args = ap.parse_args(argv)
    try:
        deck = read_deck(args.deck)
        text = params_text(deck, args.solver)
        network_spec(deck, args.solver)  # validate before writing
    except ConfigError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    Path(args.output).write_text(text)
    print(f"wrote {args.output}: {len(deck.lines)} line(s), {len(deck.points)} point(s), {len(deck.bodies)} body(ies)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
