"""Divergence recovery of the stepping drivers: the single-line driver (tether_sim/ros/driver.py) and
the network driver (tether_sim/ros/network_driver.py) share this code and its policy (no rclpy).

Policy (docs/node.md, "Divergence"; docs/network.md, "Recovery after a divergence"):

- A snapshot of the whole simulated state is kept: the solver's (a network's: every line's state,
  with its winch, every body's state, every point's motion and the end loads) and the driven ends'
  commanded states, taken at the start and then every ``node.snapshot_interval`` s of simulated time.
- On a divergence (:class:`~tether_sim.errors.SolverDivergedError`: a DG state turning
  non-finite, a hybrid Newton failure, a network body's state turning non-finite) the last good
  snapshot is restored, the anchor moves so that the lost clock time is skipped (the restored
  state carries the clock time the failed tick was heading for: stamps stay monotonic), and each
  driven end is blended from its snapshot state onto its input
  (:meth:`~tether_sim.ros.end_commands.EndCommands._start_blend`, reason "recovered from a
  snapshot"); snap detection is suspended from the discontinuity until the blends end and then
  restarts with fresh detectors, so no snap can be made of the recovery; the outputs are degraded
  meanwhile.
- A second divergence before a newer snapshot exists (the restored state diverged again) rebuilds
  the simulation from a fresh static equilibrium at the current end positions (a winch keeps its
  length and command).
- Each divergence is counted (``divergences``), its message kept (``last_error``) with how it was
  recovered (``last_recovery``: "snapshot" or "static") and reported on the tick's report
  (``error``, ``recovery``); the nodes log it as an error and their diagnostics turn ERROR.

:class:`Recovery` is a mixin: the driver provides ``_sim_time`` (the solver time),
``_capture_snapshot()`` (the state to keep), ``_restore_snapshot(snap)`` (put it back, with its
ends' commanded states), ``_rebuild_static(now, report)`` and the end-command state of
:class:`~tether_sim.ros.end_commands.EndCommands` (``_end_state``, ``_blends``, ``catchup``, ``anchor``).
"""

import math


class Recovery:
    """Snapshots and divergence recovery of a driver (module doc)."""

    def _init_recovery(self):
        self.divergences = 0
        self.last_error = None
        self.last_recovery = None  # "snapshot" or "static" after a divergence
        self._snapshot = None
        self._snapshot_time = -math.inf
        self._snapshot_failed = False

    def _snapshot_due(self, interval) -> bool:
        """True when ``interval`` s of simulated time have passed since the last snapshot."""
        return self._sim_time - self._snapshot_time >= interval

    def _take_snapshot(self):
        self._snapshot = self._capture_snapshot()
        self._snapshot_time = self._sim_time
        self._snapshot_failed = False

    def _recover(self, now, message, report):
        """Restore the last good snapshot at clock time ``now``, or rebuild from a static equilibrium
        if that snapshot already diverged once (module doc)."""
        self.divergences += 1
        self.last_error = message
        self.last_recovery = None
        report.error = message
        self._blends.clear()
        self.catchup.clear()
        if self._snapshot is not None and not self._snapshot_failed:
            self._restore_snapshot(self._snapshot)
            self._snapshot_failed = True  # a second divergence before a new snapshot -> rebuild
            report.recovery = self.last_recovery = "snapshot"
            self.anchor = now - self._sim_time
            for end in list(self._end_state):
                self._start_blend(end, now, "recovered from a snapshot", report)
            self._suspend_detection(now)
        else:
            self._rebuild_static(now, report)
            report.recovery = self.last_recovery = "static"
