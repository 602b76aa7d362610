"""Point-multipole rotor clusters in OpenMM's AmoebaMultipoleForce, shared by
the fixture generator (``fixtures/gen_multipoles.py``) and the live check
(``checks/multipoles_openmm.py``).

Each rotor is three OpenMM particles: the multipole site and two massless
frame atoms placed at ``site + FRAME_ARM * R(Q) e_z`` and
``site + FRAME_ARM * R(Q) e_x``, so that OpenMM's ZThenX local frame is the
rotor's body frame and the "molecular" multipoles are the body multipoles.
Frame atoms carry zero multipoles, and each rotor's atoms are in one another's
covalent-12 lists. NoCutoff, Direct polarisation, zero polarisability.

Units: OpenMM works in nm, e, kJ/mol. quatrot's reduced units take lengths in
nm, charges in e and 4 pi eps0 = 1, so reduced energies and torques are
OpenMM's divided by ONE_4PI_EPS0 (kJ mol^-1 nm e^-2). Quadrupoles: OpenMM
expects Buckingham's Theta divided by 3 (see src/potential/multipole/convention.rs).
"""

from __future__ import annotations

import math

import numpy as np
import openmm as mm
from openmm import unit

# Coulomb's constant e^2 N_A / (4 pi eps0) in kJ mol^-1 nm, from the CODATA 2018
# exact e and N_A and eps0 = 8.8541878128e-12 F/m (OpenMM 8 uses the same values).
ONE_4PI_EPS0 = 1.602176634e-19**2 * 6.02214076e23 / (4 * math.pi * 8.8541878128e-12) * 1e-3 * 1e9
FRAME_ARM = 0.1  # nm, distance of the frame atoms from the site


def rotation(q):
    """R(Q) = A(Q)^T, body to space, for a scalar-first unit quaternion (eq 7 transposed)."""
    q0, q1, q2, q3 = q
    return np.array(
        [
            [q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
            [2 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 - q0 * q1)],
            [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3],
        ]
    )


def random_orientations(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def random_quadrupole(rng, scale):
    m = rng.uniform(-scale, scale, size=(3, 3))
    s = 0.5 * (m + m.T)
    return s - np.eye(3) * np.trace(s) / 3


def random_cluster(rng, n, kind, spacing=0.5):
    """Sites on a jittered cubic grid (nm) and body multipoles (e nm, Buckingham e nm^2).
    kind: "dipole", "quadrupole" or "mixed" (rotors with a dipole, a quadrupole or both)."""
    edge = math.ceil(round(n ** (1 / 3), 9))
    grid = np.array([(k // (edge * edge), (k // edge) % edge, k % edge) for k in range(n)], float)
    sites = grid * spacing + rng.uniform(-0.1, 0.1, size=(n, 3)) * spacing
    dipoles, quadrupoles = [], []
    for k in range(n):
        has_d = kind == "dipole" or (kind == "mixed" and k % 3 != 1)
        has_q = kind == "quadrupole" or (kind == "mixed" and k % 3 != 0)
        dipoles.append(rng.uniform(-0.05, 0.05, size=3) if has_d else None)
        quadrupoles.append(random_quadrupole(rng, 0.02) if has_q else None)
    return sites, dipoles, quadrupoles


class OpenMMCluster:
    """An OpenMM Context on the Reference platform for one cluster."""

    def __init__(self, sites, dipoles, quadrupoles, pme=None):
        """``pme = (box (3,), cutoff, ewald_error_tolerance)`` for an
        orthorhombic periodic box summed by PME (tin-foil surface), else an
        open cluster (NoCutoff)."""
        self.sites = np.asarray(sites, float)
        system = mm.System()
        force = mm.AmoebaMultipoleForce()
        if pme is None:
            force.setNonbondedMethod(mm.AmoebaMultipoleForce.NoCutoff)
        else:
            box, cutoff, tolerance = pme
            force.setNonbondedMethod(mm.AmoebaMultipoleForce.PME)
            force.setCutoffDistance(cutoff)
            force.setEwaldErrorTolerance(tolerance)
            system.setDefaultPeriodicBoxVectors(*(mm.Vec3(*(np.eye(3)[a] * box[a])) for a in range(3)))
        force.setPolarizationType(mm.AmoebaMultipoleForce.Direct)
        zero3, zero9 = [0.0] * 3, [0.0] * 9
        for k, (mu, theta) in enumerate(zip(dipoles, quadrupoles)):
            site, z_atom, x_atom = 3 * k, 3 * k + 1, 3 * k + 2
            for _ in range(3):
                system.addParticle(0.0)
            mu = zero3 if mu is None else [float(x) for x in mu]
            quad = zero9 if theta is None else [float(x) for x in (np.asarray(theta) / 3.0).ravel()]
            force.addMultipole(0.0, mu, quad, mm.AmoebaMultipoleForce.ZThenX, z_atom, x_atom, -1, 0.0, 0.0, 0.0)
            for _ in range(2):
                force.addMultipole(0.0, zero3, zero9, mm.AmoebaMultipoleForce.NoAxisType, -1, -1, -1, 0.0, 0.0, 0.0)
            force.setCovalentMap(site, mm.AmoebaMultipoleForce.Covalent12, [z_atom, x_atom])
            force.setCovalentMap(z_atom, mm.AmoebaMultipoleForce.Covalent12, [site])
            force.setCovalentMap(x_atom, mm.AmoebaMultipoleForce.Covalent12, [site])
        system.addForce(force)
        platform = mm.Platform.getPlatformByName("Reference")
        self.context = mm.Context(system, mm.VerletIntegrator(1e-3), platform)

    def evaluate(self, orientations):
        """Reduced energy and (n, 3) space-frame torques about each site."""
        n = len(self.sites)
        positions = np.empty((3 * n, 3))
        for k, q in enumerate(orientations):
            r = rotation(q)
            positions[3 * k] = self.sites[k]
            positions[3 * k + 1] = self.sites[k] + FRAME_ARM * r[:, 2]
            positions[3 * k + 2] = self.sites[k] + FRAME_ARM * r[:, 0]
        self.context.setPositions(positions * unit.nanometer)
        state = self.context.getState(getEnergy=True, getForces=True)
        energy = state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
        forces = state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer)
        arms = positions - np.repeat(self.sites, 3, axis=0)
        torques = np.cross(arms, forces).reshape(n, 3, 3).sum(axis=1)
        return energy / ONE_4PI_EPS0, torques / ONE_4PI_EPS0


def calibrate_coulomb_constant():
    """OpenMM's Coulomb constant, measured on two head-to-tail dipoles
    (closed form V = -2 mu^2 / r^3): must equal ONE_4PI_EPS0."""
    mu, r = 0.05, 0.7
    cluster = OpenMMCluster([[0, 0, 0], [0, 0, r]], [np.array([0, 0, mu])] * 2, [None, None])
    energy, _ = cluster.evaluate([[1.0, 0, 0, 0]] * 2)
    return energy * ONE_4PI_EPS0 / (-2 * mu * mu / r**3)


def versions():
    return {"openmm": mm.__version__, "numpy": np.__version__}
