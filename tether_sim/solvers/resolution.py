"""``dg.resolution: auto``: the DG mesh (N, P) and safety factor dg.cfl chosen for a snap-peak tolerance.

The rule is a table of MEASURED errors, not a model. ``benchmarks/resolution_ladder.py`` ran the
ROPOS slack-snap case (circular fairlead orbit a = 2 m, f = 0.2 Hz) on ladders of N at P = 4 and
dg.cfl 0.8 against a converged explicit reference (N = max(10, ceil(L / 20 m)), P = 4, cfl 0.5)
for lengths 100-2000 m, a stiff (ROPOS, EA = 45.5 MN) and a soft (EA = 2 MN) cable, bending off
and on (EI = 0 and EI* = 2620 N m^2) and the cage or a free end; the measured figures are in
docs/data/resolution_ladder.csv and docs/performance.md ("Accuracy-chosen resolution").

``_WORST_ERROR[end][L][N]`` is the worst relative error of the first snap peak (largest end tension
of the first full-amplitude forcing period, ship and vehicle end, resampled at 200 Hz) over every
case measured with vehicle end kind ``end`` (body = the cage, free) at length L, and of the
bending effect on it (peak(EI*) - peak(EI = 0), relative to the peak) where both were measured.
The rule:

1. the smallest N whose worst error, and that of every finer N of the ladder, is at most
   SAFETY x tolerance (SAFETY = 1/2: a margin for what the ladders did not vary, e.g. the
   forcing). "Every finer N" because the error is not monotone in N (at L = 500 m: 0.55 % at
   N = 3, 0.28 % at N = 4, 0.91 % at N = 6): a lucky zero crossing is not convergence;
2. between two measured lengths, both bracketing lengths must satisfy 1 for the same N (the
   range is that of the measured lengths: 100-2000 m with the cage, 200-975 m free);
3. P = 4 and dg.cfl = 0.8, the values every ladder rung ran at (cfl 1.1 was measured to give
   +68 % at L = 200 m in session 2, so no larger factor is ever chosen).

Outside what was measured (length, EA, EI, end kinds, explicit damping, a uniform mesh) the rule
refuses with a ConfigError rather than guess: set dg.resolution to manual there.
"""

from dataclasses import dataclass, replace

from tether_sim.errors import ConfigError

ORDER = 4
CFL = 0.8
SAFETY = 0.5

# vehicle_end.kind -> L (m) -> {N: worst first-snap-peak error (relative) over the cases measured with
# that end at L}, P = 4, cfl 0.8.
# Source: docs/data/resolution_ladder.csv (benchmarks/resolution_ladder.py --table prints this).
_WORST_ERROR = {
    "body": {
        100: {1: 0.0116, 2: 0.0080, 3: 0.0068, 4: 0.0054, 6: 0.0031, 8: 0.0012},
        200: {1: 0.0179, 2: 0.0047, 3: 0.0012, 4: 0.0009, 6: 0.0009, 8: 0.0006},
        500: {1: 0.0310, 2: 0.0168, 3: 0.0056, 4: 0.0029, 6: 0.0092, 8: 0.0043, 12: 0.0016, 16: 0.0015, 24: 0.0011},
        975: {1: 0.0430, 2: 0.0099, 3: 0.0170, 4: 0.0193, 6: 0.0042, 8: 0.0062, 12: 0.0126, 16: 0.0094, 24: 0.0041, 32: 0.0018},
        1730: {1: 0.0848, 2: 0.0225, 3: 0.0061, 4: 0.0002, 6: 0.0016, 8: 0.0009, 12: 0.0011, 16: 0.0013, 24: 0.0007, 32: 0.0009},
        2000: {1: 0.0546, 2: 0.0093, 3: 0.0003, 4: 0.0063, 6: 0.0030, 8: 0.0025, 12: 0.0018, 16: 0.0016, 24: 0.0012, 32: 0.0010},
    },
    "free": {
        200: {1: 0.1276, 2: 0.1030, 3: 0.0167, 4: 0.0014, 6: 0.0011, 8: 0.0004},
        975: {1: 0.0023, 2: 0.0078, 3: 0.0031, 4: 0.0031, 6: 0.0018, 8: 0.0009, 12: 0.0015, 16: 0.0007, 24: 0.0001, 32: 0.0001},
    },
}

EA_RANGE = (2.0e6, 45.5e6)  # N
EI_MAX = 2620.0  # N m^2
SHIP_KINDS = ("prescribed",)


@dataclass(frozen=True)
class Resolution:
    """The chosen mesh and what it was chosen for."""

    n_elements: int
    order: int
    cfl: float
    tolerance: float
    measured_error: float  # worst measured first-snap-peak error of this N at the bracketing lengths

    def describe(self) -> str:
        return (f"N = {self.n_elements}, P = {self.order}, dg.cfl {self.cfl:g} for a first-snap-peak "
                f"tolerance of {100 * self.tolerance:g} % (worst measured error {100 * self.measured_error:.2f} %)")


def choose(length, tolerance, end="body"):
    """N, P, cfl for a tether of unstretched length ``length`` (m) with vehicle end kind ``end`` and
    first-snap-peak ``tolerance``: the smallest N whose measured worst error, and that of every finer
    measured N, is within SAFETY x tolerance at both measured lengths that bracket ``length``."""
    if end not in _WORST_ERROR:
        raise ConfigError(f"dg.resolution auto: vehicle_end.kind {end} was not measured "
                          f"(only {', '.join(_WORST_ERROR)}); set dg.resolution: manual (docs/performance.md)")
    table = _WORST_ERROR[end]
    lo, hi = min(table), max(table)
    if not lo <= length <= hi:
        raise ConfigError(f"dg.resolution auto: cable.length {length:g} m is outside the range measured with "
                          f"vehicle_end.kind {end}, {lo:g}-{hi:g} m; set dg.resolution: manual (docs/performance.md)")
    measured = sorted(table)
    brackets = {max(x for x in measured if x <= length), min(x for x in measured if x >= length)}
    rungs = sorted(set.intersection(*(set(table[x]) for x in brackets)))
    for i, n in enumerate(rungs):
        # n and every finer measured rung within the margin: the error has settled, not crossed zero
        if all(table[x][m] <= SAFETY * tolerance for x in brackets for m in rungs[i:]):
            worst = max(table[x][n] for x in brackets)
            return Resolution(n_elements=n, order=ORDER, cfl=CFL, tolerance=tolerance, measured_error=worst)
    finest = rungs[-1]
    worst = max(table[x][finest] for x in brackets)
    raise ConfigError(
        f"dg.snap_tolerance {tolerance:g}: the finest measured rung near L = {length:g} m (N = {finest}) has "
        f"{100 * worst:.2f} % error, more than {SAFETY:g} x the tolerance; set dg.resolution: manual with a "
        "finer mesh (docs/performance.md)")


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
    if config.vehicle_end.kind not in _WORST_ERROR:
        problems.append(f"vehicle_end.kind {config.vehicle_end.kind} was not measured (only {', '.join(_WORST_ERROR)})")
    if dg.damping != "explicit":
        problems.append("dg.damping implicit was not measured")
    if dg.element_lengths or dg.fixed_time_step > 0.0:
        problems.append("dg.element_lengths / dg.fixed_time_step set (the ladders use uniform meshes and the stability rule)")
    if problems:
        raise ConfigError("dg.resolution auto: " + "; ".join(problems)
                          + "; set dg.resolution: manual (docs/performance.md)")


def resolve(config, given=()):
    """``config`` with dg.n_elements/order/cfl set by the rule when dg.resolution is auto (else unchanged).

    ``given``: the dotted keys the user set explicitly; an explicit dg.n_elements, dg.order or
    dg.cfl that differs from the rule's choice is a ConfigError (two answers to one question).
    """
    dg = config.dg
    if dg.resolution != "auto" or config.solver != "dg":
        return config
    check_domain(config)
    chosen = choose(float(config.cable.length), float(dg.snap_tolerance), config.vehicle_end.kind)
    values = {"n_elements": chosen.n_elements, "order": chosen.order, "cfl": chosen.cfl}
    for name, value in values.items():
        if f"dg.{name}" in given and getattr(dg, name) != value:
            raise ConfigError(f"dg.{name} = {getattr(dg, name)} is set while dg.resolution is auto (which chooses "
                              f"{value}); remove dg.{name} or set dg.resolution: manual")
    return replace(config, dg=replace(dg, **values))


def mesh_summary(n_elements, order, cfl, resolution, snap_tolerance) -> str:
    """One line naming the DG mesh in use and how it was chosen (node log, report)."""
    how = (f"dg.resolution auto, first-snap-peak tolerance {100 * float(snap_tolerance):g} %"
           if resolution == "auto" else "dg.resolution manual")
    return f"N = {n_elements}, P = {order}, dg.cfl {float(cfl):g} ({how})"
