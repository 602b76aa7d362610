//! Point-multipole rotors on fixed sites (dipoles and Buckingham quadrupoles),
//! with open or periodic boundaries (a truncated sum, or the Ewald sum:
//! direct on any sites, by FFT on lattices) and uniform external fields. The
//! energy is a polynomial of the quaternion components, so the quaternion
//! force of eq 14 is its analytic gradient.

mod auto_choice;
mod boundary;
pub mod convention;
mod error;
mod ewald;
pub mod ewald_parameters;
mod ewald_terms;
mod external;
mod fft3;
mod field_sum;
mod image_grid;
mod kernels;
mod lattice_fft;
mod lattice_grid;
mod lattice_kernel;
pub mod mesh_ewald;
mod mesh_sum;
mod pairs;
mod periodic_sum;
mod potential;
mod row_quads;
mod sum_method;

pub use auto_choice::{
    AutoChoice, DIRECT_QUADRUPOLE_FACTOR, DIRECT_SECONDS_PER_UNIT, PME_DIPOLE_CALIBRATION,
    PME_QUADRUPOLE_CALIBRATION,
};
pub use boundary::{Boundary, BYTES_PER_PAIR, MAX_PAIRS};
pub use error::PotentialError;
pub use ewald::MAX_WAVE_VECTORS;
pub use ewald_parameters::EwaldParameters;
pub(crate) use ewald_terms::{radial_functions, ChargeDipole};
pub use external::ExternalFields;
pub use lattice_fft::MAX_FFT_BYTES;
pub use lattice_grid::{LatticeGrid, LATTICE_TOLERANCE};
pub use periodic_sum::{Accuracy, PeriodicSum, SumKind, SumOptions, Surface};
pub use potential::MultipolePotential;
pub use sum_method::{SumMethod, SumPath};
