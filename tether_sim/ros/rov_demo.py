"""A vehicle flown on the tether, end to end (console script ``tether-sim-rov-demo``).

    tether-sim-rov-demo [--duration S] [--output FILE.mcap] [--current U]

In a private ROS domain (as ``make run``): the recorder (every topic, sim time), tether-sim with
config/rov_demo.yaml (a light 60 m tether from a heaving vessel, a current along +x), tether-sim-poses
(the vessel's heave from that file) and tether-sim-vehicle (the MuJoCo BlueROV2 Heavy, owner of
/clock, held still until the tether's first wrench). The vehicle holds station 44.6 m up-current of
the fairlead at 35 m depth for the first third of the run, then transits at 0.3 m/s to (-30, 30, -35)
and holds there. At the end: the MCAP, tether-sim-report's tether report next to it and
a vehicle figure (path, thrust, the tether's force on the vehicle) with its summary appended to the
report. Exit 0 when every step worked; logs of each process in <output dir>/logs.
"""

from __future__ import annotations

import argparse
import math
import signal
import sys
import time
from pathlib import Path

from tether_sim.ros.processes import (ProcessGroup, StepFailed, claim_domain_id, command_for, isolated_env,
                                      run_job)

REPO = Path(__file__).resolve().parents[2]
PARAMS = Path("config/rov_demo.yaml")
START = STATION = (-44.6, 0.0, -35.0)  # up-current of the vessel (config/rov_demo.yaml)
TRANSIT = (-30.0, 30.0, -35.0)


def say(text: str) -> None:
    print(f"[rov_demo {time.strftime('%H:%M:%S')}] {text}", flush=True)


def run(root: Path, mcap: Path, args, group: ProcessGroup) -> None:
    """Start the four processes, wait for the vehicle's mission to end, stop the rest."""
    if mcap.exists():
        mcap.unlink()
    recorder = group.start("recorder", command_for("tether-sim-record") + [
        "--ros-args", "--params-file", str(root / "config/recorder.yaml"), "-p", f"output:={mcap}",
        "-p", "all_topics:=true", "-p", "use_sim_time:=true"])
    node = group.start("tether_sim", command_for("tether-sim") + [
        "--ros-args", "--params-file", str(root / PARAMS), "-p", "use_sim_time:=true"])
    ship = group.start("ship", command_for("tether-sim-poses") + [
        "--params", str(root / PARAMS), "--ros-args", "-p", "use_sim_time:=true"])
    vehicle = group.start("vehicle", command_for("tether-sim-vehicle") + [
        "--clock", "--hold-until-tether", "--position", *map(str, START), "--setpoint", *map(str, STATION),
        "--transit", *map(str, TRANSIT), "--transit-after", f"{args.duration / 3:g}", "--transit-speed", "0.3",
        "--current", f"{args.current:g}", "0", "0", "--stop-after", f"{args.duration:g}"])
    say(f"started the recorder, tether-sim, the ship and the vehicle in ROS_DOMAIN_ID={group.env['ROS_DOMAIN_ID']} "
        f"(logs in {group.log_dir}); the vehicle is held until the tether node's first wrench")
    t0 = time.monotonic()
    limit = 600.0 + 3.0 * args.duration  # start-up (numba cache) and a loaded machine
    while vehicle.alive:
        for child in (recorder, node, ship):
            if not child.alive:
                raise StepFailed(f"{child.name} stopped during the run; last lines of {child.log_path}:\n{child.tail()}")
        if time.monotonic() - t0 > limit:
            raise StepFailed(f"the vehicle's mission did not end within {limit:.0f} s of wall time")
        time.sleep(0.5)
    if vehicle.proc.returncode != 0:
        raise StepFailed(f"the vehicle simulator exited with {vehicle.proc.returncode}; see {vehicle.log_path}:\n"
                         f"{vehicle.tail()}")
    time.sleep(1.0)  # the last messages reach the recorder
    for child in (ship, node):
        child.stop()
    code = recorder.stop(sig=signal.SIGTERM)
    if code != 0:
        raise StepFailed(f"the recorder exited with {code}; see {recorder.log_path}:\n{recorder.tail()}")


def vehicle_report(mcap: Path, out_dir: Path, hold_s: float) -> str:
    """The vehicle's figure (path seen from above, depth, thrust and tether force against the mission's
    time, from the vehicle's release) and a markdown summary; reads /vehicle/pose, /vehicle/thrust and
    /tether/vehicle_wrench. ``hold_s``: how long the mission held the station before the transit."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from tether_sim.io.mcap_log import read_messages

    pose, thrust, wrench = [], [], []
    for topic, _t, ns, msg in read_messages(str(mcap)):
        if topic == "/vehicle/pose":
            p = msg.pose.position
            pose.append((ns * 1e-9, p.x, p.y, p.z))
        elif topic == "/vehicle/thrust":
            f = msg.wrench.force
            thrust.append((ns * 1e-9, math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)))
        elif topic == "/tether/vehicle_wrench":
            f = msg.wrench.force
            wrench.append((ns * 1e-9, math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)))
    if not pose or not wrench:
        raise StepFailed(f"{mcap} holds no vehicle poses or no tether wrench on the vehicle")
    P, T, W = np.array(pose), np.array(thrust), np.array(wrench)
    t0 = W[0, 0]  # the vehicle is released at the tether's first wrench: the mission's time 0
    P, T, W = P[P[:, 0] >= t0], T[T[:, 0] >= t0], W[W[:, 0] >= t0]
    P[:, 0] -= t0
    T[:, 0] -= t0
    W[:, 0] -= t0
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    ax[0].plot(P[:, 1], P[:, 2], "b-")
    ax[0].plot([0.0], [0.0], "ks", label="fairlead (vessel)")
    ax[0].plot([STATION[0], TRANSIT[0]], [STATION[1], TRANSIT[1]], "r+", ms=12, label="station, transit target")
    ax[0].set(xlabel="x (east), m", ylabel="y (north), m", title="vehicle path, seen from above", aspect="equal")
    ax[0].legend(loc="best", fontsize=8)
    ax[1].plot(P[:, 0], P[:, 3], "b-")
    ax[1].set(xlabel="time since the release, s", ylabel="z, m", title="vehicle depth")
    ax[2].plot(T[:, 0], T[:, 1], "g-", lw=0.8, label="|thrust| (all thrusters)")
    ax[2].plot(W[:, 0], W[:, 1], "m-", lw=0.8, label="|tether force on the vehicle|")
    ax[2].axvline(hold_s, color="0.5", ls=":", lw=1)
    ax[2].set(xlabel="time since the release, s", ylabel="N", title="thrust and tether force (dotted: transit starts)")
    ax[2].legend(loc="best", fontsize=8)
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    out_dir.mkdir(parents=True, exist_ok=True)
    png = out_dir / "vehicle.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    hold = P[(P[:, 0] >= hold_s / 2) & (P[:, 0] <= hold_s)]  # the second half of the station keeping
    drift = float(np.max(np.linalg.norm(hold[:, 1:] - np.array(STATION), axis=1))) if len(hold) else math.nan
    return "\n".join([
        "", "## Vehicle (tether-sim-vehicle, MuJoCo BlueROV2 Heavy)", "",
        f"![vehicle](figures/{png.name})", "",
        f"- {len(P)} poses over {P[-1, 0]:.1f} s from the release (the tether's first wrench); end at "
        f"({P[-1, 1]:.1f}, {P[-1, 2]:.1f}, {P[-1, 3]:.1f}) m (transit target {TRANSIT}).",
        f"- Station keeping, second half of the {hold_s:g} s hold: within {drift:.2f} m of the station {STATION}.",
        f"- Tether force on the vehicle: median {np.median(W[:, 1]):.1f} N, largest {W[:, 1].max():.1f} N; "
        f"thrust median {np.median(T[:, 1]):.1f} N, largest {T[:, 1].max():.1f} N.", ""])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="tether-sim-rov-demo", description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=90.0, help="simulated seconds after the vehicle's release")
    ap.add_argument("--output", default="out/rov_demo/rov_demo.mcap", help="the MCAP to write")
    ap.add_argument("--current", type=float, default=0.2, help="current along +x, m/s (the tether file has 0.2)")
    args = ap.parse_args(argv)
    if not (math.isfinite(args.duration) and 3.0 <= args.duration <= 3600.0):
        print(f"tether-sim-rov-demo: --duration {args.duration}: between 3 and 3600 s", file=sys.stderr)
        return 2
    if not (math.isfinite(args.current) and abs(args.current) <= 2.0):
        print(f"tether-sim-rov-demo: --current {args.current}: at most 2 m/s", file=sys.stderr)
        return 2
    root = Path.cwd() if (Path.cwd() / PARAMS).is_file() else REPO
    mcap = Path(args.output).resolve()
    out = mcap.parent
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.monotonic()
    try:
        domain = claim_domain_id()
    except StepFailed as exc:
        say(f"FAILED: {exc}")
        return 1

    def job(group: ProcessGroup) -> None:
        run(root, mcap, args, group)
        say(f"recorded {mcap} ({mcap.stat().st_size / 1e6:.1f} MB); writing the report ...")
        from tether_sim.report import ReportError, make_report

        try:
            result = make_report(mcap, out / "figures")
        except ReportError as exc:
            raise StepFailed(f"the recording has nothing to report: {exc}") from exc
        text = vehicle_report(mcap, out / "figures", args.duration / 3)
        report = Path(result["report_path"])
        report.write_text(report.read_text() + text)
        say(f"report: {report} (vehicle figure {out / 'figures' / 'vehicle.png'})")
        print(text)
        say(f"done in {time.monotonic() - t_start:.0f} s")

    return run_job(isolated_env(domain), out / "logs", root, job, say)


if __name__ == "__main__":
    sys.exit(main())
