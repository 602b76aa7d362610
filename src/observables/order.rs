//! Orientational order of a configuration, for one body axis `e` (unit,
//! body frame) carried by every rotor: its space direction per rotor
//! `u_i = R(Q_i) e` (`Q_i` normalised), the polar order `P1 = <u>.n` along a
//! direction `n`, and the nematic order `P2`, the largest eigenvalue of the
//! order tensor `Q = <3/2 u u^T - 1/2 I>` (symmetric, traceless), whose
//! eigenvector is the director `d` (de Gennes & Prost, The Physics of
//! Liquid Crystals, 2nd ed., section 2.1). `<...>` is the mean over rotors.
//!
//! `P2` is 1 when every axis is parallel or antiparallel to `d`, and tends
//! to 0 for isotropic axes as `N` grows (for finite `N` it is positive,
//! `O(N^-1/2)`: the largest eigenvalue of a noisy zero tensor).

use crate::checks::{num, InputError};
use crate::quaternion::Quat;
use nalgebra::{Matrix3, Unit, Vector3};

/// The nematic order of a set of axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NematicOrder {
    /// `Q = <3/2 u u^T - 1/2 I>`.
    pub q_tensor: Matrix3<f64>,
    /// The largest eigenvalue of `Q`, in `[0, 1]` (`Q` is traceless).
    pub p2: f64,
    /// The unit eigenvector of `p2`, signed so that `<u>.d >= 0`.
    pub director: Unit<Vector3<f64>>,
    /// The polar order along the director, `<u>.d >= 0`.
    pub p1: f64,
}

/// `v / |v|`, or `None` unless `v` is finite and nonzero.
pub fn unit_axis(v: &Vector3<f64>) -> Option<Unit<Vector3<f64>>> {
    if !v.iter().all(|x| x.is_finite()) {
        return None;
    }
    let norm = v.norm();
    if norm.is_finite() && norm > 0.0 {
        return Unit::try_new(*v, 0.0);
    }
    // |v| overflowed (1e200) or underflowed (1e-300): rescaled first, so
    // that every finite nonzero axis is one (the plain division gave a zero
    // "unit" vector or none).
    let largest = v.amax();
    (largest > 0.0).then(|| Unit::new_normalize(v / largest))
}

/// [`unit_axis`] of an axis given as input at `path` (an analysis' body
/// axes, the order's axis and direction, the axis of a rotation): the one
/// check that an axis is finite and nonzero.
pub fn checked_unit_axis(path: &str, v: &Vector3<f64>) -> Result<Unit<Vector3<f64>>, InputError> {
    unit_axis(v).ok_or_else(|| {
        InputError::new(
            path,
            format!(
                "must be finite and nonzero, got [{}, {}, {}]",
                num(v.x),
                num(v.y),
                num(v.z)
            ),
        )
    })
}

/// The space direction `u_i = R(Q_i) e` of the body axis `e` for each
/// orientation (normalised first: a drifting `|Q|` does not scale `u`).
pub fn space_axes<'a>(
    orientations: &'a [Quat],
    axis_body: &'a Unit<Vector3<f64>>,
) -> impl Iterator<Item = Vector3<f64>> + 'a {
    orientations
        .iter()
        .map(move |q| q.try_normalize().unwrap_or(*q).body_to_space(axis_body))
}

/// The polar order `P1 = <u>.n` along the unit direction `n` (signed, in
/// `[-1, 1]`); `None` for no axes.
pub fn polar_order(axes: &[Vector3<f64>], direction: &Unit<Vector3<f64>>) -> Option<f64> {
    mean(axes).map(|m| m.dot(direction))
}

/// `Q`, `P2`, the director and `P1` along it; `None` for no axes.
pub fn nematic_order(axes: &[Vector3<f64>]) -> Option<NematicOrder> {
    let mean_axis = mean(axes)?;
    let n = axes.len() as f64;
    let q_tensor = axes
        .iter()
        .fold(Matrix3::zeros(), |q, u| q + u * u.transpose())
        * (1.5 / n)
        - Matrix3::identity() * 0.5;
    let eigen = q_tensor.symmetric_eigen();
    let largest = eigen.eigenvalues.imax();
    let d = eigen.eigenvectors.column(largest).into_owned();
    // The eigenvector's sign is arbitrary: point it along the mean axis (and,
    // for an apolar set, make its first nonzero component positive).
    let along = d.dot(&mean_axis);
    let first = d.iter().copied().find(|x| *x != 0.0).unwrap_or(1.0);
    let sign = if along != 0.0 {
        along.signum()
    } else {
        first.signum()
    };
    let director = Unit::new_normalize(d * sign);
    Some(NematicOrder {
        q_tensor,
        p2: eigen.eigenvalues[largest],
        director,
        p1: mean_axis.dot(&director),
    })
}

fn mean(axes: &[Vector3<f64>]) -> Option<Vector3<f64>> {
    (!axes.is_empty()).then(|| axes.iter().sum::<Vector3<f64>>() / axes.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Perfect polar order: P1 = P2 = 1 and the director is the common axis;
    /// flipping half of the axes keeps P2 = 1 and gives P1 = 0.
    #[test]
    fn aligned_and_antiparallel_axes() {
        let d = Vector3::new(1.0, 2.0, -2.0) / 3.0;
        let aligned = vec![d; 4];
        let order = nematic_order(&aligned).unwrap();
        assert!((order.p2 - 1.0).abs() < 1e-14);
        assert!((order.p1 - 1.0).abs() < 1e-14);
        assert!((order.director.into_inner() - d).norm() < 1e-14);
        let apolar = vec![d, -d, d, -d];
        let order = nematic_order(&apolar).unwrap();
        assert!((order.p2 - 1.0).abs() < 1e-14 && order.p1.abs() < 1e-14);
        assert!((order.q_tensor.trace()).abs() < 1e-14);
    }

    /// The director's sign whatever sign the eigen-solver picks: along the
    /// mean axis for a polar set (P1 > 0, also when the mean axis has a
    /// negative first component); for an apolar set, whose mean axis is
    /// zero, with its first nonzero component positive.
    #[test]
    fn the_director_points_along_the_mean_axis_or_else_its_first_component_is_positive() {
        // Directions on a spiral over the sphere, and some with zero components.
        let spiral = (0..40).map(|k| {
            let z = 1.0 - (2 * k + 1) as f64 / 40.0;
            let phi = 2.399963 * k as f64;
            let r = (1.0 - z * z).sqrt();
            Vector3::new(r * phi.cos(), r * phi.sin(), z)
        });
        let special = [
            Vector3::new(0.0, -0.6, 0.8),
            Vector3::new(0.0, 0.6, -0.8),
            Vector3::new(-0.6, 0.0, -0.8),
            Vector3::new(0.0, 0.0, -1.0),
            -Vector3::x(),
        ];
        for u in spiral.chain(special) {
            let polar = nematic_order(&[u, u, u]).unwrap();
            assert!((polar.director.into_inner() - u).norm() < 1e-14, "{u:?}");
            assert!((polar.p1 - 1.0).abs() < 1e-14, "{u:?}");
            let apolar = nematic_order(&[u, -u]).unwrap();
            let first = u.iter().copied().find(|x| *x != 0.0).unwrap();
            let expected = u * first.signum();
            assert!(
                (apolar.director.into_inner() - expected).norm() < 1e-14,
                "{u:?}"
            );
        }
    }

    /// Axes spread evenly in a plane (the six directions +-x, +-y, (x+-y)/sqrt2
    /// ...): Q has eigenvalues (1/4, 1/4, -1/2), so P2 = 1/4 with the
    /// director in the plane; the three Cartesian axes give Q = 0.
    #[test]
    fn planar_and_isotropic_sets() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let planar = [
            Vector3::x(),
            Vector3::y(),
            Vector3::new(s, s, 0.0),
            Vector3::new(s, -s, 0.0),
        ];
        let order = nematic_order(&planar).unwrap();
        assert!((order.p2 - 0.25).abs() < 1e-14);
        assert!(order.director.z.abs() < 1e-12);
        let cubic = [Vector3::x(), Vector3::y(), Vector3::z()];
        assert!(nematic_order(&cubic).unwrap().q_tensor.norm() < 1e-15);
        assert!(nematic_order(&[]).is_none());
    }

    /// The space axis is the column of R(Q): body z of a rotor turned by 90
    /// degrees about x points along -y; |Q| does not matter. P1 along a
    /// given direction is the mean projection.
    #[test]
    fn space_axes_and_polar_order() {
        let q = Quat::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2) * 3.0;
        let z = Vector3::z_axis();
        let u: Vec<_> = space_axes(&[q, Quat::IDENTITY], &z).collect();
        assert!((u[0] + Vector3::y()).norm() < 1e-15);
        let p1 = polar_order(&u, &Vector3::z_axis()).unwrap();
        assert!((p1 - 0.5).abs() < 1e-15);
        assert!(unit_axis(&Vector3::zeros()).is_none());
        assert!(unit_axis(&Vector3::new(f64::NAN, 0.0, 1.0)).is_none());
    }

    /// Found by the analysis fuzz (issue 37): an axis of 1e200 became the
    /// zero vector (its norm overflowed) and one of 1e-300 was refused as
    /// zero (its norm underflowed); any finite nonzero axis is a direction.
    #[test]
    fn huge_and_tiny_axes_are_directions() {
        for scale in [1e200, 1e307, 1e-300, 5e-324] {
            let u = unit_axis(&(Vector3::new(3.0, 0.0, -4.0) * scale)).expect("nonzero");
            let expected = Vector3::new(0.6, 0.0, -0.8);
            assert!((u.into_inner() - expected).norm() < 1e-15, "{scale}: {u:?}");
        }
    }

    /// An axis given as input is refused by name when it is zero or not
    /// finite, and normalised otherwise.
    #[test]
    fn checked_axes_name_the_input() {
        assert_eq!(
            checked_unit_axis("axis", &Vector3::zeros())
                .unwrap_err()
                .to_string(),
            "axis: must be finite and nonzero, got [0, 0, 0]"
        );
        assert_eq!(
            checked_unit_axis("axes_body[1]", &Vector3::new(f64::INFINITY, 0.0, 1.0))
                .unwrap_err()
                .to_string(),
            "axes_body[1]: must be finite and nonzero, got [inf, 0, 1]"
        );
        let u = checked_unit_axis("axis", &Vector3::new(0.0, 3.0, 4.0)).unwrap();
        assert!((u.into_inner() - Vector3::new(0.0, 0.6, 0.8)).norm() < 1e-15);
    }
}
