"""Make data/ropos_ship_heave.mcap: a SYNTHETIC, seeded ship heave record for the ROPOS runs.

The field record of the ROPOS tests (Driscoll et al., PE2020 Sec. 6.1) is not published, so this
script draws an irregular sea instead: a JONSWAP heave spectrum (Tp = 7 s, gamma = 3.3) cut to the
0-0.8 Hz band PE2020 filtered to, random phases from a fixed seed, scaled so that the largest
zero-up-crossing wave (peak to trough) is 4.0 m (the field tests' reported maximum), 10 min at
10 Hz, cosine-tapered over the first and last 10 s so the ship starts and ends at rest at z = 0.
Written as geometry_msgs/msg/PoseStamped on /ship/pose, frame "map", in a rosbag2-compatible MCAP.

Usage: python tools/make_ropos_record.py [--out data/ropos_ship_heave.mcap] [--seed 20200811]
"""

import argparse
import math
from pathlib import Path

import numpy as np

TYPE_NAME = "geometry_msgs/msg/PoseStamped"
TOPIC = "/ship/pose"
START_STAMP_NS = 1_600_000_000 * 10**9  # fixed start stamp so the file is reproducible
# ros2msg schema text as rosbag2 stores it (top-level type first, then each dependency once).
POSE_STAMPED_MSGDEF = """std_msgs/Header header
Pose pose
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: geometry_msgs/Pose
Point position
Quaternion orientation
================================================================================
MSG: geometry_msgs/Point
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x 0
float64 y 0
float64 z 0
float64 w 1
"""


def jonswap(f, tp, gamma=3.3):
    """Unnormalised JONSWAP spectral shape S(f) (the heave is rescaled afterwards)."""
    fp = 1.0 / tp
    sigma = np.where(f <= fp, 0.07, 0.09)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        s = f**-5 * np.exp(-1.25 * (fp / f) ** 4) * gamma ** np.exp(-((f - fp) ** 2) / (2 * sigma**2 * fp**2))
    return np.where(f > 0, s, 0.0)


def largest_wave_height(z):
    """Largest zero-up-crossing wave height (max - min between consecutive up-crossings)."""
    up = np.where((z[:-1] < 0) & (z[1:] >= 0))[0]
    return max(z[a:b + 1].max() - z[a:b + 1].min() for a, b in zip(up[:-1], up[1:]))


def synthetic_heave(seed=20200811, duration=600.0, rate=10.0, f_max=0.8, tp=7.0, h_max=4.0, taper=10.0):
    """(t (n,), z (n,)): seeded irregular heave with the largest wave height h_max."""
    n = int(round(duration * rate))
    t = np.arange(n) / rate
    rng = np.random.default_rng(seed)
    f = np.arange(1, n // 2) / duration  # periodic in the record length
    band = f <= f_max
    amp = np.sqrt(2 * jonswap(f[band], tp) / duration)
    phase = rng.uniform(0.0, 2 * math.pi, band.sum())
    z = (amp[:, None] * np.cos(2 * math.pi * f[band][:, None] * t[None, :] + phase[:, None])).sum(axis=0)
    window = np.ones(n)
    k = int(taper * rate)
    window[:k] = 0.5 - 0.5 * np.cos(np.pi * np.arange(k) / k)
    window[n - k:] = window[:k][::-1]
    z *= window
    z *= h_max / largest_wave_height(z)
    return t, z


def pose_messages(t, z):
    """PoseStamped dicts of heave z (n,) at x = y = 0, or of positions z (n, 3)."""
    xyz = np.asarray(z, float)
    if xyz.ndim == 1:
        xyz = np.column_stack([np.zeros_like(xyz), np.zeros_like(xyz), xyz])
    for ti, (xi, yi, zi) in zip(t, xyz):
        ns = START_STAMP_NS + int(round(ti * 1e9))
        yield ns, {"header": {"stamp": {"sec": ns // 10**9, "nanosec": ns % 10**9}, "frame_id": "map"},
                   "pose": {"position": {"x": float(xi), "y": float(yi), "z": float(zi)},
                            "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}}


def write_record(path, t, z):
    """Write with tether_sim's RosMcapWriter when it can find the .msg files, else with mcap_ros2."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        from mcap_ros2._dynamic import serialize_dynamic

        from tether_sim.io.mcap_log import RosMcapWriter

        encode = serialize_dynamic(TYPE_NAME, POSE_STAMPED_MSGDEF)[TYPE_NAME]
        with RosMcapWriter(path) as writer:
            writer.add_topic(TOPIC, TYPE_NAME, qos="reliable")
            for ns, msg in pose_messages(t, z):
                writer.write(TOPIC, encode(msg), ns)
        return "RosMcapWriter"
    except (ImportError, LookupError):
        from mcap_ros2.writer import Writer

        with open(path, "wb") as f:
            writer = Writer(f)
            schema = writer.register_msgdef(TYPE_NAME, POSE_STAMPED_MSGDEF)
            for ns, msg in pose_messages(t, z):
                writer.write_message(TOPIC, schema, msg, log_time=ns, publish_time=ns)
            writer.finish()
        return "mcap_ros2.writer"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "data" / "ropos_ship_heave.mcap"))
    ap.add_argument("--seed", type=int, default=20200811)
    args = ap.parse_args(argv)
    t, z = synthetic_heave(seed=args.seed)
    how = write_record(args.out, t, z)
    spec_f = np.fft.rfftfreq(t.size, t[1] - t[0])
    energy = np.abs(np.fft.rfft(z)) ** 2
    acc = np.diff(z, 2) / (t[1] - t[0]) ** 2
    print(f"wrote {args.out} with {how}: {t.size} poses, {t[-1] + 0.1:.0f} s at 10 Hz; "
          f"largest wave {largest_wave_height(z):.2f} m, Hs = {4 * z.std():.2f} m, "
          f"range [{z.min():.2f}, {z.max():.2f}] m, energy above 0.8 Hz: {energy[spec_f > 0.8].sum() / energy.sum():.1e}; "
          f"heave acceleration max {np.abs(acc).max():.2f} m/s^2, rms {acc.std():.2f} m/s^2")


if __name__ == "__main__":
    main()
