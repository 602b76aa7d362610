//! quatrot: rotational dynamics of rigid rotors in quaternion form.
//!
//! Source: M. P. Allen, "Quaternion parameter algorithms" (equation numbers
//! in the doc comments refer to that note; corrections are in ERRATA.md).
//!
//! The physics core knows nothing of files, the command line or Python:
//!
//! * [`quaternion`]: the conventions (stated once) and the quaternion algebra.
//! * [`checks`]: the checks of input values every constructor shares.
//! * [`rotor`]: the rotor model (fixed site, inertia, body multipoles).
//! * [`lattice`]: sc, bcc and fcc lattices of fixed sites.
//! * [`memory`]: the memory limit that every size decided by input is
//!   checked against before allocation.
//! * [`potential`]: the potential-energy trait and its terms.
//! * [`integrators`]: the integrator trait, [`integrators::IntegratorSpec`]
//!   (the one dispatch), Allen's schemes A and B, the baselines.
//! * [`thermostat_hook`]: what a thermostat sees of an integrator's step and
//!   what an integrator asks of a thermostat (below both).
//! * [`thermostats`]: Langevin, Bussi and Nose-Hoover chains on the
//!   rotational degrees of freedom, inside the integrators' steps.
//! * [`dynamics`]: an integrator paired with its thermostat (above both).
//! * [`observables`]: energies, norm errors and angular velocities of a state;
//!   the total dipole and the orientational order of a configuration.
//! * [`analysis`]: post-processing of recorded series and trajectories
//!   (time-correlation functions, block averages, the dielectric constant).
//! * [`stats`]: least-squares lines, block means, energy drift.
//! * [`simulation`]: the one run loop, its observers and stop conditions.
//! * [`experiments`]: the note's experiment on the corrections of scheme B.
//! * [`parallel`]: where long computations run (a worker of rayon's pool).
//!
//! The outer layers build physics objects and call them:
//!
//! * [`scene`]: scene files (TOML), read into the physics types.
//! * [`run`]: the outputs of a scene's run, and the run itself.
//! * [`cli`]: the `quatrot` command line; the Python extension (feature
//!   `python`) beside it.

#![warn(
    missing_docs,
    trivial_casts,
    unused_import_braces,
    variant_size_differences
)]
#![warn(unused_qualifications, unused_results, rust_2018_idioms)]
#![deny(unused_must_use)]

#[cfg(test)]
mod allocation_meter;
pub mod analysis;
pub mod bodies;
pub mod checks;
pub mod cli;
pub mod dynamics;
pub mod experiments;
pub mod integrators;
pub mod lattice;
pub mod memory;
pub mod observables;
pub mod parallel;
pub mod potential;
pub mod quaternion;
pub mod rotor;
pub mod run;
pub mod scene;
pub mod simulation;
pub mod stats;
pub mod thermostat_hook;
pub mod thermostats;

#[cfg(feature = "python")]
mod python;

pub use quaternion::Quat;
