//! Numerical experiments built on the integrators (the harness reports them).
//!
//! * [`every_step`]: a run recording every step, for comparisons with other codes.
//! * [`gear_corrections`]: the note's comparison of scheme A with scheme B and
//!   its corrections.

pub mod every_step;
pub mod gear_corrections;
