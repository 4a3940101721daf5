"""The physical plausibility guard of snap events (docs/snap_guard.md).

:class:`SnapGuard` bounds a re-tensioning peak by what the cable's axial impedance, the moving mass and the
relative end speed allow, refuses a rise faster than the axial wave crosses an element, and links a
re-tensioning to the front of a rejected one elsewhere on the cable when its peak comes when that front
arrives (:meth:`SnapGuard.same_episode`). An event that fails is a :class:`NumericalSnapWarning`: reported,
never published as a snap. The detector that applies it: :class:`tether_sim.physics.snap.SnapDetector`.
"""

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class NumericalSnapWarning:
    """A re-tensioning the plausibility guard rejected (:class:`SnapGuard`): numerical, not a snap.

    ``tension_peak`` is the rejected peak (deliberately not called ``peak_tension``: nothing that
    handles snap events takes this for one)."""

    time: float
    location: str
    arc_length: float
    tension_peak: float
    bound: float  # guard_margin x the physical bound, N
    rise_time: float
    crossing_time: float  # axial wave crossing of the shortest element, s
    relative_speed: float  # largest relative end speed over the slack period and the rise, m/s
    static_tension: float
    slack_start: float
    reason: str


@dataclass(frozen=True)
class SnapGuard:
    """Physical plausibility bound of a re-tensioning peak (derivation: docs/snap_guard.md).

    For a cable of axial impedance Z = sqrt(EA gamma0), stiffness k = EA / L, between ends whose
    relative speed stays below dv while it is slack and re-tensions (rise time t_r), and a moving
    mass M (bodies with added mass and the cable; infinite between two kinematic ends):

        T_peak <= B = margin * (2 |T_static| + dv * (2 Z + min(sqrt(k M), k t_r)))

    2 Z dv: a front arresting the relative speed dv carries Z dv, doubled where it reflects at a
    held or heavy end; sqrt(k M) dv: the kinetic energy of M relative to the other end stored as
    stretch; k t_r dv: the stretch the ends can impose within the rise; 2 T_static: a weight taken up
    from slack overshoots at most to twice its static value. A peak above B, or a rise shorter than
    ``crossing_time`` (the axial wave crossing the shortest element: faster than the discretisation
    can carry a physical front), is numerical.

    One slack episode, one verdict (:meth:`same_episode`): a re-tensioning at another location of the
    cable whose slack period overlaps a rejected re-tensioning's, that started no earlier than it, and
    whose peak comes when the rejected front arrives there (directly or after one reflection at an end,
    within one element crossing) carries that front and is numerical too."""

    impedance: float  # N s/m
    stiffness: float  # N/m
    mass: float  # kg (inf: both ends kinematic)
    crossing_time: float  # s
    margin: float = 1.5
    travel_time: float = 0.0  # s, the axial wave's crossing of the whole cable, L / c (the episode rule)
    length: float = 0.0  # m, the cable's unstretched length L (arc lengths; 0: no episode rule)

    def bound(self, static_tension: float, speed: float, rise_time: float) -> float:
        """The largest plausible peak (N) for a relative end speed ``speed`` and rise time ``rise_time``."""
        energy = math.sqrt(self.stiffness * self.mass) if math.isfinite(self.mass) else math.inf
        quasi = min(energy, self.stiffness * max(rise_time, 0.0))
        return self.margin * (2.0 * abs(static_tension) + max(speed, 0.0) * (2.0 * self.impedance + quasi))

    def arrivals(self, source: float, target: float) -> list:
        """Travel times (s) of an axial front from arc length ``source`` to arc length ``target``: the direct
        path and the paths reflected once at either end (s = 0, s = L), each at most 2 L long; ascending."""
        L = self.length
        paths = {abs(source - target), source + target, 2.0 * L - source - target}
        return sorted(p / L * self.travel_time for p in paths)

    def arrival(self, event, rejected):
        """The travel time (s) of the ``rejected`` front along the path whose arrival at ``event``'s location
        holds ``event``'s peak (docs/snap_guard.md, "One slack episode, one verdict"), or None. The front
        leaves between the rejected rise's start and its peak; the peak it makes at the location lies within
        one element crossing of its arrival (a DG element's polynomial spreads a front over the element: its
        end nodes feel it from when it enters the element until it has left it)."""
        start = rejected.time - rejected.rise_time
        for travel in self.arrivals(rejected.arc_length, event.arc_length):
            if start + travel - self.crossing_time <= event.time <= rejected.time + travel + self.crossing_time:
                return travel
        return None

    def same_episode(self, event, rejected) -> bool:
        """True when ``event`` (at another location) belongs to the slack episode of the ``rejected``
        re-tensioning and is carried by its front (docs/snap_guard.md, "One slack episode, one verdict"): the
        slack periods overlap, ``event`` started its own re-tensioning no earlier than the rejected one, and
        its peak comes when the rejected front arrives at its location (:meth:`arrival`: directly or after one
        reflection at an end, within one element crossing). A re-tensioning that peaks at another time is not
        that front (a front that arrived has passed within an element crossing; a rise of its own peaks when
        the ends' motion has stretched the cable) and is judged on its own."""
        if self.margin <= 0.0 or self.length <= 0.0 or event.location == rejected.location:
            return False
        rise_start, rejected_rise_start = event.time - event.rise_time, rejected.time - rejected.rise_time
        exit_time = event.slack_start + event.slack_duration
        return (rise_start >= rejected_rise_start and exit_time >= rejected.slack_start
                and self.arrival(event, rejected) is not None)

    def carried(self, event, origin, speed: float) -> NumericalSnapWarning:
        """The warning replacing ``event``, which carries the front of the rejected ``origin``
        (:meth:`same_episode`)."""
        travel = self.arrival(event, origin)
        late = event.time - origin.time
        reason = (f"peaked {late * 1e3:.3g} ms after the rejected re-tensioning at {origin.location} in the same "
                  f"slack episode, when its front arrives ({(travel or 0.0) * 1e3:.3g} ms of axial travel, within "
                  f"an element crossing {self.crossing_time * 1e3:.3g} ms): it carries that front "
                  f"(rejected peak {origin.tension_peak / 1e3:.4g} kN at t = {origin.time:.3f} s)")
        return NumericalSnapWarning(time=event.time, location=event.location, arc_length=event.arc_length,
                                    tension_peak=event.peak_tension,
                                    bound=self.bound(event.static_tension, speed, event.rise_time),
                                    rise_time=event.rise_time, crossing_time=self.crossing_time,
                                    relative_speed=speed, static_tension=event.static_tension,
                                    slack_start=event.slack_start, reason=reason)

    def check(self, event, speed: float, front_time: float | None = None):
        """None when ``event`` is plausible, else the :class:`NumericalSnapWarning` replacing it.

        The rise checked (and in the bound's ``k t_r``) is the front's: from the last upward crossing of
        the re-tension level before the peak (``front_time``, from the detector) when that is shorter
        than ``event.rise_time`` (from the slack level): a tension that left slack earlier and stood
        between the two levels must not lend its waiting time to a front that then rose in one step."""
        if self.margin <= 0.0:
            return None
        rise = event.rise_time
        if front_time is not None and math.isfinite(front_time) and 0.0 <= front_time < rise:
            rise = front_time
        bound = self.bound(event.static_tension, speed, rise)
        reasons = []
        if event.peak_tension > bound:
            reasons.append(f"peak {event.peak_tension / 1e3:.4g} kN above the impedance/energy bound "
                           f"{bound / 1e3:.4g} kN (relative end speed {speed:.3g} m/s)")
        if rise < self.crossing_time:
            origin = "" if rise == event.rise_time else " from the re-tension level"
            reasons.append(f"rise{origin} {rise * 1e3:.3g} ms shorter than the axial wave's crossing "
                           f"of an element ({self.crossing_time * 1e3:.3g} ms)")
        if not reasons:
            return None
        return NumericalSnapWarning(time=event.time, location=event.location, arc_length=event.arc_length,
                                    tension_peak=event.peak_tension, bound=bound, rise_time=rise,
                                    crossing_time=self.crossing_time, relative_speed=speed,
                                    static_tension=event.static_tension, slack_start=event.slack_start,
                                    reason="; ".join(reasons))


KINEMATIC_END_KINDS = ("prescribed", "fixed", "clamped")


def snap_guard(config, element_length: float) -> SnapGuard:
    """The guard of a simulation ``config`` (cable, ends, body, ``snap.guard_margin``) whose shortest
    element (DG) or segment (hybrid) is ``element_length`` m long."""
    cab = config.cable
    EA = float(cab.EA)
    if cab.material == "table" and len(cab.table_strain) > 1:
        eps = np.asarray(cab.table_strain, float)
        ten = np.asarray(cab.table_tension, float)
        EA = max(EA, float(np.max(np.diff(ten) / np.diff(eps))))
    kinds = (config.ship_end.kind, config.vehicle_end.kind)
    mass = float(cab.gamma0) * float(cab.length)
    if all(k in KINEMATIC_END_KINDS for k in kinds):
        mass = math.inf
    for kind in kinds:
        if kind == "body":
            body = config.body
            mass += float(body.mass) + float(np.max(body.added_mass))
    c = math.sqrt(EA / float(cab.gamma0))
    return SnapGuard(impedance=math.sqrt(EA * float(cab.gamma0)), stiffness=EA / float(cab.length), mass=mass,
                     crossing_time=float(element_length) / c if c > 0 else 0.0, margin=float(config.snap.guard_margin),
                     travel_time=float(cab.length) / c if c > 0 else 0.0, length=float(cab.length))
