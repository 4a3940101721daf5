"""The water, gravity, current and seabed the cable lives in [PE2020 Eq. 12-17].

Frames follow REP-103: world ENU, z up; the still-water surface is z = 0 and depth is -z.
With ``free_surface`` on, water occupies z < eta(x, y, t) (eta = 0 in still water, the wave elevation
with waves); above it the cable is in air (weight, air buoyancy and air drag only). The wetted fraction
of a point ramps smoothly across a band of half-width max(surface_smoothing / 2, the vertical half-extent
of the arc the point stands for): physics/hydrodynamics.wetted_fraction, docs/dg_solver.md "Free surface".
"""

from dataclasses import dataclass

from tether_sim.spec import param


@dataclass(frozen=True)
class Environment:
    """Fluid, gravity, depth-varying current and seabed contact parameters."""

    g: float = param(9.81, unit="m/s^2", doc="gravitational acceleration", min=0.0, max=100.0)
    fluid_density: float = param(1025.0, unit="kg/m^3", doc="fluid density rho_f (1.225 for air)", min=0.0, max=1e4)
    current_z: tuple = param((), unit="m", doc="depths (z, increasing) of the current profile; empty = no current")
    current_x: tuple = param((), unit="m/s", doc="east current at current_z (linear in between, constant outside)")
    current_y: tuple = param((), unit="m/s", doc="north current at current_z")
    seabed: bool = param(False, doc="enable seabed contact [PE2020 Eq. 15-16]")
    seabed_z: float = param(-2000.0, unit="m", doc="seabed height z_g", min=-1e5, max=1e5)
    seabed_stiffness: float = param(3.0e6, unit="N/m^3", doc="ground bulk modulus K_g in f = K_g*d*delta [PE2020 Eq. 15]", min=0.0, max=1e12)
    seabed_damping: float = param(1.0, doc="seabed damping ratio zeta (1 = critical) [PE2020 Eq. 15]", min=0.0, max=100.0)
    seabed_friction: float = param(0.0, doc="dynamic friction coefficient mu [PE2020 Eq. 16]", min=0.0, max=10.0)
    seabed_friction_speed: float = param(0.01, unit="m/s", doc="speed v_mu above which friction is fully developed [PE2020 Eq. 16]", min=1e-9, max=100.0)
    free_surface: bool = param(False, doc="water only below z = eta (0 still, wave elevation with waves): buoyancy, added mass and drag act on the wetted part, air above (off: the whole cable is submerged, PE2020's assumption)")
    air_density: float = param(1.225, unit="kg/m^3", doc="air density above the free surface (air buoyancy and drag)", min=0.0, max=100.0)
    air_Cdn: float = param(1.2, doc="normal drag coefficient in air (free_surface on; 0 = no air drag)", min=0.0, max=100.0)
    air_Cdt: float = param(0.0, doc="tangential drag coefficient in air (free_surface on)", min=0.0, max=100.0)
    surface_smoothing: float = param(1.0, unit="m", doc="minimum width L_s of the band over which a point's wetted fraction goes from 1 to 0 across the surface (smoothstep); the DG solver widens it to the vertical extent of each quadrature point's arc", min=1e-3, max=100.0)
