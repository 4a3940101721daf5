"""The simulation node's tick cost without the timer and DDS timing: the real node driven by hand.

``bench_node.py`` measures the node as it runs (its own process, a 50 Hz timer, poses from another
process); its tick figures carry the machine's scheduling and the DDS threads. This script builds the
same node (``TetherSimNode`` from the parameter file, every output it publishes) in one process, gives
it a simulated clock (``_now`` returns a counter advanced by one output period per tick) and feeds it
the ship pose on the file's motion (``_on_pose`` with a PoseStamped, as the subscription would), then
calls the timer's callback ``_on_tick`` in a loop and takes its thread CPU time. A sink process
subscribes (raw bytes, no decoding) to every periodic output and /tf, so the node builds and
publishes everything a recorder or RViz would get, to another process as they would. Per tick it also times the
solver's parts (``advance_to``; ``state``; ``end_forces`` / ``body_state`` / ``drain_end_tensions``)
and the publish calls (``--split``) so the node's own work is the difference; the 1 Hz diagnostics and the pose callback are
timed apart.

Every live file runs: a line-network file (config/ropos_tms.yaml) builds the network node
(``NetworkSimNode``; the sink subscribes to its lines' and points' topics) with the ship on the live files'
fairlead circle (a = 2 m, 0.2 Hz) and the other driven points held; a file whose ship follows its RAO
response to the configured sea (``motion.kind rao``, config/ropos_forecast.yaml) gets no ship pose (the
forecast's look-ahead runs in its worker thread, outside the tick's thread CPU); any other driven end (a
vehicle on vehicle/pose) is held at its configured position.

``--profile N``: cProfile of N ticks after the timed ones (the functions by own time; environment
BENCH_PROFILE_TIMER=thread times them in thread CPU, BENCH_PROFILE_SORT / BENCH_PROFILE_ROWS order and cut the list).
``--baseline DIR``: a second node from another checkout's ``tether_sim`` (renamed copy, as
bench_tick.load_baseline; its first run compiles its kernels) in the same process, the two ticked
alternately, so that their ratio does not depend on the machine's load. ``--baseline same``: the second
node is this tree's without the ``-p`` parameters (e.g. ``-p node.shape_rate:=10`` against the default;
not with ``--split``, whose wrappers are per module).

Usage: nice -n 10 .venv/bin/python benchmarks/bench_node_tick.py [--params config/ropos_L200.yaml ...]
           [--ticks 1500] [--alpha 0] [--repeat 3] [--baseline ../other-checkout] [--profile 500] [--split]
           [-p node.shape_rate:=10]
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from benchmarks.bench_node import EI_STAR, instrument  # noqa: E402


def _timed_class(cls, timed):
    """``cls`` whose methods time themselves under "output frame: <method>"."""
    class Timed(cls):
        pass
    for name, fn in vars(cls).items():
        if callable(fn) and not name.startswith("__"):
            setattr(Timed, name, timed(fn, f"output frame: {name}"))
    Timed.__init__ = timed(cls.__init__, "output frame: construction")
    return Timed


def is_network(params) -> bool:
    from tether_sim.network.params import file_is_network

    return file_is_network(str(params))


def network_ship_motion(position):
    """The ship's motion on a line-network file (which has no motion section): the live files' fairlead
    circle, radius 2 m at 0.2 Hz in the vertical x-z plane, ramped over 5 s (config/ropos_L1730.yaml)."""
    from tether_sim.physics.motion import MotionConfig, build_motion

    return build_motion(MotionConfig(kind="circle", amplitude=2.0, frequency=0.2, ramp_time=5.0), tuple(position))


class _Bench:
    """One node of one tree, its simulated clock and pose feed, and its per-tick figures."""

    def __init__(self, pkg, params, alpha, split, overrides=()):
        import importlib

        from geometry_msgs.msg import PoseStamped

        self.pkg = pkg
        sim_node = importlib.import_module(f"{pkg}.ros.sim_node")
        self.convert = importlib.import_module(f"{pkg}.ros.convert")
        build_solver = importlib.import_module(f"{pkg}.solvers.factory").build_solver
        build_motion = importlib.import_module(f"{pkg}.physics.motion").build_motion
        self.parts = {"advance": 0.0, "state": 0.0, "outputs": 0.0, "publish": 0.0}
        parts = self.parts

        def timed(fn, *keys):
            def wrapper(*a, **k):
                c = time.thread_time()
                out = fn(*a, **k)
                dt = time.thread_time() - c
                for key in keys:
                    parts[key] = parts.get(key, 0.0) + dt
                return out
            return wrapper

        self.network = is_network(params)
        if self.network:  # a line network (docs/network.md): its own node; every periodic output of every line
            if overrides:
                raise SystemExit(f"{params}: a line network takes no -p here")
            network_node = importlib.import_module(f"{pkg}.ros.network_node")
            self.node = network_node.NetworkSimNode(files=[str(params)])
            periodic = [t for t in self.node.pubs if not t.endswith(("/description", "/snap_events", "/slack_warnings"))
                        and t != "/diagnostics"]
            self.publishers = [self.node.pubs[t] for t in periodic] + ([self.node.tf_pub] if self.node.tf_pub else [])
            if split:
                self._split_network(pkg, timed)
        else:
            self.node = sim_node.TetherSimNode(where=str(params), solver_factory=instrument(build_solver, timed) if split else build_solver,
                                               parameter_overrides=list(overrides))
            wanted = [t for t in self.node.pubs if t in self.convert.SHAPE_TOPICS or t.endswith(("_wrench", "sim_pose"))]
            self.publishers = [self.node.pubs[t] for t in wanted] + ([self.node.tf.pub] if self.node.tf.enabled else [])
        cfg = self.cfg = self.node.config
        if split and not self.network:
            for publisher in self.publishers:
                publisher.publish = timed(publisher.publish, "publish", "publish " + publisher.topic_name)
            # inclusive parts of the node's tick (each holds the solver calls and publishes made inside it)
            node, driver = self.node, self.node.driver
            driver.tick = timed(driver.tick, "driver tick (advance + detection + snapshot)")
            driver._detect = timed(driver._detect, "snap detection")
            node._handle_report = timed(node._handle_report, "report handling")
            node.tf.publish = timed(node.tf.publish, "/tf (build + publish)")
            node.winch_io.tick = timed(node.winch_io.tick, "winch outputs")
            node.forecast_io.tick = timed(node.forecast_io.tick, "forecast hand-off")
            self.convert.tick_outputs = timed(self.convert.tick_outputs, "periodic outputs (solver outputs + encoders)")
            self.convert.OutputFrame = _timed_class(self.convert.OutputFrame, timed)
            self.convert.tension_colours = timed(self.convert.tension_colours, "marker colours")
            cdr = importlib.import_module(f"{pkg}.ros.cdr")
            for name in dir(cdr):
                cls = getattr(cdr, name)
                if isinstance(cls, type) and name.endswith("Encoder") and hasattr(cls, "encode"):
                    cls.encode = timed(cls.encode, f"encode {name}")
        self.part_rows = []
        # the ship's pose on the file's motion, fed as the subscription would; none where the node moves the ship
        # itself (motion.kind rao: the RAO response to the configured sea) or the ship end is not driven; the
        # other driven ends and a network's other driven points held
        if self.network:
            self.motion = network_ship_motion(self.node.spec.points["ship"].position)
            self.held = {n: p.position for n, p in self.node.spec.points.items() if p.kind == "prescribed" and n != "ship"}
        else:
            self.motion = build_motion(cfg.motion, cfg.ship_end.position) if "ship" in self.node.inputs else None
            # another driven end (a vehicle on vehicle/pose): its body frame held where its attachment is the
            # configured end position
            self.held = {end: tuple(a - b for a, b in zip(getattr(cfg, f"{end}_end").position,
                                                           getattr(cfg.node, f"{end}_attachment")))
                         for end in self.node.inputs if end != "ship"}
        self.period = 1.0 / cfg.node.output_rate
        self.clock = 100.0  # the node's clock, s; the motion's time is clock - 100
        self.node._now = lambda: self.clock
        self.msg = PoseStamped()
        self.msg.header.frame_id = cfg.node.world_frame
        self.msg.pose.orientation.w = 1.0
        self.rows, self.pose_cpu, self.diag_cpu = [], [], []

    def _split_network(self, pkg, timed):
        """--split on a line network: the network solver's tick (advance) and each line solver's inside it, each
        line's snap detection and state sampling (state), the bodies' and points' outputs (outputs: body motion,
        wrenches), the encoders and each publish; inclusive parts as the single-line split."""
        import importlib

        node, driver = self.node, self.node.driver
        outputs = importlib.import_module(f"{pkg}.ros.network_outputs")
        snap = importlib.import_module(f"{pkg}.physics.snap")
        cdr = importlib.import_module(f"{pkg}.ros.cdr")
        for publisher in self.publishers:
            publisher.publish = timed(publisher.publish, "publish", "publish " + publisher.topic_name)
        driver.tick = timed(driver.tick, "driver tick (network tick + detection)")
        self._patch_net = lambda: self._split_net(timed)  # (the node rebuilds the network at its first ticks)
        driver.line_state = timed(driver.line_state, "state", "line states (sampled once per tick)")
        driver._command = timed(driver._command, "point commands (pose inputs)")
        base = importlib.import_module(f"{pkg}.solvers.base")  # (read by the drivers' lazy speed, when needed)
        base.relative_end_speed = timed(base.relative_end_speed, "relative end speed (snap guard)")
        update = snap.SnapDetector.update

        def detector_update(det, *a, **k):
            c = time.thread_time()
            out = update(det, *a, **k)
            key = "snap detection: " + det.locations[0].split("/")[0]
            self.parts[key] = self.parts.get(key, 0.0) + time.thread_time() - c
            return out
        snap.SnapDetector.update = detector_update
        outputs.tick_outputs = timed(outputs.tick_outputs, "periodic outputs (solver outputs + encoders)")
        outputs.point_wrench = timed(outputs.point_wrench, "outputs", "point wrenches")
        outputs.body_wrench = timed(outputs.body_wrench, "outputs", "body wrenches")
        network_node = importlib.import_module(f"{pkg}.ros.network_node")
        network_node.tf_message_cdr = timed(network_node.tf_message_cdr, "/tf encode")
        node._publish_outputs = timed(node._publish_outputs, "outputs and publishing (all)")
        for name in dir(cdr):
            cls = getattr(cdr, name)
            if isinstance(cls, type) and name.endswith("Encoder") and hasattr(cls, "encode"):
                cls.encode = timed(cls.encode, f"encode {name}")

    def _split_net(self, timed):
        """The network solver's calls timed (again after the node rebuilt it)."""
        net = self._patched = self.node.driver.net
        net.tick = timed(net.tick, "advance", "network solver tick (lines + bodies)")
        for name, solver in net.lines.items():
            solver.tick = timed(solver.tick, f"line solver tick: {name}")
        net.body_motion = timed(net.body_motion, "outputs", "body motion (sim_twist, sim_accel, hydro_wrench)")

    def tick(self, k, timed, prof=None):
        if getattr(self, "_patch_net", None) is not None and self.node.driver.net is not getattr(self, "_patched", None):
            self._patch_net()
        self.clock += self.period
        c = time.thread_time()
        self.msg.header.stamp = self.convert.time_msg(self.clock)
        for name, position in self.held.items():
            self.msg.pose.position.x, self.msg.pose.position.y, self.msg.pose.position.z = (float(v) for v in position)
            self.node._on_pose(name, self.msg)
        if self.motion is not None:
            p, _, _ = self.motion.at(self.clock - 100.0)
            self.msg.pose.position.x, self.msg.pose.position.y, self.msg.pose.position.z = (float(v) for v in p)
            self.node._on_pose("ship", self.msg)
        self.pose_cpu.append(time.thread_time() - c)
        for key in self.parts:
            self.parts[key] = 0.0
        if prof is not None:
            prof.enable()
        c = time.thread_time()
        self.node._on_tick()
        cpu = time.thread_time() - c
        if prof is not None:
            prof.disable()
        if timed:
            self.part_rows.append(dict(self.parts))
            self.rows.append((cpu, self.parts["advance"], self.parts["state"], self.parts["outputs"], self.parts["publish"]))
        if k % round(self.cfg.node.output_rate) == 0:  # the 1 Hz diagnostics
            c = time.thread_time()
            self.node._publish_diagnostics()
            self.diag_cpu.append(time.thread_time() - c)

    def report(self, params, alpha):
        import numpy as np

        r = np.array(self.rows) * 1e3
        output_rate = self.cfg.node.output_rate
        node_own = r[:, 0] - r[:, 1:].sum(axis=1)
        med = lambda a: [float(np.median(a)), float(np.percentile(a, 99))]  # noqa: E731
        return {"params": str(params), "alpha": alpha, "package": self.pkg, "ticks": len(self.rows),
                "subscribed": f"{sum(p.get_subscription_count() > 0 for p in self.publishers)}/{len(self.publishers)}",
                "tick_ms": med(r[:, 0]), "advance_ms": med(r[:, 1]), "state_ms": med(r[:, 2]), "outputs_ms": med(r[:, 3]),
                "publish_ms": med(r[:, 4]),
                "node_own_ms": med(node_own), "pose_callback_ms": float(np.median(self.pose_cpu) * 1e3),
                "diagnostics_ms": float(np.median(self.diag_cpu) * 1e3), "tick_errors": self.node.tick_errors,
                "parts_ms": {key: float(np.median([row.get(key, 0.0) for row in self.part_rows]) * 1e3)
                             for key in sorted({k for row in self.part_rows for k in row})},
                "snaps": self.node.snaps_published, "tick_cpu_s": [float(x) for x in r[:, 0] * 1e-3],
                "outputs_per_s": output_rate, "pose_input": self.motion is not None}


def child(params, ticks, alpha, profile, split, baseline, extra=()):
    """Runs in a child process: one node per tree (this one, and ``baseline``'s renamed copy), ticked
    alternately (the order swapped every tick); prints one JSON line."""
    import numpy as np
    import rclpy

    pkgs = ["tether_sim"]
    if baseline == "same":  # a second node of this tree, without the -p parameters
        pkgs.append("tether_sim")
    elif baseline:
        from benchmarks.bench_tick import load_baseline

        load_baseline(baseline, with_ros=True)
        pkgs.append("tether_sim_base")
    import yaml
    from rclpy.parameter import Parameter

    rclpy.init(args=["tether_sim", "--ros-args", "--params-file", str(params), "-p", f"cable.EI:={alpha * EI_STAR}"])
    overrides = [Parameter(key, value=yaml.safe_load(text)) for key, _, text in (item.partition(":=") for item in extra)]
    benches = [_Bench(pkg, params, alpha, split, overrides if i == 0 else []) for i, pkg in enumerate(pkgs)]
    deadline = time.monotonic() + 30.0
    while any(p.get_subscription_count() == 0 for b in benches for p in b.publishers) and time.monotonic() < deadline:
        time.sleep(0.05)  # discovery of the sink process
    warm = 100  # the first ticks start the solver and may load lazily used kernels
    prof = None
    for k in range(warm + ticks + (profile or 0)):
        if k == warm + ticks:
            import cProfile
            # BENCH_PROFILE_TIMER=thread: the thread's CPU time (a loaded machine's preemptions left out)
            prof = cProfile.Profile(time.thread_time) if os.environ.get("BENCH_PROFILE_TIMER") == "thread" else cProfile.Profile()
        for b in (benches if k % 2 == 0 else benches[::-1]):
            b.tick(k, warm <= k < warm + ticks, prof if b is benches[0] else None)
    reports = [b.report(params, alpha) for b in benches]
    if profile:
        import io
        import pstats
        s = io.StringIO()
        pstats.Stats(prof, stream=s).sort_stats(os.environ.get("BENCH_PROFILE_SORT", "tottime")).print_stats(int(os.environ.get("BENCH_PROFILE_ROWS", "30")))
        reports[0]["profile"] = s.getvalue()
    if baseline:  # tick by tick: the two nodes' ticks k ran next to each other
        a, b = (np.array(r.pop("tick_cpu_s")) for r in reports)
        reports[0]["baseline_over_this"] = float(np.median(b) / np.median(a))
    else:
        reports[0].pop("tick_cpu_s")
    load = list(os.getloadavg())
    for r in reports:
        r["load"] = load
    print("BENCH_NODE_TICK " + json.dumps(reports), flush=True)
    for b in benches:
        b.node.destroy_node()
    rclpy.shutdown()


def sink(params=None):
    """Runs in its own process: raw subscriptions to every periodic output and /tf, spun (a line network's
    topics for a network file ``params``)."""
    import importlib

    import rclpy
    from rclpy.executors import ExternalShutdownException

    from tether_sim.ros import convert
    from tether_sim.ros.sim_node import RELIABLE
    from tether_sim.ros.tf import TF_QOS, TFMessage

    rclpy.init()
    node = rclpy.create_node("bench_node_tick_sink")
    topics = convert.TOPICS
    if params and is_network(params):
        from tether_sim.network.params import load_network_files
        from tether_sim.ros.network_outputs import output_topics

        spec, _ = load_network_files([params])
        topics = {t: v for t, v in output_topics(spec, list(spec.lines)).items()
                  if not t.endswith(("/description", "/snap_events", "/slack_warnings")) and t != "/diagnostics"}
    for topic, (type_name, _) in topics.items():
        if topic in convert.SHAPE_TOPICS or topic.endswith(("_wrench", "sim_pose")) or topics is not convert.TOPICS:
            package, _, name = type_name.split("/")
            msg_type = getattr(importlib.import_module(f"{package}.msg"), name)
            node.create_subscription(msg_type, topic, lambda _m: None, RELIABLE, raw=True)
    if TFMessage is not None:
        node.create_subscription(TFMessage, "/tf", lambda _m: None, TF_QOS, raw=True)
    print("SINK_READY", flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


def bench_env(extra=None) -> dict:
    """This process's environment with DDS kept on this host and a domain of its own (no other run's topics)."""
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", ROS_DOMAIN_ID=str(100 + os.getpid() % 100))
    env.update(extra or {})
    return env


def run_child(cmd, env, marker, with_sink=True, timeout=3600, params=None) -> dict:
    """Run the measuring child ``cmd`` (beside a subscriber process of every periodic output, :func:`sink`, when
    ``with_sink``; of the line network's outputs for a network file ``params``) and return the JSON it prints
    after ``marker``."""
    sink_proc = None
    if with_sink:
        sink_proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--sink"]
                                     + (["--sink-params", str(params)] if params else []), env=env, cwd=ROOT,
                                     stdout=subprocess.PIPE, text=True)
    try:
        if sink_proc is not None and sink_proc.stdout.readline().strip() != "SINK_READY":
            raise RuntimeError("the subscriber process did not start")
        proc = subprocess.run(cmd, env=env, cwd=ROOT, capture_output=True, text=True, timeout=timeout)
    finally:
        if sink_proc is not None:
            sink_proc.send_signal(signal.SIGINT)
            try:
                sink_proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                sink_proc.kill()
    for line in proc.stdout.splitlines():
        if line.startswith(marker + " "):
            return json.loads(line[len(marker) + 1:])
    raise RuntimeError(f"run failed ({proc.returncode}):\n{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}")


def launch(params, ticks, alpha, profile, split, baseline=None, extra=()):
    cmd = [sys.executable, __file__, "--child", str(params), "--ticks", str(ticks), "--alpha", str(alpha)]
    if profile:
        cmd += ["--profile", str(profile)]
    if split:
        cmd += ["--split"]
    if baseline:
        cmd += ["--baseline", str(baseline)]
    for item in extra:
        cmd += ["-p", item]
    return run_child(cmd, bench_env(), "BENCH_NODE_TICK", params=params)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", nargs="+", default=["config/ropos_L200.yaml", "config/ropos_L1730.yaml"])
    ap.add_argument("--ticks", type=int, default=1500)
    ap.add_argument("--alpha", type=float, default=0.0, help="bending factor, EI = alpha * 2.62 kN m^2")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--baseline", default=None, help="another checkout, timed interleaved with this one")
    ap.add_argument("--profile", type=int, default=0)
    ap.add_argument("--split", action="store_true", help="also time the solver's calls (adds ~10 clock reads a tick)")
    ap.add_argument("--json", default="out/bench_node_tick.json")
    ap.add_argument("--child", default=None)
    ap.add_argument("--sink", action="store_true")
    ap.add_argument("--sink-params", default=None)
    ap.add_argument("-p", dest="extra", action="append", default=[], metavar="KEY:=VALUE",
                    help="a parameter of this tree's node (not the baseline's), e.g. node.shape_rate:=10")
    args = ap.parse_args(argv)
    if args.sink:
        return sink(args.sink_params)
    if args.child:
        return child(args.child, args.ticks, args.alpha, args.profile, args.split, args.baseline, args.extra)
    print(f"bench_node_tick, {os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{args.ticks} ticks, alpha={args.alpha:g}{''.join(' -p ' + e for e in args.extra)}, load average {os.getloadavg()[0]:.2f}", flush=True)
    rows = []
    for params in args.params:
        ratios = []
        for _ in range(args.repeat):
            reports = launch(params, args.ticks, args.alpha, args.profile, args.split, args.baseline, args.extra)
            for r, name in zip(reports, ("this tree", "baseline")):
                rows.append(r)
                split = (f"advance {r['advance_ms'][0]:.3f}, state {r['state_ms'][0]:.3f}, other solver outputs "
                         f"{r['outputs_ms'][0]:.3f}, publishing {r['publish_ms'][0]:.3f}, the node's own rest "
                         f"{r['node_own_ms'][0]:.3f} (p99 {r['node_own_ms'][1]:.3f}); "
                         if args.split else "")
                print(f"{Path(params).name} [{name}] tick CPU median {r['tick_ms'][0]:.3f} ms (p99 {r['tick_ms'][1]:.3f}): "
                      f"{split}pose callback {r['pose_callback_ms']:.3f}, diagnostics (1 Hz) {r['diagnostics_ms']:.3f}; "
                      f"outputs subscribed {r['subscribed']}, snaps {r['snaps']}, tick errors {r['tick_errors']}, "
                      f"load {r['load'][0]:.2f}", flush=True)
                if args.split and r.get("parts_ms"):
                    print("  parts (median ms per tick, inclusive: a part holds the parts called inside it):")
                    for key, value in r["parts_ms"].items():
                        print(f"    {key:60s} {value:.4f}")
                if r.get("profile"):
                    print(r["profile"])
            if args.baseline:
                ratios.append(reports[0]["baseline_over_this"])
        if args.baseline:
            print(f"{Path(params).name}: baseline / this tree, tick CPU median: " + ", ".join(f"{x:.2f}" for x in ratios),
                  flush=True)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(rows, indent=1))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
