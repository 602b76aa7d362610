//! Numerical experiments built on the integrators (the harness reports them).
//!
//! * [`gear_corrections`]: the note's comparison of scheme A with scheme B and
//!   its corrections.

pub mod gear_corrections;
