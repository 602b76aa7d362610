//! Point-multipole rotors on fixed sites (dipoles and Buckingham quadrupoles),
//! with open or periodic boundaries and uniform external fields. The energy is
//! a polynomial of the quaternion components, so the quaternion force of
//! eq 14 is its analytic gradient.

mod boundary;
pub mod convention;
mod error;
mod external;
mod kernels;
mod pairs;
mod potential;
mod row_quads;

pub use boundary::{Boundary, MAX_PAIRS};
pub use error::PotentialError;
pub use external::ExternalFields;
pub use potential::MultipolePotential;
