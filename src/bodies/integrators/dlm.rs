//! Velocity Verlet for the centres with the Dullweber-Leimkuhler-McLachlan
//! splitting for the rotations (J. Chem. Phys. 107, 5840 (1997)), as LAMMPS
//! `fix nve/sphere update dipole/dlm` and HOOMD-blue's rigid bodies do.
//!
//! One step of `dt` ([`BodyKicked`]): half kicks `v += dt/2 F / m` and
//! `L_b += dt/2 A(Q) tau` (eq 6); drift `R += dt v` and the rotors' DLM
//! free rotation (exact rotations about body axes 1, 2, 3, 2, 1 for
//! `dt/2, dt/2, dt, dt/2, dt/2`; [`DlmOptions`], its options); forces and
//! torques at the new configuration (one evaluation); half kicks again.
//!
//! Properties: second order, symplectic (a composition of exact flows of
//! Hamiltonian pieces), time reversible; total linear momentum is conserved
//! to round-off, and the angular momentum of an open cluster too (every
//! piece conserves it). Stores per body `L_b` (3) besides the state, and the
//! last evaluation.

use super::kicked::BodyKicked;
use crate::integrators::DlmOptions;

/// Velocity Verlet + DLM.
pub type BodyDlm = BodyKicked<DlmOptions>;
