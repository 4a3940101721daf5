"""The main job (`make run`): the ROPOS validation run, live, then its report.

1. Pre-flight: the shipped record (data/ropos_ship_heave.mcap), the parameters
   (config/ropos_validation.yaml), the simulation node and the solver must all be present; the
   solver is built once here (its static equilibrium gives the expected static tensions, and the
   numba cache is warm before the node starts). A missing piece stops the job, named.
2. In a private ROS_DOMAIN_ID with localhost discovery: the recorder (config/recorder.yaml, sim
   time), the simulation node (``tether-sim --ros-args --params-file config/ropos_validation.yaml
   -p use_sim_time:=true``); once the graph shows the node's outputs matched by the recorder, the
   replay of the record with /clock (config/replay.yaml) at ``--rate``.
3. When the replay ends: the node and the recorder are stopped (SIGINT / SIGTERM), then
   tether-sim-report writes figures and report.md next to the MCAP, and the findings are printed.

Progress: a banner per stage (set-up, solver kernels, start, replay, report: ``== step k/5``); the
solver is built once before the node starts (tether_sim.warm), so a cold numba cache compiles here
with progress messages; the ROS domain and a command to watch the run from another terminal are
printed when the node starts.

Outputs: out/ropos_validation/ropos_validation.mcap, out/ropos_validation/figures/*.png and
report.md, out/ropos_validation/logs/*.log. Exit code 0 only when every step worked.
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
import time
from pathlib import Path

from tether_sim.ros.graph_probe import GraphProbe
from tether_sim.ros.processes import (ProcessGroup, StepFailed, claim_domain_id, command_for,
                                      isolated_env, run_job)

REPO = Path(__file__).resolve().parents[2]
RECORD = DEFAULT_RECORD = Path("data/ropos_ship_heave.mcap")
PARAMS = Path("config/ropos_validation.yaml")
OUT = Path("out/ropos_validation")
MCAP_NAME = "ropos_validation.mcap"
NODE_OUTPUTS = ("/tether/state", "/tether/ship_wrench", "/tether/vehicle_wrench",
                "/tether/snap_events", "/tether/slack_warnings")


STAGES = ("set-up", "solver kernels", "start the recorder and the node", "replay", "report")


def say(text: str) -> None:
    print(f"[main_job {time.strftime('%H:%M:%S')}] {text}", flush=True)


def stage(name: str, text: str = "") -> None:
    """A progress banner: ``== step k/5: name: text``."""
    k = STAGES.index(name) + 1
    say(f"== step {k}/{len(STAGES)}: {name}" + (f": {text}" if text else ""))


def watch_hint(domain: int, root: Path) -> str:
    """How to watch the run from another terminal of this machine (printed at the start)."""
    from tether_sim.ros.processes import FASTDDS_PROFILE

    env = f"ROS_DOMAIN_ID={domain} ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST"
    if FASTDDS_PROFILE.is_file():
        env += f" FASTRTPS_DEFAULT_PROFILES_FILE={FASTDDS_PROFILE}"
    return (f"the run uses ROS_DOMAIN_ID={domain}, discovery on this machine only. To watch it from "
            f"another terminal:\n"
            f"    {env} {root}/.venv/bin/python -m tether_sim.ros.watch\n"
            f"  or, with a ROS 2 Jazzy install, the same variables and\n"
            f"    ros2 topic echo /tether/snap_events      rviz2 -d {root}/rviz/tether_sim.rviz\n"
            f"  (the recording opens in Foxglove with the layout foxglove/tether_sim.json)")


def warm_kernels(config) -> None:
    """Build the node's solver once here, so a cold numba cache compiles now, with progress, and
    the node only loads it (tether_sim.warm; `make setup` normally did it already)."""
    from tether_sim.warm import exercise, run_interruptibly

    t0 = time.monotonic()
    run_interruptibly(lambda: exercise(config), log=say, should_stop=lambda: False,
                      what=f"{config.solver} solver kernels")
    say(f"solver kernels ready in {time.monotonic() - t0:.1f} s")


def preflight(root: Path, params: Path = PARAMS) -> dict:
    """Check every piece the run needs; returns {config, static, record}. Raises StepFailed."""
    import importlib
    import importlib.util

    missing = []
    if not (root / RECORD).is_file():
        missing.append(f"the ship-motion record {RECORD} (tools/make_ropos_record.py, ROPOS issue)")
    if not (root / params).is_file():
        missing.append(f"the parameter file {params} (ROPOS issue)")
    if importlib.util.find_spec("tether_sim.ros.sim_node") is None:
        missing.append("the simulation node tether_sim/ros/sim_node.py (console script tether-sim)")
    if importlib.util.find_spec("tether_sim_msgs") is None:
        missing.append("the interface package tether_sim_msgs (run `make setup`)")
    if missing:
        raise StepFailed("cannot run the ROPOS validation: missing " + "; ".join(missing))
    from tether_sim.errors import ConfigError
    from tether_sim.io.mcap_log import McapLogError, read_summary
    from tether_sim.io.params import load_config

    try:
        config = load_config(root / params)
    except ConfigError as exc:
        raise StepFailed(f"{params} is not valid: {exc}") from exc
    try:
        record = read_summary(root / RECORD)
    except McapLogError as exc:
        raise StepFailed(str(exc)) from exc
    if "/ship/pose" not in record.topics:
        raise StepFailed(f"{RECORD} has no /ship/pose topic (topics: {sorted(record.topics)})")
    from tether_sim.solvers import factory

    module_name, class_name = factory._SOLVERS.get(config.solver, (None, None))
    try:
        getattr(importlib.import_module(module_name), class_name)
    except Exception as exc:  # noqa: BLE001 - any failure here means the solver is unusable
        raise StepFailed(f"the {config.solver!r} solver ({module_name}.{class_name}) is not "
                         f"available in this checkout ({type(exc).__name__}: {exc})") from exc
    static = None
    return {"config": config, "static": static, "record": record}


def largest_wave_window(path: Path, before=(30.0, 10.0), after: float = 30.0):
    """(start offset, duration, wave time, wave height) in s / m: a window around the record's
    largest zero-up-crossing heave wave, starting where the ship moves slowest (min |dz/dt|) in
    [wave - before[0], wave - before[1]], so the node's static start meets no velocity jump."""
    import numpy as np

    from tether_sim.io.mcap_log import read_messages

    samples = [(log, msg.pose.position.z) for _, _, log, msg in read_messages(path, ["/ship/pose"])]
    t = (np.array([a for a, _ in samples]) - samples[0][0]) / 1e9
    z = np.array([b for _, b in samples])
    z0 = z - z.mean()
    ups = np.flatnonzero((z0[:-1] < 0) & (z0[1:] >= 0))
    if len(ups) < 2:
        return 0.0, 0.0, 0.0, float(z.max() - z.min())
    heights = [z[a:b + 1].max() - z[a:b + 1].min() for a, b in zip(ups[:-1], ups[1:])]
    k = int(np.argmax(heights))
    t_wave = 0.5 * (t[ups[k]] + t[ups[k + 1]])
    speed = np.abs(np.gradient(z, t))
    inside = (t >= t_wave - before[0]) & (t <= t_wave - before[1])
    start = float(t[inside][np.argmin(speed[inside])]) if inside.any() else max(0.0, t_wave - before[0])
    end = min(float(t[-1]), t_wave + after)
    return start, float(end - start), float(t_wave), float(heights[k])


def run_live(root: Path, out: Path, args, group: ProcessGroup, checked: dict) -> Path:
    """Recorder + node, wait for discovery, replay, stop. Returns the recorded MCAP path."""
    mcap = out / MCAP_NAME
    if mcap.exists():
        mcap.unlink()
    recorder, node = _start_recorder_and_node(root, mcap, args, group)
    probe = GraphProbe()
    try:
        _wait_for_discovery(probe, args, group, node, recorder)
        first = _replay_start(root, args, checked)
        _prime_node(probe, first, args, group, node)
    finally:
        probe.close()
    _replay(root, mcap, args, group, node, checked["record"])
    time.sleep(1.0)  # the last ticks of the node reach the recorder
    code_node = node.stop()
    code_rec = recorder.stop(sig=signal.SIGTERM)
    if code_rec != 0:
        raise StepFailed(f"the recorder exited with {code_rec}; see {recorder.log_path}:\n{recorder.tail()}")
    if code_node not in (0, -2, 130):
        say(f"warning: the simulation node exited with {code_node}; see {node.log_path}")
    return mcap


def _start_recorder_and_node(root: Path, mcap: Path, args, group: ProcessGroup):
    """The recorder (sim time, writing ``mcap``) and the simulation node with the job's parameters."""
    recorder = group.start("recorder", command_for("tether-sim-record") + [
        "--ros-args", "--params-file", str(root / "config/recorder.yaml"),
        "-p", f"output:={mcap}", "-p", "use_sim_time:=true"])
    node = group.start("tether_sim", command_for("tether-sim") + [
        "--ros-args", "--params-file", str(root / args.params), "-p", "use_sim_time:=true"])
    say(f"started recorder (pid {recorder.proc.pid}) and simulation node (pid {node.proc.pid}) "
        f"in ROS_DOMAIN_ID={group.env['ROS_DOMAIN_ID']}; waiting for the node's outputs (its "
        f"warm-up only loads the kernels compiled in step 2) ...")
    return recorder, node


def _wait_for_discovery(probe: GraphProbe, args, group: ProcessGroup, node, recorder) -> None:
    """Until the recorder is subscribed to every node output (StepFailed after the timeout or when
    either process stops)."""
    deadline = time.monotonic() + args.discovery_timeout
    waiting = list(NODE_OUTPUTS)
    while waiting:
        group.check_alive()
        if not node.alive or not recorder.alive:
            gone = node if not node.alive else recorder
            raise StepFailed(f"{gone.name} stopped during start-up; last lines of "
                             f"{gone.log_path}:\n{gone.tail()}")
        if time.monotonic() > deadline:
            raise StepFailed(f"after {args.discovery_timeout:.0f} s the recorder is still not "
                             f"subscribed to {', '.join(waiting)} (is the node publishing "
                             f"them?); node log {node.log_path}:\n{node.tail()}")
        time.sleep(0.2)
        waiting = probe.recorder_matched(NODE_OUTPUTS)
    say("discovery complete: the recorder is subscribed to the node's outputs")


def _replay_start(root: Path, args, checked: dict):
    """The replay window (default: around the record's largest wave) and its first ship pose."""
    if args.start_offset is None:
        args.start_offset, window, t_wave, height = largest_wave_window(root / RECORD)
        if args.duration is None:
            args.duration = window
        say(f"window: {args.start_offset:.1f}-{args.start_offset + args.duration:.1f} s of the "
            f"record, around its largest wave ({height:.2f} m peak to trough at {t_wave:.1f} s), "
            f"starting where the ship moves slowest")
    elif args.duration is None:
        args.duration = 0.0
    from tether_sim.io.mcap_log import iter_raw

    first = next(r for r in iter_raw(root / RECORD, ["/ship/pose"])
                 if r.log_time_ns >= checked["record"].start_ns + int(args.start_offset * 1e9))
    checked["t_record_s"] = first.log_time_ns / 1e9
    return first


def _prime_node(probe: GraphProbe, first, args, group: ProcessGroup, node) -> None:
    """Hold /clock before the replay's start until the node has built its solver; with ``--rate``
    <= 0 measure its speed and choose the replay rate from it."""
    say("holding /clock just before the replay's start while the node builds its solver ...")

    def check():
        group.check_alive()
        if not node.alive:
            raise StepFailed(f"the simulation node stopped while starting; last lines of "
                             f"{node.log_path}:\n{node.tail()}")

    auto = args.rate <= 0
    took, rtf, load = probe.prime(first.log_time_ns, first.data, args.solver_timeout, check,
                                  measure_s=8.0 if auto else 0.0)
    say(f"the node is ready after {took:.1f} s")
    if auto:
        args.rate = replay_rate(rtf, load)
        if rtf is None:
            say("could not measure the node's speed; replaying in real time")
        else:
            say(f"the node kept {rtf:.2f} x real time, its ticks taking {100 * (load or 0.0):.0f} % of the wall "
                f"time: replaying at x{args.rate:g}" + (" (slower than real time so that the node keeps up)"
                                                         if args.rate < 1 else ""))


def replay_rate(rtf: float | None, load: float | None) -> float:
    """Replay rate from what the node showed under a real-time clock, in steps of 0.05, between
    0.05 and real time. ``load`` is the fraction of wall time the node spent in its ticks: when it
    kept up (``rtf`` >= 0.95) it could run 1 / load x real time, and half of that is taken. When it
    fell behind, or gave no load figure (an older node), 70 % of the simulated time it kept per
    wall second (``rtf``). With neither figure, real time."""
    if load is not None and load > 0.0 and (rtf is None or rtf >= 0.95):
        rate = 0.5 / load
    elif rtf is not None:
        rate = 0.7 * rtf
    else:
        return 1.0
    return max(0.05, min(1.0, math.floor(rate * 20) / 20))


def _replay(root: Path, mcap: Path, args, group: ProcessGroup, node, record) -> None:
    """The replay of the record's window with /clock at ``args.rate``, watched until it ends."""
    replay_args = ["--ros-args", "--params-file", str(root / "config/replay.yaml"),
                   "-p", f"input:={root / RECORD}", "-p", f"rate:={args.rate}",
                   "-p", f"start_offset_s:={args.start_offset}", "-p", f"duration_s:={args.duration}",
                   "-p", "wait_for_subscribers_s:=20.0", "-p", "min_subscribers:=2",  # the node and the recorder
                   "-p", "topics:=['/ship/pose']"]
    replay = group.start("replay", command_for("tether-sim-replay") + replay_args)
    span = (args.duration or (record.end_ns - record.start_ns) / 1e9 - args.start_offset) / args.rate
    stage("replay", f"{RECORD} at x{args.rate:g} (about {span:.0f} s of wall time)")
    t0, last_note = time.monotonic(), time.monotonic()
    while replay.alive:
        group.check_alive()
        if not node.alive:
            raise StepFailed(f"the simulation node stopped during the run; last lines of "
                             f"{node.log_path}:\n{node.tail()}")
        if time.monotonic() - t0 > 1.5 * span + 120:
            raise StepFailed(f"the replay did not finish within {1.5 * span + 120:.0f} s")
        if time.monotonic() - last_note > 15:
            last_note = time.monotonic()
            say(f"... {time.monotonic() - t0:.0f} s of {span:.0f} s, recording "
                f"{mcap.stat().st_size / 1e6 if mcap.exists() else 0:.1f} MB")
        time.sleep(0.5)
    if replay.proc.returncode != 0:
        raise StepFailed(f"the replay failed (exit {replay.proc.returncode}); last lines of "
                         f"{replay.log_path}:\n{replay.tail()}")


def print_findings(result: dict, static_expected, out: Path) -> None:
    from tether_sim.physics.boundary import END_NAMES

    run, periods = result["run"], result["periods"]
    span = float(run.t[-1] - run.t[0])
    say(f"times below: {run.time_label}")
    say(f"recorded {len(run.t)} tether states over {span:.1f} s of simulated time "
        f"(solver {run.solver})")
    for end in END_NAMES:
        line = f"static tension, {end} end: {result['static'][end]:.0f} N (first recorded state)"
        if static_expected:
            line += f"; solver equilibrium {static_expected[END_NAMES.index(end)]:.0f} N"
        say(line)
    for end in END_NAMES:
        spans = periods[end]
        total = sum(p["duration"] for p in spans)
        say(f"slack periods, {end} end: {len(spans)} (total {total:.2f} s)" +
            "".join(f"\n    {p['start']:8.2f} s - {p['end']:8.2f} s  min {p['min_tension']:.0f} N"
                    for p in spans[:10]) + ("\n    ..." if len(spans) > 10 else ""))
    snaps = sorted(run.snaps, key=lambda e: e["t_peak"])
    say(f"snap-load events: {len(snaps)}" + "".join(
        f"\n    {e['end']:7s} s={e['arc_length']:7.1f} m  peak {e['peak']:.0f} N at {e['t_peak']:.2f} s "
        f"(static {e['static']:.0f} N, x{e['amplification']:.2f}, slack {e['slack_duration']:.2f} s)"
        for e in snaps[:15]) + ("\n    ..." if len(snaps) > 15 else ""))
    from tether_sim.report import node_health

    health = node_health(run)
    if health is None:
        say("node health: no /diagnostics recorded")
    else:
        skipped = health["dropped_s"]
        say(f"node health: real-time factor {health['real_time_factor']:.2f} (last second), "
            f"{skipped:.1f} s of {span:.1f} s of clock time skipped (solver behind), "
            f"{health['divergences']:.0f} divergence recoveries")
        if skipped > 0.05 * max(span, 1e-9):
            say(f"WARNING: the node could not keep up with the replay on this machine and skipped "
                f"{skipped:.1f} s of the record; the tensions above cover only the simulated "
                f"stretches. Re-run slower, e.g. `python -m tether_sim.ros.main_job --rate 0.5`.")
    say(f"MCAP:    {out / MCAP_NAME}")
    for name, path in result["figures"].items():
        say(f"figure:  {path}  ({name})")
    say(f"summary: {result['report_path']}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tether_sim.ros.main_job", description=__doc__.split("\n")[0])
    parser.add_argument("--rate", type=float, default=0.0,
                        help="replay speed factor; 0 (default) = measure the node's speed first and "
                             "replay at 70 %% of it, at most real time")
    parser.add_argument("--start-offset", type=float, default=None,
                        help="skip seconds of the record (default: a window around the largest wave)")
    parser.add_argument("--duration", type=float, default=None,
                        help="replay seconds (0: to the end; default: the window around the largest "
                             "wave, or to the end when --start-offset is given)")
    parser.add_argument("--params", default=str(PARAMS), help="parameter file of the node")
    parser.add_argument("--record", default=str(DEFAULT_RECORD), help="MCAP of /ship/pose to replay (default: %(default)s)")
    parser.add_argument("--out", default=str(OUT), help="output directory")
    parser.add_argument("--domain-id", type=int, default=None,
                        help="ROS_DOMAIN_ID (default: a free one, claimed with a lock file)")
    parser.add_argument("--discovery-timeout", type=float, default=600.0,
                        help="s to wait for the node's outputs (it compiles its solver first)")
    parser.add_argument("--solver-timeout", type=float, default=600.0,
                        help="s to wait for the node to build its solver")
    args = parser.parse_args(argv)
    global RECORD
    RECORD = Path(args.record)  # (another ship motion, e.g. the ROPOS descent's heave: scenarios/ropos_descent.py)
    root = Path.cwd() if (Path.cwd() / "config").is_dir() else REPO
    os.chdir(root)
    out = (root / args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.monotonic()
    try:
        domain = args.domain_id if args.domain_id is not None else claim_domain_id()
    except StepFailed as exc:
        say(f"FAILED: {exc}")
        return 1
    os.environ.update(isolated_env(domain))  # the graph probe joins the same private domain

    def job(group: ProcessGroup) -> None:
        stage("set-up", "the environment is up to date (`make run` ran tools/setup_env.sh)")
        checked = preflight(root, Path(args.params))
        stage("solver kernels", "loading numba's cache (compiling it if cold)")
        warm_kernels(checked["config"])
        stage("start the recorder and the node", watch_hint(domain, root))
        motion, record = checked["config"].motion, checked["record"]
        say(f"ship motion: {RECORD} ({record.message_count} poses over "
            f"{(record.end_ns - record.start_ns) / 1e9:.0f} s; SYNTHETIC seeded sea, see "
            f"tools/make_ropos_record.py) is replayed byte for byte and the node uses the poses as "
            f"received, so the recorded amplitude is the simulated one; motion.record_scale "
            f"(= {motion.record_scale:g} in {args.params}) applies only to offline runs")
        mcap = run_live(root, out, args, group, checked)
        stage("report", f"figures and report.md from {mcap}")
        from tether_sim.report import ReportError, make_report

        try:
            result = make_report(mcap, out / "figures", t0_s=checked["t_record_s"],
                                 time_label=f"time since {args.start_offset:.1f} s of the record "
                                            f"(replay start; t < 0: start-up hold)")
        except ReportError as exc:
            raise StepFailed(f"the recording has nothing to report: {exc}") from exc
        print_findings(result, checked["static"], out)
        say(f"done in {time.monotonic() - t_start:.0f} s")

    return run_job(isolated_env(domain), out / "logs", root, job, say)


if __name__ == "__main__":
    sys.exit(main())
