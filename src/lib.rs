//! quatrot: rotational dynamics of rigid rotors in quaternion form.
//!
//! Source: M. P. Allen, "Quaternion parameter algorithms" (equation numbers
//! in the doc comments refer to that note; corrections are in ERRATA.md).
//!
//! The public modules are the library's API. The physics core knows nothing
//! of files, the command line or Python:
//!
//! * [`quaternion`]: the conventions (stated once) and the quaternion algebra.
//! * [`rotor`]: the rotor model (fixed site, inertia, body multipoles).
//! * [`lattice`]: sc, bcc and fcc lattices of fixed sites.
//! * [`bodies`]: rigid bodies that move (translation and rotation).
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
//!
//! The outer layers build physics objects and call them:
//!
//! * [`units`]: physical units (`reduced` or `real`): the constants and the
//!   conversions at the boundary.
//! * [`scene`]: scene files (TOML), read into the physics types.
//! * [`run`]: the outputs of a scene's run, and the run itself.
//!
//! [`InputError`] is the error of every input check (a field path and a
//! message). Internal, not part of the API: the checks every constructor
//! shares (`checks`), the memory limit every size decided by input is
//! checked against before allocation (`memory`, set by the environment
//! variable `QUATROT_MEMORY_LIMIT`), where long computations run
//! (`parallel`), the `quatrot` command line (`cli`) and the Python extension
//! (feature `python`). The binary, the tests and the benchmarks reach the
//! few internals they need through the hidden module `internals`.

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
pub(crate) mod checks;
pub(crate) mod cli;
pub mod dynamics;
pub mod experiments;
pub mod integrators;
pub(crate) mod lanes;
pub mod lattice;
pub(crate) mod memory;
pub mod observables;
pub(crate) mod parallel;
pub mod potential;
pub mod quaternion;
pub mod rotor;
pub mod run;
pub mod scene;
pub mod simulation;
pub mod stats;
pub mod thermostat_hook;
pub mod thermostats;
pub mod units;

#[cfg(feature = "python")]
mod python;

pub use checks::InputError;
pub use quaternion::Quat;

/// What the `quatrot` binary, the tests, the doc examples and the benchmarks
/// reach of the internals: not part of the library's API (hidden from its
/// documentation, no stability promised).
#[doc(hidden)]
pub mod internals {
    pub use crate::checks::from_name;
    pub use crate::cli::main as cli_main;
    pub use crate::memory::{set_limit, LIMIT_VARIABLE};
    pub use crate::parallel::{
        automatic_threads, fixed_threads, on_worker, ROTORS_PER_THREAD, SITES_PER_THREAD,
    };
}
