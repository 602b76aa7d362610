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
//! * [`observables`]: energies, norm errors and angular velocities of a state.
//! * [`scene`]: scene files (TOML), parsed and validated into typed objects.
//! * [`run`]: the runner, its observers and output files.
//! * [`cli`]: the `quatrot` command line.

#![warn(
    missing_docs,
    trivial_casts,
    unused_import_braces,
    variant_size_differences
)]
#![warn(unused_qualifications, unused_results, rust_2018_idioms)]
#![deny(unused_must_use)]

pub mod checks;
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
pub mod simulation;
pub mod stats;

#[cfg(feature = "python")]
mod python;

pub use quaternion::Quat;
