"""Child ROS processes for main_job: isolated DDS domain, logs to files, clean stop by PID.

Only processes started here are ever signalled (by their own Popen handle)."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

NODE_MODULES = {  # console script -> (module, entry function)
    "tether-sim": ("tether_sim.ros.sim_node", "main"),
    "tether-sim-record": ("tether_sim.ros.recorder_node", "main"),
    "tether-sim-replay": ("tether_sim.ros.replay_node", "main"),
    "tether-sim-poses": ("tether_sim.ros.pose_source", "main"),
    "tether-sim-vehicle": ("tether_sim.ros.vehicle_node", "main"),
}


class StepFailed(RuntimeError):
    """A step of the main job failed; the message says which and why."""


REPO = Path(__file__).resolve().parents[2]
FASTDDS_PROFILE = REPO / "tools" / "fastdds_localhost.xml"
_claimed = {}  # domain id -> open lock file, held until this process exits


def claim_domain_id(first: int = 1, last: int = 101) -> int:
    """A ROS_DOMAIN_ID no other process on this machine holds (the lock files the test suite
    uses too: <tmp>/tether_sim_ros_domain_<id>.lock); domains <= 101 keep DDS ports valid."""
    import fcntl
    import random
    import tempfile

    ids = list(range(first, last + 1))
    start = random.SystemRandom().randrange(len(ids))
    for domain in ids[start:] + ids[:start]:
        handle = open(Path(tempfile.gettempdir()) / f"tether_sim_ros_domain_{domain}.lock", "a+")  # noqa: SIM115
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        _claimed[domain] = handle
        return domain
    raise StepFailed("no free ROS domain id (1-101 are all held by other processes)")


def isolated_env(domain_id: int) -> dict:
    """This environment plus a private ROS_DOMAIN_ID and localhost-only discovery (and the
    repository's loopback-only Fast DDS profile when present)."""
    env = dict(os.environ)
    env.update(ROS_DOMAIN_ID=str(domain_id), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               PYTHONUNBUFFERED="1")
    env.pop("ROS_LOCALHOST_ONLY", None)  # deprecated in Jazzy; RANGE above replaces it
    if FASTDDS_PROFILE.is_file() and "FASTRTPS_DEFAULT_PROFILES_FILE" not in env:
        env["FASTRTPS_DEFAULT_PROFILES_FILE"] = str(FASTDDS_PROFILE)
    return env


def command_for(script: str) -> list[str]:
    """The venv's console script when installed, else the module run by this interpreter."""
    exe = Path(sys.executable).with_name(script)
    if exe.is_file() and os.access(exe, os.X_OK):
        return [str(exe)]
    found = shutil.which(script)
    if found and Path(found).parent == Path(sys.executable).parent:
        return [found]
    module, func = NODE_MODULES[script]
    return [sys.executable, "-c", f"import sys; from {module} import {func}; sys.exit({func}())", script]


class Child:
    """One started process with its log file."""

    def __init__(self, name: str, argv: list[str], env: dict, log_dir: Path, cwd: Path):
        self.name, self.argv = name, argv
        self.log_path = log_dir / f"{name}.log"
        self._log = open(self.log_path, "w")  # noqa: SIM115 - closed in stop()
        self.proc = subprocess.Popen(argv, env=env, cwd=cwd, stdout=self._log,
                                     stderr=subprocess.STDOUT, start_new_session=True)
        self.started = time.monotonic()

    @property
    def alive(self) -> bool:
        return self.proc.poll() is None

    def tail(self, n: int = 25) -> str:
        try:
            lines = self.log_path.read_text(errors="replace").splitlines()
        except OSError:
            return ""
        return "\n".join(f"    | {line}" for line in lines[-n:])

    def stop(self, sig=signal.SIGINT, timeout: float = 20.0) -> int:
        """Signal this process (only it), wait, escalate to SIGKILL; returns the exit code."""
        if self.alive:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=10)
        self._log.close()
        return self.proc.returncode


class ProcessGroup:
    """Children started in order and stopped in reverse order, also on errors."""

    def __init__(self, env: dict, log_dir: Path, cwd: Path):
        self.env, self.log_dir, self.cwd = env, log_dir, cwd
        self.children: list[Child] = []
        log_dir.mkdir(parents=True, exist_ok=True)

    def start(self, name: str, argv: list[str]) -> Child:
        child = Child(name, argv, self.env, self.log_dir, self.cwd)
        self.children.append(child)
        return child

    def check_alive(self) -> None:
        for child in self.children:
            if not child.alive and child.proc.returncode not in (0, None):
                raise StepFailed(f"{child.name} exited with code {child.proc.returncode}; "
                                 f"last lines of {child.log_path}:\n{child.tail()}")

    def stop_all(self) -> None:
        for child in reversed(self.children):
            child.stop()


def _terminate(signum, _frame):
    raise KeyboardInterrupt(f"signal {signum}")


def run_job(env: dict, log_dir: Path, root: Path, body, say) -> int:
    """Run body(group) on a new ProcessGroup whose children are stopped however it ends (SIGTERM
    included, as `make run` may send): 0 when body returns, 1 on StepFailed (its reason said),
    130 on an interrupt."""
    old = signal.signal(signal.SIGTERM, _terminate)
    group = ProcessGroup(env, log_dir, root)
    try:
        body(group)
        return 0
    except StepFailed as exc:
        say(f"FAILED: {exc}")
        return 1
    except KeyboardInterrupt:
        say("interrupted")
        return 130
    finally:
        group.stop_all()
        signal.signal(signal.SIGTERM, old)
