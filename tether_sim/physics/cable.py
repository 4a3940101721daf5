"""Cable (tether) properties [PE2020 Sec. 2, Table 2-3; GP Table 1]. SI units throughout.

Arc length s is the unstretched material coordinate, s = 0 at the ship (fairlead) end and
s = L at the vehicle (cage) end.
"""

from dataclasses import dataclass

from tether_sim.spec import param


@dataclass(frozen=True)
class CableProperties:
    """Material, geometry and hydrodynamic coefficients of a uniform cable."""

    length: float = param(200.0, unit="m", doc="unstretched length L", min=1e-3, max=1e5)
    EA: float = param(45.5e6, unit="N", doc="axial stiffness EA", min=0.0, max=1e12)
    gamma0: float = param(3.01, unit="kg/m", doc="mass per unstretched metre gamma0", min=1e-9, max=1e5)
    diameter: float = param(0.03, unit="m", doc="hydrodynamic diameter d (drag, added mass)", min=1e-6, max=10.0)
    density: float = param(7153.0, unit="kg/m^3", doc="material density rho_c; cross-section A = gamma0/rho_c [PE2020 Eq. 14]", min=1e-3, max=1e5)
    EI: float = param(0.0, unit="N m^2", doc="bending stiffness EI (0: perfectly flexible, no bending work)", min=0.0, max=1e12)
    GIp: float = param(0.0, unit="N m^2", doc="torsional stiffness GI_p [PE2020 Eq. 19, 21]", min=0.0, max=1e12)
    torque: float = param(0.0, unit="N m", doc="constant torsional moment GI_p*Omega_1 set by the end conditions [PE2020 Eq. 21]; 0 = torsion off", min=-1e9, max=1e9)
    damping: float = param(0.0, unit="N s", doc="axial material damping zeta in T = EA*eps + zeta*deps/dt [PE2020 Eq. 22]", min=0.0, max=1e12)
    bending_damping: float = param(0.0, unit="N m^2 s", doc="bending damping zeta_b in M = i x (EI*kappa + zeta_b*dkappa/dt) [PE2020 Eq. 19]", min=0.0, max=1e12)
    material: str = param("bilinear", doc="tension-strain law: bilinear (no compression, Eq. 22), linear, table", choices=("bilinear", "linear", "table"))
    compression: str = param("none", doc="what a slack cable with bending pushes: none (PE2020 Eq. 22 as printed: the material shortens freely, bending acts on the curved line only; as MoorDyn) or buckling (the push is carried up to the Euler load EI (pi P / h)^2 of the mesh's shortest wave: a rod that must buckle to shorten; mesh-dependent where a slack phase reaches it). Laws without compression only (bilinear, table); no effect without bending. docs/dg_solver.md \"Slack with bending\"", choices=("none", "buckling"))
    table_strain: tuple = param((), unit="-", doc="strain points of the tabulated law (increasing, first 0)")
    table_tension: tuple = param((), unit="N", doc="tension at table_strain (material=table)")
    Cdn: float = param(1.0, doc="normal drag coefficient C_d,perp [PE2020 Eq. 17]", min=0.0, max=100.0)
    Cdt: float = param(0.02, doc="tangential drag coefficient C_dt [PE2020 Eq. 17]", min=0.0, max=100.0)
    Cmn: float = param(1.0, doc="normal added-mass coefficient C_m,perp [PE2020 Eq. 13]", min=0.0, max=100.0)
    Cmt: float = param(0.0, doc="tangential added-mass coefficient C_m,par [PE2020 Eq. 13]", min=0.0, max=100.0)
    breaking_load: float = param(0.0, unit="N", doc="minimum breaking load (MBL) of the cable; 0: not given. Not used by the solvers: tether-sim-report states the largest tension as a fraction of it (utilisation)", min=0.0, max=1e10)

    @property
    def area(self) -> float:
        """Material cross-section A = gamma0 / rho_c (m^2), used for weight and buoyancy."""
        return self.gamma0 / self.density

    @property
    def wave_speed(self) -> float:
        """Axial (snap) wave speed c = sqrt(EA / gamma0) (m/s)."""
        return (self.EA / self.gamma0) ** 0.5
