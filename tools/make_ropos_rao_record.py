"""Make data/ropos_ship_rao.mcap: a SYNTHETIC ROPOS fairlead record from the RAO ship-motion source.

The second synthetic ROPOS record (the first, data/ropos_ship_heave.mcap, is a band-limited JONSWAP heave
drawn directly at the fairlead; docs/ropos.md). This one is what a ship would do: a seeded short-crested
JONSWAP sea (Tp = 7 s as the first record, gamma 3.3, cos-2s s = 6 over 5 directions, waves from 15 deg
off the port bow) through the ILLUSTRATIVE RAO table of a ~80 m support vessel
(config/rao_support_vessel_80m.txt), carried to a stern fairlead at the still-water level 35 m aft of
midships (motion.kind rao, physics/ship_motion.py). Hs is chosen so that the largest zero-up-crossing
heave wave of the fairlead is 4.0 m (the field tests' reported maximum, as for the first record): the
response is linear in the wave amplitudes, so the record for Hs = 1 m is scaled. 10 min at 10 Hz, the
ship response ramped in (C2, 10 s) and cosine-tapered over the last 10 s so the ship ends at rest.
Positions x, y, z (m, frame map) of the fairlead; orientation identity (the pose IS the fairlead).

Usage: python tools/make_ropos_rao_record.py [--out data/ropos_ship_rao.mcap] [--seed 20200811]
"""

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from make_ropos_record import largest_wave_height, write_record  # noqa: E402

from tether_sim.config import SimConfig  # noqa: E402
from tether_sim.physics.motion import MotionConfig, build_motion  # noqa: E402
from tether_sim.physics.waves import WaveConfig, wave_components  # noqa: E402

RAO_TABLE = "config/rao_support_vessel_80m.txt"


def rao_fairlead_record(seed=20200811, duration=600.0, rate=10.0, tp=7.0, h_max=4.0, taper=10.0):
    """(t (n,), xyz (n, 3), Hs): fairlead positions of the RAO ship, scaled to the largest heave wave h_max."""
    waves = WaveConfig(kind="jonswap", Hs=1.0, Tp=tp, gamma=3.3, direction=195.0, n_frequencies=64,
                       n_directions=5, spreading=6.0, seed=seed)
    cfg = replace(SimConfig(), waves=waves)
    motion = build_motion(MotionConfig(kind="rao", rao_path=str(ROOT / RAO_TABLE), rao_lever_arm=(-35.0, 0.0, 0.0),
                                       ship_heading=0.0, ramp_time=taper), np.zeros(3), wave_components(cfg))
    n = int(round(duration * rate))
    t = np.arange(n) / rate
    xyz = np.array([motion.at(ti)[0] for ti in t])
    k = int(taper * rate)
    window = np.ones(n)
    window[n - k:] = 0.5 + 0.5 * np.cos(np.pi * np.arange(k) / k)
    xyz *= window[:, None]
    scale = h_max / largest_wave_height(xyz[:, 2])
    return t, xyz * scale, scale


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "data" / "ropos_ship_rao.mcap"))
    ap.add_argument("--seed", type=int, default=20200811)
    args = ap.parse_args(argv)
    t, xyz, hs = rao_fairlead_record(seed=args.seed)
    how = write_record(args.out, t, xyz)
    z = xyz[:, 2]
    acc = np.diff(z, 2) / (t[1] - t[0]) ** 2
    print(f"wrote {args.out} with {how}: {t.size} poses; sea Hs = {hs:.2f} m (Tp 7 s); fairlead largest heave wave "
          f"{largest_wave_height(z):.2f} m, heave std x 4 = {4 * z.std():.2f} m, range [{z.min():.2f}, {z.max():.2f}] m, "
          f"horizontal std {xyz[:, 0].std():.2f} / {xyz[:, 1].std():.2f} m; heave acceleration max {np.abs(acc).max():.2f} "
          f"m/s^2, rms {acc.std():.2f} m/s^2")


if __name__ == "__main__":
    main()
