"""``dg.resolution: auto``: the DG mesh (N, P) and safety factor dg.cfl chosen for a snap-peak tolerance.

The rule is a table of MEASURED errors, not a model. ``benchmarks/studies/resolution_ladder.py`` ran the
ROPOS slack-snap case (circular fairlead orbit a = 2 m, f = 0.2 Hz) on ladders of N at P = 2, 3
and 4 and dg.cfl 0.8 (full ladders N = 1 ... 32 below the reference), and at dg.cfl 0.5, 0.65
and 1.0 (N = 2 ... 8), against a converged explicit reference (N = max(10, ceil(L / 20 m)),
P = 4, cfl 0.5) for lengths 100-2000 m, a stiff (ROPOS, EA = 45.5 MN) and a soft (EA = 2 MN)
cable, bending off and on (EI = 0 and EI* = 2620 N m^2) and the cage or a free end; the figures
are in docs/data/resolution_ladder.csv and docs/resolution_ladder.md (which also explains the rule).

``WORST_ERROR[end][L][(P, cfl)][N]`` (tether_sim/solvers/resolution_table.py, generated from the
CSV) is the worst relative error of the first snap peak (largest end tension of the first
full-amplitude forcing period, ship and vehicle end, resampled at 200 Hz) over every case
measured with vehicle end kind ``end`` (body = the cage, free) at length L, and of the bending
effect on it (peak(EI*) - peak(EI = 0), relative to the peak) where both were measured. The rule:

1. per ladder (P, cfl): the smallest N >= 2 whose worst error, and that of every finer N of that
   ladder, is at most SAFETY x tolerance (SAFETY = 1/2: a margin for what the ladders did not
   vary, e.g. the forcing). "Every finer N" because the error is not monotone in N (at L = 975 m,
   P = 3: 0.5 % at N = 3 and 4, 2.1 % at N = 6, 0.3 % from N = 12 on): a lucky zero crossing is
   not convergence. Only a ladder with every rung from N = 2 to the finest below the reference
   at that length takes part (the dg.cfl 0.5 / 0.65 / 1.0 ladders stop at N = 8: they take part
   at 100 and 200 m only);
2. between two measured lengths, both bracketing lengths must satisfy 1 for the same (P, cfl, N)
   (the range is that of the measured lengths: 100-2000 m with the cage, 200-1730 m free);
3. dg.cfl at most MAX_CFL = 0.8: cfl 1.0 is the stability limit itself (calibrated on a straight
   taut cable, docs/dg_solver.md) and cfl 1.1 gave +68 % at L = 200 m (2026-11-21);
4. of the rungs that pass 1-3, the cheapest by the cost model :func:`cost` (substeps per
   simulated second from the solver's own stability rule x a per-substep cost fitted to the
   ladders' thread CPU).

Outside what was measured (length, EA, EI, end kinds, explicit damping, a uniform mesh) the rule
refuses with a ConfigError rather than guess: set dg.resolution to manual there.
"""

import math
from dataclasses import dataclass, replace

from tether_sim.errors import ConfigError
from tether_sim.solvers.dg.timestep import stable_dt
from tether_sim.solvers.resolution_table import WORST_ERROR
from tether_sim.solvers.config import SPLIT_DAMPING

SAFETY = 0.5
MAX_CFL = 0.8
MIN_ELEMENTS = 2  # one element has no inner element boundary: never chosen (975 m free end measured it "good")
LADDER_NS = (1, 2, 3, 4, 6, 8, 12, 16, 24, 32)  # the rungs of benchmarks/studies/resolution_ladder.py

# Per-substep cost model (thread CPU): COST_FIXED + (COST_NODE + COST_NODE_BENDING [EI > 0]) x N (P + 1),
# least squares over the stiff-cable rows of docs/data/resolution_ladder.csv (benchmarks/studies/
# resolution_report.cost_fit; test/solvers/test_resolution.py checks these are that fit, rounded).
# At the coarse 1 % meshes the fixed part dominates, so the choice is mostly "fewest substeps".
COST_FIXED = 18.4e-6  # s per substep
COST_NODE = 0.331e-6  # s per substep per node N (P + 1)
COST_NODE_BENDING = 0.388e-6  # s, extra with bending (the LDG gradient and its flux)

EA_RANGE = (2.0e6, 45.5e6)  # N
EI_MAX = 2620.0  # N m^2
SHIP_KINDS = ("prescribed",)
ROPOS_CABLE = {"EA": 45.5e6, "gamma0": 3.01, "damping": 45.5e3, "EI": 0.0, "bending_damping": 0.0}


@dataclass(frozen=True)
class Resolution:
    """The chosen mesh and what it was chosen for."""

    n_elements: int
    order: int
    cfl: float
    tolerance: float
    measured_error: float  # worst measured first-snap-peak error of this rung at the bracketing lengths
    cost: float = 0.0  # modelled thread CPU per simulated second (s), :func:`cost`

    def describe(self) -> str:
        return (f"N = {self.n_elements}, P = {self.order}, dg.cfl {self.cfl:g} for a first-snap-peak "
                f"tolerance of {100 * self.tolerance:g} % (worst measured error {100 * self.measured_error:.2f} %)")


def reference_elements(length):
    """N of the ladders' converged reference: h <= 20 m, at least 10 elements."""
    return max(10, math.ceil(length / 20.0))


def finest_rung(length):
    """The finest ladder rung below the reference at ``length``: a ladder must reach it to count."""
    return max(n for n in LADDER_NS if n < reference_elements(length))


def cost(length, n, order, cfl, cable=None):
    """Modelled thread CPU (s) per simulated second of a uniform mesh of ``n`` elements of order
    ``order`` at ``cfl``: substeps per second (the solver's stability rule, explicit damping)
    times the per-substep cost model above. ``cable``: dict with EA, gamma0, damping, EI,
    bending_damping (default: the ROPOS cable, alpha = 0)."""
    c = dict(ROPOS_CABLE, **(cable or {}))
    dt = cfl * stable_dt([length / n], order, c["EA"], c["gamma0"], c["damping"], c["EI"], c["bending_damping"])
    per_node = COST_NODE + (COST_NODE_BENDING if c["EI"] > 0.0 else 0.0)
    return (COST_FIXED + per_node * n * (order + 1)) / dt


def _complete(ladder, length):
    """A ladder counts at a measured length if it has every rung N = 2 ... finest_rung(length)."""
    return all(n in ladder for n in LADDER_NS if 2 <= n <= finest_rung(length))


def _brackets(table, length):
    measured = sorted(table)
    return sorted({max(x for x in measured if x <= length), min(x for x in measured if x >= length)})


def _settled(ladders, tol):
    """The smallest N >= MIN_ELEMENTS measured at every bracketing length whose error, and that of
    every finer rung measured at each of them, is within ``tol`` (``ladders``: one {N: error} per
    bracketing length), with its worst error; else None."""
    common = sorted(set.intersection(*(set(errs) for errs in ladders)))
    for n in common:
        if n >= MIN_ELEMENTS and all(e <= tol for errs in ladders for m, e in errs.items() if m >= n):
            return n, max(errs[n] for errs in ladders)
    return None


def _settled_range(ladders, tol):
    """A winch run's rung: settled (:func:`_settled`) at each measured length on its own, and the finest
    of those N. At a length whose ladder stops below that N the mesh is finer than its settled rung and
    than every rung measured there (the ladders stop below the converged reference), so it counts as
    settled there too; worst error: at each length, the largest error over its measured rungs >= N's
    settled rung there."""
    found = [_settled([errs], tol) for errs in ladders]
    if any(f is None for f in found):
        return None
    n = max(f[0] for f in found)
    worst = max(max(e for m, e in errs.items() if m >= f[0]) for errs, f in zip(ladders, found))
    return n, worst


def candidates(length, tolerance, end="body", cable=None, up_to=None):
    """Every ladder's settled rung near ``length`` (rule points 1-3), cheapest first:
    [(cost, n, order, cfl, worst_error)]. ``up_to`` (a winch run, length varying in [length, up_to]):
    the rung must be settled at every measured length bracketing or inside that range; its cost is
    taken at the shortest length (the most substeps per simulated second)."""
    if end not in WORST_ERROR:
        raise ConfigError(f"dg.resolution auto: vehicle_end.kind {end} was not measured "
                          f"(only {', '.join(WORST_ERROR)}); set dg.resolution: manual (docs/resolution_ladder.md)")
    table = WORST_ERROR[end]
    lo, hi = min(table), max(table)
    top = length if up_to is None else max(length, up_to)
    for x, what in ((length, "cable.length" if up_to is None else "the shortest winch length"),
                    (top, "the longest winch length")):
        if not lo <= x <= hi:
            raise ConfigError(f"dg.resolution auto: {what} {x:g} m is outside the range measured with "
                              f"vehicle_end.kind {end}, {lo:g}-{hi:g} m; set dg.resolution: manual (docs/resolution_ladder.md)")
    brackets = sorted(set(_brackets(table, length)) | set(_brackets(table, top))
                      | {x for x in table if length <= x <= top})
    out = []
    for order, cfl in sorted(set.intersection(*(set(table[x]) for x in brackets))):
        if cfl > MAX_CFL or not all(_complete(table[x][(order, cfl)], x) for x in brackets):
            continue
        ladders = [table[x][(order, cfl)] for x in brackets]
        found = (_settled(ladders, SAFETY * tolerance) if up_to is None
                 else _settled_range(ladders, SAFETY * tolerance))
        if found is not None:
            out.append((cost(length, found[0], order, cfl, cable), found[0], order, cfl, found[1]))
    return sorted(out)


def choose(length, tolerance, end="body", cable=None, up_to=None):
    """N, P, cfl for a tether of unstretched length ``length`` (m) with vehicle end kind ``end`` and
    first-snap-peak ``tolerance``: the cheapest of the settled rungs of :func:`candidates`
    (``up_to``: a winch run whose length varies over [length, up_to])."""
    found = candidates(length, tolerance, end, cable, up_to)
    if not found:
        raise ConfigError(
            f"dg.snap_tolerance {tolerance:g}: no measured ladder near L = {length:g} m settles within "
            f"{SAFETY:g} x the tolerance; set dg.resolution: manual with a finer mesh (docs/resolution_ladder.md)")
    c, n, order, cfl, worst = found[0]
    return Resolution(n_elements=n, order=order, cfl=cfl, tolerance=tolerance, measured_error=worst, cost=c)


def check_domain(config):
    """ConfigError naming the first setting outside what the ladders measured."""
    cable, dg = config.cable, config.dg
    problems = []
    if not EA_RANGE[0] <= cable.EA <= EA_RANGE[1]:
        problems.append(f"cable.EA {cable.EA:g} N is outside the measured {EA_RANGE[0]:g}-{EA_RANGE[1]:g} N")
    if cable.EI > EI_MAX:
        problems.append(f"cable.EI {cable.EI:g} N m^2 is above the measured {EI_MAX:g} N m^2")
    if config.ship_end.kind not in SHIP_KINDS:
        problems.append(f"ship_end.kind {config.ship_end.kind} was not measured (only {', '.join(SHIP_KINDS)})")
    if config.vehicle_end.kind not in WORST_ERROR:
        problems.append(f"vehicle_end.kind {config.vehicle_end.kind} was not measured (only {', '.join(WORST_ERROR)})")
    if dg.damping != "explicit":
        problems.append(f"dg.damping {dg.damping} was not measured")
    if dg.element_lengths or dg.fixed_time_step > 0.0:
        problems.append("dg.element_lengths / dg.fixed_time_step set (the ladders use uniform meshes and the stability rule)")
    if problems:
        raise ConfigError("dg.resolution auto: " + "; ".join(problems)
                          + "; set dg.resolution: manual (docs/resolution_ladder.md)")


def resolve(config, given=()):
    """``config`` with dg.n_elements/order/cfl set by the rule when dg.resolution is auto (else unchanged).

    ``given``: the dotted keys the user set explicitly; an explicit dg.n_elements, dg.order or
    dg.cfl that differs from the rule's choice is a ConfigError (two answers to one question).
    """
    dg = config.dg
    if dg.resolution != "auto" or config.solver != "dg":
        return config
    check_domain(config)
    cab = config.cable
    cable = {"EA": cab.EA, "gamma0": cab.gamma0, "damping": cab.damping, "EI": cab.EI,
             "bending_damping": cab.bending_damping}
    shortest, longest = float(cab.length), None
    winch = getattr(config, "winch", None)
    if winch is not None and winch.enabled:  # fixed elements over a varying length: settled over the whole range
        shortest = min(shortest, float(winch.min_length))
        longest = max(float(cab.length), float(winch.max_length))
    chosen = choose(shortest, float(dg.snap_tolerance), config.vehicle_end.kind, cable, longest)
    values = {"n_elements": chosen.n_elements, "order": chosen.order, "cfl": chosen.cfl}
    for name, value in values.items():
        if f"dg.{name}" in given and getattr(dg, name) != value:
            raise ConfigError(f"dg.{name} = {getattr(dg, name)} is set while dg.resolution is auto (which chooses "
                              f"{value}); remove dg.{name} or set dg.resolution: manual")
    return replace(config, dg=replace(dg, **values))


# Slack phases on fine meshes (docs/dg_solver.md "Slack with bending", docs/performance.md): on the ROPOS 200 m
# slack-snap case, P = 4, explicit, bending factor 100, cable.compression none (2026-11-27): where the cage element
# re-tensions, Eq. 22's Kelvin-Voigt term switches on at its outermost Gauss point with the strain rate there, which
# grows as the node spacing h / P shrinks: a one-step cage event of 87 kN at 2.5 m (N = 20) and 264 kN at 1.25 m
# (N = 40), both rejected by the snap guard; the snaps after them agree within 0.2 % between the two meshes (ship
# 232.1 / 232.5 kN, cage 225.1 / 225.5 kN). dg.damping implicit at 1.25 m was not clean even without bending
# (2026-11-26: numerical events of 8-11 MN, all rejected by the snap guard), nor with bending factor 1 and the
# compression cap (2026-11-27: tensions of MN through the slack phase).
FINE_MESH_SPACING = 2.5  # m


def bending_mesh_warning(length, n_elements, order, EI, element_lengths=(), damping="explicit") -> str:
    """A warning (one line) when bending is on or dg.damping is implicit and the DG node spacing min(h) / P
    is below FINE_MESH_SPACING, else "". ``element_lengths``: dg.element_lengths, relative weights scaled to
    ``length``. A caution drawn from measured cases, not a proven bound."""
    implicit = damping in SPLIT_DAMPING
    if not (EI > 0.0 or implicit):
        return ""
    from tether_sim.solvers.work import mesh_sizes

    h = float(min(mesh_sizes(length, n_elements, element_lengths)))  # dg.element_lengths are weights
    spacing = h / max(int(order), 1)
    if spacing >= FINE_MESH_SPACING:
        return ""
    what = " and ".join(x for x in (f"bending (EI {EI:g} N m^2)" if EI > 0.0 else "",
                                    f"dg.damping {damping}" if implicit else "") if x)
    return (f"{what} on a DG node spacing of {spacing:.3g} m (h / P): below {FINE_MESH_SPACING:g} m slack phases show "
            f"larger one-step end-tension events where a slack part re-tensions (Eq. 22's damping switching on at the "
            f"outermost Gauss point; ROPOS 200 m slack-snap case, explicit, bending factor 100: 87 kN at 2.5 m, 264 kN at "
            f"1.25 m, rejected by the snap guard, the snaps after them within 0.2 % of each other; docs/dg_solver.md "
            f"\"Slack with bending\" (6)): check numerical warnings; they are smaller on a coarser mesh")


def mesh_summary(n_elements, order, cfl, resolution, snap_tolerance) -> str:
    """One line naming the DG mesh in use and how it was chosen (node log, report)."""
    how = (f"dg.resolution auto, first-snap-peak tolerance {100 * float(snap_tolerance):g} %"
           if resolution == "auto" else "dg.resolution manual")
    return f"N = {n_elements}, P = {order}, dg.cfl {float(cfl):g} ({how})"


# dg.damping implicit where a cable with bending can reach its compression cap (physics/constitutive.py): the
# implicit step freezes, for a whole substep, which points are damped and where the total tension is held at the
# cap, and in a slack phase in which the cap binds that is not right. ROPOS 200 m slack-snap case, bending factor 1
# (2026-11-27, benchmarks/studies/slack_bending_ladder.py --set dg.damping=implicit): N = 20 published a 93 kN cage
# "snap" at 5.44 s where explicit damping has a rejected one-step event; N = 40 carried tensions of MN through
# the slack phase (10 numerical warnings), and at dg.cfl 0.25 published snaps of 193 kN (ship) and 384 kN (cage)
# against 218 and 210 kN explicit. Where the cap stays above what the cable carries it is clean: bending factor
# 100 (cap 414 kN / 1.65 MN) matches explicit damping within 1.4e-5 at N = 20 and 40.
def implicit_damping_refusal(config) -> str:
    """The reason (one line) why dg.damping implicit is refused for ``config``, or "". Refused when the cable has
    bending, a law without compression, ``cable.compression: buckling`` and a compression cap EI (pi P / h)^2 on its longest element below the
    weight it carries (the cable's dry weight plus a body end's submerged weight: the compression a slack phase
    can pile up is of that size)."""
    from tether_sim.physics.bodies import submerged_weight
    from tether_sim.physics.constitutive import LAW_CODES, LAW_LINEAR, cap_stiffness, compression_cap
    from tether_sim.solvers.work import element_sizes

    cab, dg = config.cable, config.dg
    law = LAW_CODES.get(cab.material, LAW_LINEAR)
    if config.solver != "dg" or dg.damping not in SPLIT_DAMPING or cap_stiffness(cab) <= 0.0 or law == LAW_LINEAR:
        return ""
    h = float(max(element_sizes(config)))
    pc = compression_cap(law, cap_stiffness(cab), int(dg.order), h)
    weight = float(cab.gamma0) * config.environment.g * float(cab.length)
    if "body" in (config.ship_end.kind, config.vehicle_end.kind):
        weight += max(submerged_weight(config.body, config.environment), 0.0)
    if pc >= weight:
        return ""
    return (f"dg.damping {dg.damping} with bending (cable.EI {cab.EI:g} N m^2) and cable.compression buckling on a cable "
            f"without compression (cable.material {cab.material}): its compression cap EI (pi P / h)^2 = {pc:.4g} N (h = {h:.4g} m, P = "
            f"{dg.order}) is below the weight it carries ({weight:.4g} N), so slack phases reach it, and there the "
            f"implicit damping step is not right (ROPOS 200 m, bending factor 1: cage snaps of 93-384 kN against 210 kN "
            f"with explicit damping; docs/dg_solver.md \"Slack with bending\"): use dg.damping explicit or cable.compression none")
