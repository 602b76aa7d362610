//! Velocity Verlet for the centres with the Richardson-extrapolated
//! quaternion update of LAMMPS `fix rigid` and `fix nve/asphere` for the
//! rotations.
//!
//! One step of `dt` ([`BodyKicked`]): half kicks `v += dt/2 F / m` and
//! `L_s += dt/2 tau`; drift `R += dt v` and the rotors' Richardson update
//! of `Q` (two explicit Euler half steps of eq 10 against one whole step,
//! extrapolated and normalised; [`RichardsonOptions`]); forces and torques at
//! the new configuration (one evaluation); half kicks again.
//!
//! Properties: second order; neither symplectic nor time reversible (the
//! quaternion update is explicit and one-sided). Total linear momentum is
//! conserved to round-off, and so is the angular momentum of an open
//! cluster: the kicks add `dt/2 sum (R x F + tau) = 0` (the forces and
//! torques of one configuration are internal), the drift keeps `R x m v`,
//! and the orientation update leaves `L_s` as it is. Stores per body `L_s`
//! (3) besides the state, and the last evaluation.

use super::kicked::BodyKicked;
use crate::integrators::RichardsonOptions;

/// Velocity Verlet + Richardson.
pub type BodyRichardson = BodyKicked<RichardsonOptions>;
