//! A trajectory of per-rotor values as the analysis reads it: frame-major,
//! checked once for shape and finiteness.

use super::error::AnalysisError;
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// Per-rotor values over frames, frame-major: element `t * rotors + i` is
/// rotor `i` at frame `t` (the layout of `TrajectoryFrames` and of a numpy
/// array of shape `(frames, rotors, ...)`).
#[derive(Clone, Copy, Debug)]
pub struct Frames<'a, T> {
    data: &'a [T],
    rotors: usize,
    what: &'a str,
}

/// A value the analysis can check for finiteness.
pub trait Finite {
    /// What is wrong with the value, if anything: a component not finite
    /// or, for an orientation, a zero quaternion.
    fn problem(&self) -> Option<&'static str>;
}

impl Finite for Quat {
    fn problem(&self) -> Option<&'static str> {
        if !self.is_finite() {
            Some("must be finite")
        } else if self.try_normalize().is_none() {
            Some("must be a nonzero quaternion (an orientation)")
        } else {
            None
        }
    }
}

impl Finite for Vector3<f64> {
    fn problem(&self) -> Option<&'static str> {
        (!self.iter().all(|x| x.is_finite())).then_some("must be finite")
    }
}

impl<'a, T: Finite> Frames<'a, T> {
    /// `data` of `rotors` (>= 1) values per frame and at least one frame,
    /// every value finite; errors name the input `what` and the first bad
    /// element as `what[frame, rotor]`.
    pub fn new(data: &'a [T], rotors: usize, what: &'a str) -> Result<Self, AnalysisError> {
        if rotors == 0 {
            return Err(AnalysisError::new(what, "needs at least one rotor"));
        }
        if data.is_empty() || data.len() % rotors != 0 {
            return Err(AnalysisError::new(
                what,
                format!(
                    "needs a whole number (>= 1) of frames of {rotors} rotors, got {} values",
                    data.len()
                ),
            ));
        }
        if let Some((k, problem)) = data
            .iter()
            .enumerate()
            .find_map(|(k, v)| v.problem().map(|p| (k, p)))
        {
            return Err(AnalysisError::new(
                format!("{what}[{}, {}]", k / rotors, k % rotors),
                problem,
            ));
        }
        Ok(Frames { data, rotors, what })
    }
}

impl<T: Copy> Frames<'_, T> {
    /// The number of frames.
    pub fn frames(&self) -> usize {
        self.data.len() / self.rotors
    }

    /// The number of rotors per frame.
    pub fn rotors(&self) -> usize {
        self.rotors
    }

    /// The name of the input, for errors about it.
    pub fn what(&self) -> &str {
        self.what
    }

    /// Rotor `rotor` at every frame, in order.
    pub fn rotor(&self, rotor: usize) -> impl Iterator<Item = T> + '_ {
        self.data.iter().skip(rotor).step_by(self.rotors).copied()
    }

    /// The values of frame `frame`.
    pub fn frame(&self, frame: usize) -> &[T] {
        &self.data[frame * self.rotors..(frame + 1) * self.rotors]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shape errors and the first non-finite element are named.
    #[test]
    fn bad_input_is_named() {
        let q = [Quat::IDENTITY; 6];
        assert!(Frames::new(&q, 4, "orientations")
            .unwrap_err()
            .to_string()
            .starts_with("orientations: needs a whole number"));
        assert!(Frames::new(&q[..0], 2, "orientations").is_err());
        assert!(Frames::new(&q, 0, "orientations").is_err());
        let mut bad = q;
        bad[5] = Quat::ZERO;
        assert_eq!(
            Frames::new(&bad, 2, "orientations").unwrap_err().path,
            "orientations[2, 1]"
        );
        let f = Frames::new(&q, 3, "orientations").unwrap();
        assert_eq!((f.frames(), f.rotors(), f.rotor(1).count()), (2, 3, 2));
    }
}
