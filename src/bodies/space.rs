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
        d - self.shift(&self.image_counts(d))
    }

    /// How many box lengths along each axis separate `d` from its minimum
    /// image (zero in open space).
    #[inline]
    pub fn image_counts(&self, d: Vector3<f64>) -> Vector3<f64> {
        match self {
            Space::Open => Vector3::zeros(),
            Space::Periodic(l) => Vector3::from_fn(|k, _| round(d[k] / l[k])),
        }
    }

    /// The shift `counts` box lengths along each axis (zero in open space).
    #[inline]
    pub fn shift(&self, counts: &Vector3<f64>) -> Vector3<f64> {
        match self {
            Space::Open => Vector3::zeros(),
            Space::Periodic(l) => l.component_mul(counts),
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

/// `x.round()` (half away from zero, the sign of zero kept) without the
/// library call `f64::round` compiles to on targets without SSE4.1: the
/// pair loops' minimum images spent a third of their instructions there.
#[inline]
fn round(x: f64) -> f64 {
    // Every float of magnitude 2^52 or more is a whole number (NaN too is
    // its own rounding).
    if x.abs() >= 4_503_599_627_370_496.0 || x.is_nan() {
        return x;
    }
    let whole = (x as i64 as f64).copysign(x);
    let rest = x - whole;
    if rest >= 0.5 {
        whole + 1.0
    } else if rest <= -0.5 {
        whole - 1.0
    } else {
        whole
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rounding is `f64::round` bit for bit: halves, their neighbours,
    /// signed zeros, large and non-finite values.
    #[test]
    fn round_is_the_library_round() {
        let mut xs = vec![
            0.0, -0.0, 0.3, -0.3, 2.5, -2.5, 1e300, -1e300, 4.5e15, -4.5e15,
        ];
        xs.extend([
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            f64::MIN_POSITIVE,
        ]);
        for half in [0.5f64, 1.5, 2.5, 1e6 + 0.5] {
            for x in [
                half,
                f64::from_bits(half.to_bits() + 1),
                f64::from_bits(half.to_bits() - 1),
            ] {
                xs.extend([x, -x]);
            }
        }
        for x in xs {
            assert_eq!(round(x).to_bits(), x.round().to_bits(), "{x:e}");
        }
        assert!(round(f64::NAN).is_nan());
    }
}
