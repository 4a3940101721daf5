"""Rigid body attached to a cable end [PE2020 Table 1 'rigid body connection', Sec. 6, Table 3].

Body frame FLU (x forward, y left, z up) per REP-103; world frame ENU.
"""

from dataclasses import dataclass

from tether_sim.spec import param


@dataclass(frozen=True)
class RigidBodyProperties:
    """A 6-DOF body (e.g. the ROPOS cage) with Morison-type hydrodynamics per body axis."""

    mass: float = param(4995.0, unit="kg", doc="dry mass m_cg", min=1e-9, max=1e9)
    density: float = param(8448.0, unit="kg/m^3", doc="mean density; displaced volume = mass/density (buoyancy)", min=1e-3, max=1e6)
    added_mass: tuple = param((9200.0, 9200.0, 9200.0), unit="kg", doc="added mass along body x, y, z")
    drag_coefficients: tuple = param((1.3, 1.3, 2.7), doc="quadratic drag coefficients along body x, y, z")
    drag_areas: tuple = param((12.6, 12.6, 7.12), unit="m^2", doc="reference areas of the drag along body x, y, z")
    inertia: tuple = param((19.0e3, 19.0e3, 19.0e3), unit="kg m^2", doc="moments of inertia about body x, y, z (centre of gravity)")
    added_inertia: tuple = param((0.0, 0.0, 0.0), unit="kg m^2", doc="added moments of inertia about body x, y, z")
    rotational_damping: tuple = param((0.0, 0.0, 0.0), unit="N m s", doc="linear rotational damping about body x, y, z")
    attachment: tuple = param((0.0, 0.0, 2.1), unit="m", doc="cable attachment point P in the body frame, from the centre of gravity")
    initial_position: tuple = param((0.0, 0.0, -200.0), unit="m", doc="initial centre-of-gravity position, world frame (overridden by the static solve if enabled)")
