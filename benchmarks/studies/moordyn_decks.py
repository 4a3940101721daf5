"""MoorDyn's own test decks through our reader: which load, and their static fairlead forces against MoorDyn's.

For every MoorDyn v2 input file under test/data/moordyn/decks/ (MoorDyn's tests/Mooring/, BSD-3,
test/data/moordyn/SOURCE.md): read it with tether_sim.network.moordyn; a deck outside the subset is
listed with the feature that refused it. For the decks that load, the static force of the lines on
each coupled (Vessel) point, ours (elastic catenaries with the frictionless seabed of
physics/statics.py, tether_sim.network.moordyn.static_point_forces) against pip moordyn's (moordyn.Init:
its initial-condition solve, then GetPointForce of the point). MoorDyn's stored initial conditions
(the fileIC option) are dropped, so it starts from its own catenary.

Usage: PYTHONPATH=. python benchmarks/studies/moordyn_decks.py [--decks DIR]
"""

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.bench_moordyn import c_stdout_silenced  # noqa: E402
from tether_sim.errors import ConfigError  # noqa: E402
from tether_sim.network.moordyn import network_spec, read_deck, static_point_forces  # noqa: E402

DECKS = Path(__file__).resolve().parents[2] / "test" / "data" / "moordyn" / "decks"


def deck_files(root=DECKS):
    """Every MoorDyn input file (a LINE TYPES section) under root, sorted."""
    out = []
    for f in sorted(list(root.rglob("*.txt")) + list(root.rglob("*.dat"))):
        text = f.read_text(errors="replace").upper()
        if "LINE TYPES" in text or "LINE DICTIONARY" in text:
            out.append(f)
    return out


def _without_file_ic(text):
    """The deck text without its fileIC / ICfile option line (MoorDyn's stored initial state)."""
    keep = []
    for line in text.splitlines():
        tok = line.split()
        if len(tok) >= 2 and tok[1].lower() in ("fileic", "icfile"):
            continue
        keep.append(line)
    return "\n".join(keep) + "\n"


def moordyn_static(deck_path):
    """{point number: force (3,) on it} of MoorDyn's initial state, for its coupled points."""
    import moordyn

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / Path(deck_path).name
        path.write_text(_without_file_ic(Path(deck_path).read_text(errors="replace")))
        with c_stdout_silenced():
            system = moordyn.Create(str(path))
            coupled, x = [], []
            for i in range(1, moordyn.GetNumberPoints(system) + 1):
                p = moordyn.GetPoint(system, i)
                if moordyn.GetPointType(p) == moordyn.POINT_TYPE_COUPLED:
                    coupled.append(i)
                    x += list(moordyn.GetPointPos(p))
            err = moordyn.Init(system, x, [0.0] * len(x))
            forces = {i: np.array(moordyn.GetPointForce(moordyn.GetPoint(system, i))) for i in coupled}
            moordyn.Close(system)
    if err != 0:
        raise RuntimeError(f"{deck_path}: moordyn.Init failed with code {err}")
    return forces


def our_static(deck):
    """{point number: force (3,) on it} of our static state, for the deck's coupled points ({} if it
    has none: no fairlead)."""
    if not any(pt.kind == "coupled" for pt in deck.points):
        return {}
    forces = static_point_forces(network_spec(deck))
    return {pt.number: forces[f"point{pt.number}"] for pt in deck.points if pt.kind == "coupled"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--decks", default=str(DECKS))
    args = ap.parse_args(argv)
    root = Path(args.decks)
    print("| deck | lines | coupled point | ours (kN) | MoorDyn (kN) | difference |")
    print("|---|---:|---:|---:|---:|---:|")
    refused = []
    for f in deck_files(root):
        rel = f.relative_to(root)
        try:
            deck = read_deck(f)
            ours = our_static(deck)
        except ConfigError as exc:
            refused.append((rel, str(exc).split(": ", 1)[1] if ": " in str(exc) else str(exc)))
            continue
        if not ours:
            print(f"| {rel} | {len(deck.lines)} | none (no Vessel point) | | | |")
            continue
        theirs = moordyn_static(f)
        for num, F in ours.items():
            a, b = np.linalg.norm(F), np.linalg.norm(theirs[num])
            print(f"| {rel} | {len(deck.lines)} | {num} | {a / 1e3:.2f} | {b / 1e3:.2f} | {100 * (a / b - 1):+.2f} % |")
    print("\nRefused:")
    for rel, why in refused:
        print(f"- {rel}: {why}")


if __name__ == "__main__":
    main()
