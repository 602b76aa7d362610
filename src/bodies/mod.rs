//! Rigid bodies that move: centres and orientations, body-fixed sites with
//! Lennard-Jones, charges, point dipoles and point quadrupoles, interacting between bodies
//! (never within one) through Verlet lists, integrated by velocity Verlet
//! with a rotor splitting.
//!
//! * [`site`], [`body_type`]: a site's parameters; a body type's mass,
//!   principal moments and sites in the principal frame.
//! * [`space`]: open space or a periodic orthorhombic box.
//! * [`neighbours`]: cell and Verlet lists with a skin (the cell grid
//!   and its scan in `cells`).
//! * [`lennard_jones`], [`electrostatics`], [`electrostatics_shifted`],
//!   [`electrostatics_ewald`]: the site-pair terms (the electrostatic
//!   methods behind one trait: a cutoff sum, plain or shifted-force, the
//!   particle-mesh Ewald sum).
//! * `pair_pass`: Lennard-Jones and a cutoff sum of charges and dipoles in
//!   one pass over the half neighbour list, four pairs at a time
//!   (`crate::lanes`), its kernels in `pair_kernels`, each site's partners within
//!   a cutoff gathered in `within`.
//! * [`system`], [`evaluate`]: bodies with their interactions; energies,
//!   forces, torques, virial and pressure of a configuration.
//! * [`temperature`]: `T_trans` and `T_rot` with their degrees of freedom.
//! * [`generate`]: random non-overlapping starts and cubic lattices at a
//!   density, with Maxwell-Boltzmann velocities and zero total momentum.
//! * [`overlap`]: overlapping sites at the start.
//! * [`quantity`]: the observables a run of bodies records.
//! * `checkpoint`: the bodies' and the neighbour list's state in a
//!   checkpoint, and the checked reads of the integrators' restores.
//! * [`integrators`]: velocity Verlet + NO_SQUISH, DLM or Richardson, and
//!   the note's Gear schemes A and B with Gear correctors for the centres;
//!   [`BodyIntegrator`], the choice a scene makes (NO_SQUISH so far).

pub mod body_type;
mod cells;
mod checkpoint;
pub mod electrostatics;
pub mod electrostatics_ewald;
pub mod electrostatics_shifted;
pub mod evaluate;
pub mod generate;
pub mod integrators;
pub mod lennard_jones;
pub mod neighbours;
pub mod overlap;
mod pair_kernels;
mod pair_pass;
mod pair_sums;
pub mod quantity;
pub mod site;
pub mod space;
pub mod system;
pub mod temperature;
mod within;

pub use body_type::{BodyType, BodyTypeSpec, ZERO_MOMENT_TOLERANCE};
pub use electrostatics::{CutoffSum, Electrostatics, SiteMultipoles, SiteResponse};
pub use electrostatics_ewald::{direct_costs, BodyEwald, EwaldOptions, DEFAULT_ACCURACY};
pub use electrostatics_shifted::ElectrostaticTruncation;
pub use evaluate::{Evaluation, Scope};
pub use generate::{lattice_start, random_start, Lattice, LatticeStart, RandomStart, MAX_PACKING};
pub use integrators::{
    BodyDlm, BodyGearA, BodyGearB, BodyIntegrator, BodyKicked, BodyNoSquish, BodyRichardson,
};
pub use lennard_jones::{LennardJonesOptions, LennardJonesTerm, Mixing, Truncation};
pub use neighbours::NeighbourList;
pub use overlap::{Overlap, OVERLAP_FRACTION};
pub use quantity::BodyQuantity;
pub use site::{LennardJones, Site};
pub use space::Space;
pub use system::{Body, BodySystem, ElectrostaticsOptions, InteractionOptions};
