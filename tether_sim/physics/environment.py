"""The water, gravity, current and seabed the cable lives in [PE2020 Eq. 12-17].

Frames follow REP-103: world ENU, z up; the still-water surface is z = 0 and depth is -z.
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
