"""The TMS file's slack excursion tether under the node soak's heave, offline: its end-tension spikes.

The network driver (no ROS) on config/ropos_tms.yaml, the ship heaving as in benchmarks/soak_node.py
(0.5 m at 0.1 Hz, from the start: a velocity step from rest), the vehicle held at its configured
position, for each excursion tether mesh ``--meshes N:P:cfl ...`` (the rest of the file as it is).
``--delay D``: the first tick comes D s late (a start-up as slow as the live node's: one
re-synchronisation, the ship blended onto its input). Prints per mesh: CPU, substeps per tick, the
cage's largest vertical speed, the largest tension at each end of the excursion tether (every
substep), the bursts above 200 N (samples more than 50 ms apart start a new one), what the driver's
detectors reported (snaps, numerical warnings with the largest), the mean end tensions, and the
median over the ticks of |median of the tick's samples - the first mesh's| (the slow force).

``--save F.npz`` keeps the first mesh's end tensions (every substep) and per-tick medians;
``--compare F.npz`` sets that saved run as the reference of the medians (another code version on
the same drive: the slow force before / after a change of the solver) and prints, per end, the
largest tension and the 99.9th percentile of both runs and the median and 99th percentile of the
per-tick |median difference|.

Usage: PYTHONPATH=. python benchmarks/excursion_rattle.py [--duration 40] [--delay 0]
       [--meshes 6:3:0.5 12:3:0.5 3:3:0.8] [--params config/ropos_tms.yaml] [--save F.npz] [--compare F.npz]
"""

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.bench_tms import Heave  # noqa: E402
from tether_sim.network.params import load_network_files  # noqa: E402
from tether_sim.physics.snap import NumericalSnapWarning, SnapEvent  # noqa: E402
from tether_sim.ros.network_driver import NetworkDriver  # noqa: E402


def with_mesh(params, n, order, cfl):
    """A copy of the network file with the excursion tether's DG mesh replaced; its path."""
    doc = yaml.safe_load(Path(params).read_text())
    section = next(v for v in doc.values() if isinstance(v, dict) and "ros__parameters" in v)
    dg = section["ros__parameters"]["network"]["lines"]["excursion"].setdefault("dg", {})
    dg.update(resolution="manual", n_elements=n, order=order, cfl=cfl)
    f = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False)  # noqa: SIM115
    yaml.safe_dump(doc, f)
    f.close()
    return f.name


def run(params, duration, delay, heave=0.5):
    spec, cfg = load_network_files([params])
    sources = {n: Heave(p.position, heave if n == "ship" else 0.0)
               for n, p in spec.points.items() if p.kind == "prescribed"}
    d = NetworkDriver(spec, cfg.node, sources=sources)
    d.start(0.0)
    chunks, cage, events = [], [], []
    tick = d.net.tick

    def recording(t, drain=True):
        out = tick(t, drain)
        chunks.append(out["excursion"]["samples"].copy())
        return out
    d.net.tick = recording
    period = 1.0 / cfg.node.output_rate
    now = delay
    c0 = time.process_time()
    while now < delay + duration - 1e-9:
        now += period
        r = d.tick(now)
        if r.error:
            raise SystemExit(f"failed: {r.error}")
        events += [ev for evs in r.events.values() for ev in evs]
        cage.append((d.stamp, d.net.bodies["cage"].state[9]))
    cpu = time.process_time() - c0
    s = np.concatenate(chunks, axis=1)
    s[0] += d.anchor
    ticks = np.floor(s[0] / period + 1e-9).astype(int)
    bounds = np.flatnonzero(np.diff(ticks)) + 1
    medians = {int(ticks[g[0]]): (np.median(s[1, g]), np.median(s[2, g])) for g in np.split(np.arange(ticks.size), bounds)}
    return dict(cpu=cpu, substeps=s.shape[1] / max(len(chunks), 1), samples=s, medians=medians,
                cage_speed=float(np.max(np.abs([v for _, v in cage]))), events=events, resyncs=d.resyncs)


def bursts(t, T, level=200.0, gap=0.05):
    idx = np.flatnonzero(T > level)
    if idx.size == 0:
        return []
    groups = np.split(idx, np.flatnonzero(np.diff(t[idx]) > gap) + 1)
    return [(float(t[g[0]]), float(T[g].max())) for g in groups]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=40.0)
    ap.add_argument("--delay", type=float, default=0.0)
    ap.add_argument("--meshes", nargs="+", default=["6:3:0.5", "12:3:0.5", "3:3:0.8"])
    ap.add_argument("--params", default=str(Path(__file__).resolve().parents[1] / "config" / "ropos_tms.yaml"))
    ap.add_argument("--save", help="keep the first mesh's samples and per-tick medians in this .npz")
    ap.add_argument("--compare", help="a --save file: the reference of the per-tick medians")
    args = ap.parse_args(argv)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}; "
          f"{args.duration:g} s, first tick {args.delay:g} s late")
    ref = None
    if args.compare:
        z = np.load(args.compare)
        ref = {int(k): tuple(v) for k, v in zip(z["ticks"], z["medians"])}
        saved = z["samples"]
        print(f"reference {args.compare}: largest tension cage end {saved[1].max():.0f} N, vehicle end "
              f"{saved[2].max():.0f} N; 99.9th percentile {np.percentile(saved[1], 99.9):.1f} / "
              f"{np.percentile(saved[2], 99.9):.1f} N; mean {saved[1].mean():.2f} / {saved[2].mean():.2f} N")
    for m in args.meshes:
        n, order, cfl = m.split(":")
        path = with_mesh(args.params, int(n), int(order), float(cfl))
        try:
            r = run(path, args.duration, args.delay)
        finally:
            os.unlink(path)
        s = r["samples"]
        snaps = [ev for ev in r["events"] if isinstance(ev, SnapEvent) and ev.location.startswith("excursion")]
        warn = [ev for ev in r["events"] if isinstance(ev, NumericalSnapWarning) and ev.location.startswith("excursion")]
        line = (f"N = {n}, P = {order}, cfl {cfl}: {r['cpu']:.1f} CPU s, {r['substeps']:.0f} substeps/tick, "
                f"re-syncs {r['resyncs']}, cage |vz| max {r['cage_speed']:.3f} m/s; largest tension cage end "
                f"{s[1].max():.0f} N, vehicle end {s[2].max():.0f} N; bursts > 200 N: cage end "
                f"{len(bursts(s[0], s[1]))}, vehicle end {len(bursts(s[0], s[2]))}; snaps {len(snaps)}, numerical "
                f"warnings {len(warn)}"
                + (f" (largest {max(w.tension_peak for w in warn):.0f} N)" if warn else "")
                + f"; mean end tensions {s[1].mean():.2f} / {s[2].mean():.2f} N")
        line += (f"; 99.9th percentile {np.percentile(s[1], 99.9):.1f} / {np.percentile(s[2], 99.9):.1f} N")
        if args.save and m == args.meshes[0]:
            keys = sorted(r["medians"])
            np.savez_compressed(args.save, samples=s, ticks=np.array(keys),
                                medians=np.array([r["medians"][k] for k in keys]))
        if ref is None:
            ref = r["medians"]
        else:
            common = sorted(set(ref) & set(r["medians"]))
            d = np.abs(np.array([np.subtract(r["medians"][k], ref[k]) for k in common]))
            what = "the saved run" if args.compare else "the first mesh"
            line += (f"; per-tick medians against {what}: median |difference| {np.median(d[:, 0]):.2f} / "
                     f"{np.median(d[:, 1]):.2f} N, 99th percentile {np.percentile(d[:, 0], 99):.2f} / "
                     f"{np.percentile(d[:, 1], 99):.2f} N")
        print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
