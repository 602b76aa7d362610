//! The space bodies move in: open, or a periodic orthorhombic box
//! `[0, L_x) x [0, L_y) x [0, L_z)` (minimum image; positions wrapped with
//! their image counts kept, so trajectories can be unwrapped).

use crate::checks::{derived, each, num, positive, InputError};
use nalgebra::Vector3;

/// Open space or a periodic orthorhombic box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Space {
    /// No boundary.
    Open,
    /// A periodic box with these edge lengths (each > 0).
    Periodic(Vector3<f64>),
}

impl Space {
    /// Checks the box lengths (path `box_lengths[k]`) and that the box
    /// holds a sphere of diameter `2 * reach` (cutoff plus skin) so the
    /// minimum image is the only image within reach.
    pub fn check(&self, reach: f64) -> Result<(), InputError> {
        if let Space::Periodic(lengths) = self {
            each(lengths.as_slice(), positive).map_err(|e| e.at("box_lengths"))?;
            if let Some(k) = (0..3).find(|&k| lengths[k] < 2.0 * reach) {
                return Err(InputError::new(
                    format!("box_lengths[{k}]"),
                    format!(
                        "must be at least twice the cutoff plus the skin ({}), got {}",
                        derived(2.0 * reach),
                        num(lengths[k])
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The minimum image of a separation.
    #[inline]
    pub fn minimum_image(&self, d: Vector3<f64>) -> Vector3<f64> {
        match self {
            Space::Open => d,
            Space::Periodic(l) => Vector3::from_fn(|k, _| d[k] - l[k] * (d[k] / l[k]).round()),
        }
    }

    /// Wraps `x` into the box, adding the number of box lengths crossed to
    /// `image`.
    pub fn wrap(&self, x: &mut Vector3<f64>, image: &mut [i64; 3]) {
        if let Space::Periodic(l) = self {
            for k in 0..3 {
                let mut shift = (x[k] / l[k]).floor();
                let mut y = x[k] - shift * l[k];
                // The subtraction can round to just outside [0, L).
                if y < 0.0 {
                    y += l[k];
                    shift -= 1.0;
                }
                if y >= l[k] {
                    y -= l[k];
                    shift += 1.0;
                }
                x[k] = y;
                image[k] += shift as i64;
            }
        }
    }

    /// The volume, `None` in open space.
    pub fn volume(&self) -> Option<f64> {
        match self {
            Space::Open => None,
            Space::Periodic(l) => Some(l.x * l.y * l.z),
        }
    }
}
