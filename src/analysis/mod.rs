//! Post-processing of recorded runs: what rotor-lattice users measure from
//! a trajectory or a series.
//!
//! * [`time_correlation`]: the orientational `C1(t)`, `C2(t)` of body axes
//!   and vector autocorrelations (angular velocity), by FFT over all time
//!   origins and rotors.
//! * [`block_average`](mod@block_average): the mean of a correlated series and its error
//!   (Flyvbjerg-Petersen blocking, Jonsson's automatic level).
//! * [`dielectric`]: the static dielectric constant from the fluctuation of
//!   the total dipole, with the formula of the boundary.
//! * [`order`](mod@order): the orientational order of a body axis frame by
//!   frame (`P2`, director, `P1` along it or along a direction, per-rotor
//!   cosines).
//! * [`displacement`]: the mean-squared displacement of moving bodies'
//!   unwrapped centres and the self-diffusion coefficient from it.
//! * [`radial`]: the radial distribution function of body centres.
//! * [`frames`]: the frame-major trajectory view the functions read.
//!
//! The order parameters and the total dipole of one configuration are
//! observables: [`crate::observables::order`],
//! [`crate::observables::polarization`].

mod autocorrelation;
pub mod block_average;
pub mod dielectric;
pub mod displacement;
mod error;
pub mod frames;
pub mod order;
pub mod radial;
pub mod time_correlation;

pub use block_average::{block_average, BlockAverage, BlockLevel};
pub use dielectric::{dielectric_constant, DielectricBoundary, DielectricConstant};
pub use displacement::{
    mean_squared_displacement, self_diffusion, unwrapped_positions, SelfDiffusion,
};
pub use error::AnalysisError;
pub use frames::Frames;
pub use order::{order_parameters, FrameOrder};
pub use radial::{radial_distribution, RadialDistribution};
pub use time_correlation::{
    lag_times, orientational_correlations, vector_autocorrelation, OrientationalCorrelation,
};
