//! The state of a body system in a checkpoint, and the checked reads every
//! body integrator's restore shares.
//!
//! Layout of [`BodySystem::write_checkpoint`]: per body (in order) its
//! centre (3), image counts (3), centre velocity (3), orientation (4) and
//! body-frame angular momentum (3); then the neighbour list's state
//! ([`NeighbourList`](super::NeighbourList): its builds and the site
//! positions of its last build). The centres are stored as the run has
//! them (wrapped at the last build) with their image counts, so the
//! restored run wraps and rebuilds at the same steps, bit for bit.

use super::system::BodySystem;
use crate::integrators::checkpoint::{read_values, write_values, Components};
use crate::integrators::gear::{GearValue, Nordsieck};
use crate::integrators::IntegratorError;
use crate::quaternion::Quat;
use crate::thermostat_hook::ThermostatState;
use nalgebra::Vector3;

/// Values per body in [`BodySystem::write_checkpoint`].
const PER_BODY: usize = 16;

/// A checkpoint that does not fit, saying why.
pub(crate) fn bad(why: &str) -> IntegratorError {
    IntegratorError::BadCheckpoint(why.to_string())
}

/// `x` as a count: a whole number in `[0, 2^53]`.
pub(crate) fn whole(x: f64, what: &str) -> Result<u64, IntegratorError> {
    if x.fract() == 0.0 && (0.0..=9.007_199_254_740_992e15).contains(&x) {
        Ok(x as u64)
    } else {
        Err(bad(&format!("{what} must be a whole number >= 0, got {x}")))
    }
}

/// Reads `values.len()` values (`what`) from the front of `data`, returning
/// the rest; refuses data too short to hold them.
pub(crate) fn take_values<'a, T: Components>(
    data: &'a [f64],
    values: &mut [T],
    what: &str,
) -> Result<&'a [f64], IntegratorError> {
    let needed = values.len() * T::LEN;
    if data.len() < needed {
        return Err(bad(&format!(
            "{what}: expected {needed} values, only {} left",
            data.len()
        )));
    }
    Ok(read_values(data, values))
}

/// Reads a Gear scheme's scaled derivatives (`what`) from the front of
/// `data`, returning the rest; refuses data too short to hold them.
pub(crate) fn take_nordsieck<'a, T: GearValue, const N: usize>(
    data: &'a [f64],
    values: &mut Nordsieck<T, N>,
    what: &str,
) -> Result<&'a [f64], IntegratorError> {
    let needed = values.flat_len();
    if data.len() < needed {
        return Err(bad(&format!(
            "{what}: expected {needed} values, only {} left",
            data.len()
        )));
    }
    Ok(values.read_flat(data))
}

/// Reads a thermostat's state from the front of `data`, where it follows
/// `after`, returning the rest; refuses data too short to hold it.
pub(crate) fn take_thermostat<'a>(
    data: &'a [f64],
    state: &mut dyn ThermostatState,
    after: &str,
) -> Result<&'a [f64], IntegratorError> {
    let expected = state.checkpoint_len();
    if data.len() < expected {
        return Err(bad(&format!(
            "expected {expected} thermostat values after {after}, got {}",
            data.len()
        )));
    }
    let (thermostat, rest) = data.split_at(expected);
    state.read_checkpoint(thermostat)?;
    Ok(rest)
}

impl BodySystem {
    /// Appends the bodies' state and the neighbour list's (module doc).
    pub(crate) fn write_checkpoint(&self, out: &mut Vec<f64>) {
        out.reserve(PER_BODY * self.bodies.len());
        for b in &self.bodies {
            out.extend_from_slice(b.position.as_slice());
            out.extend(b.image.map(|i| i as f64));
            out.extend_from_slice(b.velocity.as_slice());
            write_values(&[b.orientation], out);
            out.extend_from_slice(b.angular_momentum_body.as_slice());
        }
        self.neighbours.write_checkpoint(out);
    }

    /// Reads back [`BodySystem::write_checkpoint`]'s output from the front
    /// of `data` into this system (of the same bodies: the checkpoint's
    /// identity says so), returning the rest.
    pub(crate) fn read_checkpoint<'a>(
        &mut self,
        data: &'a [f64],
    ) -> Result<&'a [f64], IntegratorError> {
        let needed = PER_BODY * self.bodies.len();
        if data.len() < needed {
            return Err(bad(&format!(
                "the state of {} bodies: expected {needed} values, got {}",
                self.bodies.len(),
                data.len()
            )));
        }
        let (state, rest) = data.split_at(needed);
        for (i, (b, v)) in self
            .bodies
            .iter_mut()
            .zip(state.chunks(PER_BODY))
            .enumerate()
        {
            let mut image = [0; 3];
            for (k, x) in v[3..6].iter().enumerate() {
                let count = x.abs();
                image[k] =
                    whole(count, &format!("body {i}'s image count"))? as i64 * x.signum() as i64;
            }
            b.position = Vector3::from_column_slice(&v[0..3]);
            b.image = image;
            b.velocity = Vector3::from_column_slice(&v[6..9]);
            b.orientation = Quat::new(v[9], v[10], v[11], v[12]);
            b.angular_momentum_body = Vector3::from_column_slice(&v[13..16]);
        }
        self.neighbours.restore(rest, &self.site_body, &self.space)
    }
}
