"""Cost of the network bodies' motion topics (``/<body>/sim_twist``, ``/<body>/sim_accel``,
``/<body>/hydro_wrench``: NetworkSolver.body_motion) in the offline run of a network file.

One process, interleaved: ``--repeats`` pairs of ``run_network_offline`` (every output written to an
MCAP in a temporary folder, the points held), one with every output and one with ``tick_outputs``
asked for everything but those three topics; prints each run's real time per CPU second and the
best and median of each kind, and the ratio of the bests (the cost of the topics).

Usage: PYTHONPATH=. python benchmarks/bench_body_outputs.py [--params config/ropos_tms.yaml] [--duration 20] [--repeats 4]
"""

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tether_sim.network.params import load_network_files  # noqa: E402
from tether_sim.ros import network_outputs as outputs  # noqa: E402
from tether_sim.ros.network_offline import run_network_offline  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--params", default="config/ropos_tms.yaml")
    ap.add_argument("--duration", type=float, default=20.0, help="simulated s per run")
    ap.add_argument("--repeats", type=int, default=4, help="pairs of runs")
    args = ap.parse_args(argv)
    spec, cfg = load_network_files([args.params])
    body_topics = {f"/{b}/{k}" for b in spec.bodies for k in ("sim_twist", "sim_accel", "hydro_wrench")}
    every = outputs.tick_outputs

    class Without:
        """The topics of ``wanted`` (None: all) but the body topics (tick_outputs takes a container)."""

        def __init__(self, wanted):
            self.wanted = wanted

        def __contains__(self, topic):
            return topic not in body_topics and (self.wanted is None or topic in self.wanted)

    def without(driver, node, orientation_of=lambda name: None, wanted=None, shapes=True, visuals=True):
        return every(driver, node, orientation_of, Without(wanted), shapes, visuals)

    speeds = {"with": [], "without": []}
    with tempfile.TemporaryDirectory() as tmp:
        run_network_offline(spec, cfg, None, duration=2.0, progress=False)  # kernels loaded, caches warm
        for _ in range(args.repeats):
            for kind in ("without", "with"):
                outputs.tick_outputs = every if kind == "with" else without
                s = run_network_offline(spec, cfg, str(Path(tmp) / "run.mcap"), duration=args.duration, progress=False)
                speeds[kind].append(s["speed_cpu"])
                print(f"{kind:8s} the body topics: x{s['speed_cpu']:.2f} real time per CPU s, {s['messages']} messages",
                      flush=True)
        outputs.tick_outputs = every
    for kind, v in speeds.items():
        print(f"{kind:8s}: best x{max(v):.2f}, median x{float(np.median(v)):.2f} real time per CPU s")
    print(f"cost of the body topics: {100.0 * (max(speeds['without']) / max(speeds['with']) - 1.0):.1f} % "
          "(ratio of the bests)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
