//! The orientational order of one body axis over a trajectory, frame by
//! frame: [`crate::observables::order`]'s `P2`, director, order tensor and
//! `P1` along the director, and `P1` along a fixed space direction, with the
//! per-rotor cosines behind each polar order.
//!
//! Per-rotor values are returned as `(frames, rotors)` arrays here, not
//! recorded as scene series: a series has one CSV column per value, and a
//! column per rotor of a 1000-rotor lattice is a trajectory in disguise
//! (the trajectory already keeps the orientations they follow from). The
//! cosines `cos(theta_i) = u_i.n` are what a distribution of orientations
//! (a histogram over rotors and frames), a local order map or a single
//! rotor's flips are computed from.

use super::frames::Frames;
use crate::observables::order::{nematic_order, polar_order, space_axes};
use crate::quaternion::Quat;
use nalgebra::{Matrix3, Unit, Vector3};
use rayon::prelude::*;

/// The order of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameOrder {
    /// The largest eigenvalue of `Q = <3/2 u u^T - 1/2 I>`.
    pub p2: f64,
    /// `Q`.
    pub q_tensor: Matrix3<f64>,
    /// The eigenvector of `p2`, signed so that `<u>.d >= 0`.
    pub director: Unit<Vector3<f64>>,
    /// `<u>.d`, in `[0, 1]`.
    pub p1: f64,
    /// `u_i.d` of each rotor.
    pub cos_director: Vec<f64>,
    /// `<u>.n` along the given direction `n` (signed), if one was given.
    pub p1_direction: Option<f64>,
    /// `u_i.n` of each rotor, if a direction was given (empty otherwise).
    pub cos_direction: Vec<f64>,
}

/// The order of body axis `axis_body` (unit, body frame) of the rotors in
/// each frame of `orientations` (normalised per rotor, so a drifting `|Q|`
/// does not enter), and its polar order along the unit space `direction`
/// when given. Frames are independent and computed in parallel.
pub fn order_parameters(
    orientations: &Frames<'_, Quat>,
    axis_body: &Unit<Vector3<f64>>,
    direction: Option<&Unit<Vector3<f64>>>,
) -> Vec<FrameOrder> {
    (0..orientations.frames())
        .into_par_iter()
        .map(|f| {
            let u: Vec<Vector3<f64>> = space_axes(orientations.frame(f), axis_body).collect();
            let order = nematic_order(&u).expect("Frames holds at least one rotor per frame");
            let cosines = |n: &Unit<Vector3<f64>>| u.iter().map(|u| u.dot(n)).collect();
            FrameOrder {
                p2: order.p2,
                q_tensor: order.q_tensor,
                director: order.director,
                p1: order.p1,
                cos_director: cosines(&order.director),
                p1_direction: direction.and_then(|n| polar_order(&u, n)),
                cos_direction: direction.map_or_else(Vec::new, cosines),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_3;

    /// Two frames of two rotors: aligned along z, then the second rotor
    /// turned by 60 degrees about y. Frame 1 has `P2 = (1 + 3 cos 60)/4`
    /// about the bisector and `P1 = cos 30` along it, `P1 = (1 + cos 60)/2`
    /// along z; the cosines are each rotor's projection. |Q| does not
    /// matter; without a direction there are no direction values.
    #[test]
    fn frames_follow_the_configuration_order() {
        let turn = Quat::from_axis_angle(&Vector3::y_axis(), FRAC_PI_3);
        let q = [Quat::IDENTITY * 2.0, Quat::IDENTITY, Quat::IDENTITY, turn];
        let frames = Frames::new(&q, 2, "orientations").unwrap();
        let z = Vector3::z_axis();
        let order = order_parameters(&frames, &z, Some(&z));
        assert_eq!(order.len(), 2);
        assert!((order[0].p2 - 1.0).abs() < 1e-15 && (order[0].p1 - 1.0).abs() < 1e-15);
        assert_eq!(order[0].cos_direction, [1.0, 1.0]);
        let o = &order[1];
        assert!((o.p2 - (1.0 + 3.0 * FRAC_PI_3.cos()) / 4.0).abs() < 1e-14);
        assert!((o.p1 - (FRAC_PI_3 / 2.0).cos()).abs() < 1e-14);
        let bisector = Vector3::new((FRAC_PI_3 / 2.0).sin(), 0.0, (FRAC_PI_3 / 2.0).cos());
        assert!((o.director.into_inner() - bisector).norm() < 1e-14);
        assert!((o.p1_direction.unwrap() - 0.75).abs() < 1e-15);
        assert!((o.cos_direction[1] - 0.5).abs() < 1e-15);
        for c in &o.cos_director {
            assert!((c - (FRAC_PI_3 / 2.0).cos()).abs() < 1e-14);
        }
        assert!((o.q_tensor.trace()).abs() < 1e-15);
        let plain = order_parameters(&frames, &z, None);
        assert!(plain[1].p1_direction.is_none() && plain[1].cos_direction.is_empty());
    }

    /// A polar order along a direction opposite to the axes is negative.
    #[test]
    fn polar_order_along_a_direction_is_signed() {
        let q = [Quat::IDENTITY; 3];
        let frames = Frames::new(&q, 3, "orientations").unwrap();
        let down = -Vector3::z_axis();
        let order = order_parameters(&frames, &Vector3::z_axis(), Some(&down));
        assert_eq!(order[0].p1_direction, Some(-1.0));
        assert_eq!(order[0].cos_direction, [-1.0; 3]);
    }
}
