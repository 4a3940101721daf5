"""Drive any TetherSolver through its public interface and analyse what comes out.

Used by the scenario drivers, the verification tests and the convergence scripts. Nothing here
knows a solver's internals: configurations are built from flat keys through the validated schema
(``io.params.from_flat``), solvers through ``solvers.factory.build_solver``.
"""

import numpy as np

from tether_sim.io.params import from_flat
from tether_sim.solvers.factory import build_solver
from tether_sim.scenarios.references import gauss_points


def make_config(flat: dict, where: str = "scenario"):
    """Validated SimConfig from flat dotted keys (``{"cable.EA": 1e5, ...}``)."""
    return from_flat(dict(flat), where=where)


def make_solver(flat: dict):
    """(config, solver) for flat keys."""
    config = make_config(flat)
    return config, build_solver(config)


def run_sampled(solver, times, arc_lengths=None, motion=None, load=None, keep=("position", "velocity", "tension", "strain")):
    """Advance ``solver`` through ``times`` (increasing, > solver.time) and sample at each.

    motion(t) -> {end: (position, velocity)} is applied before each ``advance_to(t)`` (the end state
    to reach at t); load(t) -> {end: (force, moment)} likewise (held over the interval).
    Returns a dict of arrays: t (nt,), the SolverState fields in ``keep`` (nt, n, ...), end forces
    ship_force / vehicle_force (nt, 3), ship_tension / vehicle_tension (nt,), plus the per-substep
    end tensions ``sub_t``, ``sub_ship``, ``sub_vehicle`` from ``drain_end_tensions``.
    """
    out = {k: [] for k in keep}
    out.update(t=[], ship_force=[], vehicle_force=[], ship_tension=[], vehicle_tension=[],
               ship_moment=[], vehicle_moment=[], substeps=0)
    solver.drain_end_tensions()
    sub = ([], [], [])
    for t in times:
        if motion is not None:
            for end, (pos, vel) in motion(t).items():
                solver.set_end_motion(end, np.asarray(pos, float), np.asarray(vel, float))
        if load is not None:
            for end, (force, moment) in load(t).items():
                solver.set_end_load(end, np.asarray(force, float), np.asarray(moment, float))
        out["substeps"] += solver.advance_to(float(t))
        st = solver.state(arc_lengths)
        for k in keep:
            out[k].append(np.array(getattr(st, k), dtype=float))
        ef = solver.end_forces()
        out["t"].append(st.time)
        for k in ("ship_force", "vehicle_force", "ship_tension", "vehicle_tension", "ship_moment", "vehicle_moment"):
            out[k].append(np.array(getattr(ef, k), dtype=float))
        dt_, ts, tv = solver.drain_end_tensions()
        sub[0].append(np.asarray(dt_, float))
        sub[1].append(np.asarray(ts, float))
        sub[2].append(np.asarray(tv, float))
    res = {k: (np.array(v) if k != "substeps" else v) for k, v in out.items()}
    res["sub_t"], res["sub_ship"], res["sub_vehicle"] = (np.concatenate(x) if x else np.zeros(0) for x in sub)
    res["arc_length"] = np.array(solver.state(arc_lengths).arc_length, dtype=float)
    return res


def crossing_time(t, y, level, after=-np.inf):
    """First time (linear interpolation) after ``after`` at which y rises through ``level``."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    idx = np.nonzero((y[1:] >= level) & (y[:-1] < level) & (t[1:] > after))[0]
    if idx.size == 0:
        return np.nan
    i = idx[0]
    return float(t[i] + (level - y[i]) * (t[i + 1] - t[i]) / (y[i + 1] - y[i]))


def zero_crossings(t, y):
    """All times at which y changes sign (linear interpolation), both directions."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    idx = np.nonzero(np.signbit(y[1:]) != np.signbit(y[:-1]))[0]
    return t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])


def period_from_crossings(t, y):
    """Mean period from the first and last zero crossings (half a period between crossings)."""
    z = zero_crossings(t, y)
    if z.size < 2:
        return np.nan
    return float(2.0 * (z[-1] - z[0]) / (z.size - 1))


def dominant_frequency(t, y):
    """Frequency (Hz) of the largest spectral peak of a uniformly sampled signal (mean removed),
    refined by fitting a sinusoid around the FFT peak (least squares over frequency)."""
    t = np.asarray(t, float)
    y = np.asarray(y, float) - np.mean(y)
    dt = t[1] - t[0]
    n = 8 * t.size
    spec = np.abs(np.fft.rfft(y * np.hanning(t.size), n))
    f = np.fft.rfftfreq(n, dt)
    k = int(np.argmax(spec[1:]) + 1)
    df = f[1] - f[0]

    def misfit(freq):
        basis = np.stack([np.cos(2 * np.pi * freq * t), np.sin(2 * np.pi * freq * t), np.ones_like(t)], axis=1)
        coef, res, *_ = np.linalg.lstsq(basis, y, rcond=None)
        return float(np.sum((basis @ coef - y) ** 2))

    grid = np.linspace(f[k] - 2 * df, f[k] + 2 * df, 81)
    best = grid[int(np.argmin([misfit(g) for g in grid]))]
    fine = np.linspace(best - grid[1] + grid[0], best + grid[1] - grid[0], 81)
    return float(fine[int(np.argmin([misfit(g) for g in fine]))])


def amplitude_spectrum(t, y):
    """One-sided amplitude spectrum (f in Hz, |Y|) of a uniformly sampled signal, mean removed."""
    t = np.asarray(t, float)
    y = np.asarray(y, float) - np.mean(y)
    Y = np.abs(np.fft.rfft(y)) * 2.0 / y.size
    return np.fft.rfftfreq(y.size, t[1] - t[0]), Y


def quadrature_points(config, points_per_element=None):
    """Gauss points/weights on the solver's uniform mesh, exact for its polynomial fields."""
    n = config.dg.n_elements
    p = points_per_element or config.dg.order + 3
    return gauss_points(n, p, config.cable.length)


def mechanical_energy(velocity, strain, position, weights, config, tension_law="linear"):
    """Kinetic + elastic + gravitational energy of a cable in vacuum or air (J).

    Elastic energy per metre 0.5 EA eps^2 (linear law) or 0.5 EA max(eps,0)^2 (bilinear);
    potential w z with w = g gamma0 (buoyancy omitted: use fluid_density = 0 for this measure).
    """
    cab = config.cable
    v2 = np.sum(np.asarray(velocity) ** 2, axis=1)
    eps = np.asarray(strain)
    if tension_law == "bilinear":
        eps = np.maximum(eps, 0.0)
    z = np.asarray(position)[:, 2]
    density = 0.5 * cab.gamma0 * v2 + 0.5 * cab.EA * eps**2 + config.environment.g * cab.gamma0 * z
    return float(np.sum(weights * density))


def sag_below_chord(position):
    """Largest vertical distance of sampled points below the straight chord between the ends."""
    r = np.asarray(position)
    p0, p1 = r[0], r[-1]
    horiz = np.linalg.norm((r - p0)[:, :2], axis=1)
    span = np.linalg.norm((p1 - p0)[:2])
    chord_z = p0[2] + (p1[2] - p0[2]) * horiz / span
    return float(np.max(chord_z - r[:, 2]))


def scenario_config_path(name):
    """Path of a scenario parameter file ``config/<name>.yaml`` (source tree or ament share)."""
    from pathlib import Path

    local = Path(__file__).resolve().parents[2] / "config" / f"{name}.yaml"
    if local.exists():
        return local
    try:
        from ament_index_python.packages import get_package_share_directory

        return Path(get_package_share_directory("tether_sim")) / "config" / f"{name}.yaml"
    except Exception:  # noqa: BLE001 - no ament index: report the source-tree path
        return local


def load_scenario(name, overrides=None, build=True):
    """(config, solver) from ``config/<name>.yaml`` with flat overrides (solver None if not build)."""
    from tether_sim.io.params import load_config

    config = load_config(scenario_config_path(name), overrides=dict(overrides or {}))
    return config, (build_solver(config) if build else None)


def figure_dir(out=None):
    """Directory for PNG figures (created): ``out`` or ``docs/figures`` of the source tree."""
    from pathlib import Path

    path = Path(out) if out else Path(__file__).resolve().parents[2] / "docs" / "figures"
    path.mkdir(parents=True, exist_ok=True)
    return path
