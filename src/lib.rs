//! quatrot: rotational dynamics of rigid rotors in quaternion form.
//!
//! Source: M. P. Allen, "Quaternion parameter algorithms" (equation numbers
//! in the doc comments refer to that note; corrections are in ERRATA.md).
//!
//! * [`quaternion`]: the conventions (stated once) and the quaternion algebra.
//! * [`rotor`]: the rotor model (fixed site, inertia, body multipoles).
//! * [`lattice`]: sc, bcc and fcc lattices of fixed sites.
//! * [`potential`]: the potential-energy trait and its terms.
//! * [`integrators`]: the integrator trait, Allen's schemes A and B, baselines.
//! * [`experiments`]: the note's experiment on the corrections of scheme B.
//! * [`observables`]: energies, norm errors and angular velocities of a state;
//!   the total dipole and the orientational order of a configuration.
//! * [`analysis`]: post-processing of recorded series and trajectories
//!   (time-correlation functions, block averages, the dielectric constant).
//! * [`scene`]: scene files (TOML), parsed and validated into typed objects.
//! * [`run`]: the runner, its observers and output files.
//! * [`cli`]: the `quatrot` command line.

pub mod analysis;
pub mod cli;
pub mod experiments;
pub mod integrators;
pub mod lattice;
pub mod observables;
pub mod parallel;
pub mod potential;
pub mod quaternion;
pub mod rotor;
pub mod run;
pub mod scene;

#[cfg(feature = "python")]
mod python;

pub use quaternion::Quat;
