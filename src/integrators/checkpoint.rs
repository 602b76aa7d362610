//! The flat checkpoint layouts of all integrators: values of one kind
//! (quaternions, 3-vectors) written one after the other in storage order, and
//! the checks of a checkpoint handed back to `restore`.
//!
//! Layouts: the baselines write their per-rotor arrays back to back (no
//! header); the Gear schemes write `[dt, Nordsieck vectors...]`.

use super::IntegratorError;
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// A value with a fixed number of `f64` components in storage order.
pub trait Components {
    /// The number of components.
    const LEN: usize;
    /// The components, in storage order.
    fn components(&self) -> &[f64];
    /// The components, mutable.
    fn components_mut(&mut self) -> &mut [f64];
}

impl Components for Quat {
    const LEN: usize = 4;
    fn components(&self) -> &[f64] {
        &self.0
    }
    fn components_mut(&mut self) -> &mut [f64] {
        &mut self.0
    }
}

impl Components for f64 {
    const LEN: usize = 1;
    fn components(&self) -> &[f64] {
        std::slice::from_ref(self)
    }
    fn components_mut(&mut self) -> &mut [f64] {
        std::slice::from_mut(self)
    }
}

impl Components for Vector3<f64> {
    const LEN: usize = 3;
    fn components(&self) -> &[f64] {
        self.as_slice()
    }
    fn components_mut(&mut self) -> &mut [f64] {
        self.as_mut_slice()
    }
}

/// Appends the components of every value.
pub fn write_values<T: Components>(values: &[T], out: &mut Vec<f64>) {
    for v in values {
        out.extend_from_slice(v.components());
    }
}

/// Reads `values.len()` values from the front of `data`, returning the rest;
/// `data` must hold at least that many components.
pub fn read_values<'a, T: Components>(data: &'a [f64], values: &mut [T]) -> &'a [f64] {
    let mut rest = data;
    for v in values {
        let c = v.components_mut();
        let (head, tail) = rest.split_at(c.len());
        c.copy_from_slice(head);
        rest = tail;
    }
    rest
}

/// Checks a baseline checkpoint: exactly `rotors * per_rotor` finite values.
pub fn check_length(state: &[f64], rotors: usize, per_rotor: usize) -> Result<(), IntegratorError> {
    if state.len() != rotors * per_rotor || state.iter().any(|x| !x.is_finite()) {
        return Err(IntegratorError::BadCheckpoint(format!(
            "expected {} finite values ({rotors} rotors x {per_rotor}), got {}",
            rotors * per_rotor,
            state.len()
        )));
    }
    Ok(())
}

/// Checks a Gear checkpoint laid out as `[dt, data...]` for its data length
/// and returns the data. The `dt` slot is not compared: a restart compares
/// `dt` once, with the rest of the run's identity (`run::Checkpoint::check`),
/// so `restore` requires a setup with the checkpoint's `dt`.
pub fn checkpoint_data(state: &[f64], data_len: usize) -> Result<&[f64], IntegratorError> {
    match state.split_first() {
        Some((_, data)) if data.len() == data_len => Ok(data),
        Some((_, data)) => Err(IntegratorError::BadCheckpoint(format!(
            "expected dt and {data_len} values, got dt and {} values",
            data.len()
        ))),
        None => Err(IntegratorError::BadCheckpoint("empty".into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mixed values survive the flat round trip exactly, and the rest is
    /// returned.
    #[test]
    fn values_round_trip() {
        let q = [
            Quat::new(1.0, 2.0, 3.0, 4.0),
            Quat::new(-0.5, 0.0, 7.0, 1e-300),
        ];
        let v = [Vector3::new(8.0, -9.0, 1.5)];
        let mut flat = Vec::new();
        write_values(&q, &mut flat);
        write_values(&v, &mut flat);
        assert_eq!(flat.len(), 11);
        let (mut q2, mut v2) = ([Quat::ZERO; 2], [Vector3::zeros()]);
        let rest = read_values(&flat, &mut q2);
        assert!(read_values(rest, &mut v2).is_empty());
        assert_eq!((q2, v2), (q, v));
    }
}
