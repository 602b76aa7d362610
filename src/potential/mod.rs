//! Potential energy of a set of rotors as a function of their orientations.
//!
//! Every term provides the energy, the unconstrained quaternion gradient of
//! eq 14 (`N = -dV/dQ`, computed analytically through `dA/dq_k`), and the
//! space-fixed torques. Eq 13 relates the two: after the projection of the
//! note, `-dV/dQ + (Q.dV/dQ) Q = 2 N_s*Q` with `N_s = (0, torque_space)`.

mod free;
pub mod multipole;
mod term;
mod torque_axes;

pub use free::Free;
pub use multipole::{
    Accuracy, Boundary, ExternalFields, MultipolePotential, PeriodicSum, PotentialError, SumKind,
    SumMethod, SumOptions, SumPath, Surface,
};
pub use term::Potential;
pub use torque_axes::{multipole_torque_axes, symmetric_about, TorqueAxes};
