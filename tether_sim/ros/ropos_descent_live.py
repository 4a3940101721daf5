"""The ROPOS descent live: config/ropos_descent.yaml through the node, driven by a replay.

    .venv/bin/python -m tether_sim.ros.ropos_descent_live [--rate 4] [--duration S] [--out DIR]

Writes the fairlead's heave of the parameter file (``motion``: 2 m, 0.2 Hz, ramped) as
geometry_msgs/PoseStamped on /ship/pose at 10 Hz into ``<out>/ship_heave.mcap``, then runs the
main job's pipeline on it (:mod:`tether_sim.ros.main_job`: recorder, node with ``use_sim_time``,
replay with /clock at ``--rate``, report). The node's winch follows the schedule of the parameter
file from the node's start. The offline run of the same scenario is
``benchmarks/bench_ropos_descent.py`` (or ``tether-sim-offline --params config/ropos_descent.yaml``).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from tether_sim.io.params import load_config
from tether_sim.physics.motion import build_motion

ROOT = Path(__file__).resolve().parents[2]
START_NS = 1_600_000_000 * 10**9  # the record's first stamp (as tools/make_ropos_record.py)


def write_heave_record(config, path: Path, duration: float, rate: float = 10.0) -> Path:
    """PoseStamped of the configured ship motion on /ship/pose, frame map, ``duration`` s at ``rate`` Hz."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.serialization import serialize_message

    from tether_sim.io.mcap_log import RosMcapWriter
    from tether_sim.ros.convert import time_msg

    motion = build_motion(config.motion, np.asarray(config.ship_end.position, float))
    path.parent.mkdir(parents=True, exist_ok=True)
    with RosMcapWriter(path) as writer:
        writer.add_topic("/ship/pose", "geometry_msgs/msg/PoseStamped", "reliable")
        for k in range(int(round(duration * rate)) + 1):
            t = k / rate
            p = motion.at(t)[0]
            msg = PoseStamped()
            msg.header.stamp, msg.header.frame_id = time_msg(START_NS * 1e-9 + t), config.node.world_frame
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(x) for x in p)
            msg.pose.orientation.w = 1.0
            ns = START_NS + int(round(t * 1e9))
            writer.write("/ship/pose", serialize_message(msg), ns, ns)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m tether_sim.ros.ropos_descent_live", description=__doc__.split("\n")[0])
    ap.add_argument("--params", default="config/ropos_descent.yaml")
    ap.add_argument("--rate", type=float, default=4.0, help="replay speed factor (default: %(default)s)")
    ap.add_argument("--duration", type=float, default=None, help="replayed s (default: the file's duration)")
    ap.add_argument("--out", default="out/ropos_descent_live")
    args = ap.parse_args(argv)
    config = load_config(ROOT / args.params)
    duration = config.duration if args.duration is None else args.duration
    record = write_heave_record(config, (ROOT / args.out / "ship_heave.mcap").resolve(), duration + 5.0)
    from tether_sim.ros import main_job  # noqa: E402

    return main_job.main(["--params", args.params, "--record", str(record), "--rate", str(args.rate),
                          "--start-offset", "0", "--duration", str(duration), "--out", args.out])


if __name__ == "__main__":
    sys.exit(main())
