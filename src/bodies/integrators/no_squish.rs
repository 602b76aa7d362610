//! Velocity Verlet for the centres with NO_SQUISH for the rotations, as
//! LAMMPS `fix rigid/nve/small` does (Miller et al., J. Chem. Phys. 116,
//! 8649 (2002); Kamberaj, Low and Neal, J. Chem. Phys. 122, 224114 (2005)).
//!
//! One step of `dt` ([`BodyKicked`]): half kicks `v += dt/2 F / m` and, on
//! the conjugate quaternion momentum `P = 2 Q*(0, L_b)`,
//! `P += dt/2 * 2 Q*(0, A(Q) tau)` (the rotors' NO_SQUISH kick); drift
//! `R += dt v` and the free rotation of the rotors' NO_SQUISH
//! ([`NoSquishOptions`], its options); forces and torques at the new
//! configuration (one evaluation); half kicks again.
//!
//! Properties: second order, symplectic, time reversible; total linear
//! momentum is conserved to round-off (the site forces of each pair are
//! opposite), and the angular momentum of an open cluster too. Stores per
//! body `P` (4) besides the state, and the last evaluation.

use super::kicked::BodyKicked;
use crate::integrators::NoSquishOptions;

/// Velocity Verlet + NO_SQUISH.
pub type BodyNoSquish = BodyKicked<NoSquishOptions>;
