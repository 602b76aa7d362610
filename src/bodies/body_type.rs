//! A rigid body type: mass, principal moments of inertia and body-fixed
//! sites in the principal frame.
//!
//! The sites are given in an input frame. The inertia tensor (given, or
//! `I = sum_s m_s (|d_s|^2 1 - d_s d_s^T)` about the sites' centre of mass)
//! is diagonalised by nalgebra's `SymmetricEigen`, `I = R diag(I1, I2, I3)
//! R^T` with `det R = +1` and `I1 <= I2 <= I3`; the body frame is the
//! principal frame, and `R` (principal to input frame) is recorded as
//! [`BodyType::principal_axes`]. A body with one zero moment (within
//! [`ZERO_MOMENT_TOLERANCE`] of the largest) is linear: two rotational
//! degrees of freedom, its axis body axis 1.

use super::site::Site;
use crate::checks::{finite_matrix, num, positive, symmetric, InputError};
use crate::potential::symmetric_about;
use crate::quaternion::Quat;
use crate::thermostat_hook::Spin;
use nalgebra::{Matrix3, Vector3};

/// A principal moment at most this fraction of the largest is zero (a
/// linear body): the rounding of a tensor computed from collinear sites is
/// ~1e-16 of its largest moment.
pub const ZERO_MOMENT_TOLERANCE: f64 = 1e-12;

/// What a body type is built from (the input frame's values).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct BodyTypeSpec {
    /// The sites, at least one.
    pub sites: Vec<Site>,
    /// The mass (> 0); default the sum of the site masses.
    pub mass: Option<f64>,
    /// The inertia tensor about the centre, input frame (symmetric
    /// positive-definite, or with one zero moment); default from the site
    /// masses.
    pub inertia: Option<Matrix3<f64>>,
}

/// A body type ready for dynamics.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyType {
    /// The mass.
    pub mass: f64,
    /// Principal moments `(I1, I2, I3)`, ascending; `I1 = 0` for a linear body.
    pub moments: Vector3<f64>,
    /// The rotation from the principal (body) frame to the input frame: an
    /// orientation `Q_in` of the input frame gives the body orientation
    /// `Q_in * principal_axes`.
    pub principal_axes: Quat,
    /// The centre (centre of mass of the sites, or the input origin when
    /// they have no mass) in the input frame.
    pub centre: Vector3<f64>,
    /// The sites in the body frame, relative to the centre.
    pub sites: Vec<Site>,
}

impl BodyType {
    /// Builds the type; errors name the field (`sites`, `sites[2].charge`,
    /// `mass`, `inertia`).
    pub fn new(spec: &BodyTypeSpec) -> Result<BodyType, InputError> {
        if spec.sites.is_empty() {
            return Err(InputError::new("sites", "a body needs at least one site"));
        }
        for (k, site) in spec.sites.iter().enumerate() {
            site.check().map_err(|e| e.at(&format!("sites[{k}]")))?;
        }
        let site_mass: f64 = spec.sites.iter().map(|s| s.mass).sum();
        let mass = match spec.mass {
            Some(m) => positive(m).map_err(|e| e.at("mass"))?,
            None if site_mass > 0.0 => site_mass,
            None => {
                return Err(InputError::new(
                    "mass",
                    "must be given when the sites have no mass",
                ))
            }
        };
        let centre = if site_mass > 0.0 {
            spec.sites
                .iter()
                .map(|s| s.position * s.mass)
                .sum::<Vector3<f64>>()
                / site_mass
        } else {
            Vector3::zeros()
        };
        let tensor = match &spec.inertia {
            Some(t) => {
                finite_matrix(t).map_err(|e| e.at("inertia"))?;
                symmetric(t).map_err(|e| e.at("inertia"))?;
                t.symmetric_part()
            }
            None => site_inertia(&spec.sites, &centre),
        };
        let (moments, axes) = principal_frame(&tensor)?;
        let to_body = axes.transpose();
        let sites: Vec<Site> = spec
            .sites
            .iter()
            .map(|s| Site {
                position: to_body * (s.position - centre),
                dipole: s.dipole.map(|mu| to_body * mu),
                quadrupole: s.quadrupole.map(|t| to_body * t * axes),
                ..s.clone()
            })
            .collect();
        if moments[0] == 0.0 {
            off_axis(&sites)?;
        }
        let principal_axes = Quat::from_body_to_space_matrix(&axes, 1e-10)
            .ok_or_else(|| InputError::new("inertia", "principal axes not found"))?;
        Ok(BodyType {
            mass,
            moments,
            principal_axes,
            centre,
            sites,
        })
    }

    /// Rotational degrees of freedom: 3, or 2 for a linear body.
    pub fn rotational_degrees(&self) -> usize {
        self.moments.iter().filter(|&&m| m > 0.0).count()
    }

    /// The spin no torque reaches (`thermostat_hook::degrees`' rule, as for
    /// the rotors): every site's position and dipole along one body axis
    /// `a` through the centre (no quadrupole), the inertia symmetric about
    /// `a` with a positive moment about it; `L_b . a` is then conserved
    /// (a dipolar sphere's spin about its dipole). `None` when no site
    /// defines an axis (no torque at all: every moment counts).
    pub fn conserved_spin(&self) -> Option<Spin> {
        if self.sites.iter().any(|s| s.quadrupole.is_some()) {
            return None;
        }
        let vectors: Vec<Vector3<f64>> = self
            .sites
            .iter()
            .flat_map(|s| std::iter::once(s.position).chain(s.dipole))
            .filter(|v| v.norm() > 0.0)
            .collect();
        let axis = vectors.first()?.normalize();
        let along = |v: &Vector3<f64>| v.cross(&axis).norm() <= PARALLEL_TOLERANCE * v.norm();
        let moment = axis.dot(&self.moments.component_mul(&axis));
        let inertia = Matrix3::from_diagonal(&self.moments);
        let spinning = moment > ZERO_MOMENT_TOLERANCE * self.moments.max();
        (vectors.iter().all(along) && spinning && symmetric_about(&inertia, &axis))
            .then_some(Spin { axis, moment })
    }
}

/// Vectors within this fraction of their length from an axis lie along it.
const PARALLEL_TOLERANCE: f64 = 1e-12;

/// `sum_s m_s (|d_s|^2 1 - d_s d_s^T)` with `d_s` the site position about `centre`.
fn site_inertia(sites: &[Site], centre: &Vector3<f64>) -> Matrix3<f64> {
    sites
        .iter()
        .map(|s| {
            let d = s.position - centre;
            (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * s.mass
        })
        .sum()
}

/// A linear body's sites (body frame) must lie on its axis, body axis 1: a
/// site farther off it than `sqrt(ZERO_MOMENT_TOLERANCE)` of the body's
/// reach would, with mass, have given the axis a moment above the
/// tolerance; a planar or bent body given a zero moment is refused (its
/// torque about that axis would have no inertia to act on).
fn off_axis(sites: &[Site]) -> Result<(), InputError> {
    let reach = sites.iter().map(|s| s.position.norm()).fold(0.0, f64::max);
    let allowed = ZERO_MOMENT_TOLERANCE.sqrt() * reach;
    for (k, site) in sites.iter().enumerate() {
        let off = site.position.y.hypot(site.position.z);
        if off > allowed {
            return Err(InputError::new(
                "inertia",
                format!(
                    "has a zero principal moment (a linear body), but sites[{k}] lies {} off \
                     its axis: a planar or bent body needs three nonzero moments",
                    num(off)
                ),
            ));
        }
    }
    Ok(())
}

/// The principal moments (ascending, tiny ones snapped to 0) and the axes
/// (columns, a proper rotation) of a symmetric tensor.
fn principal_frame(tensor: &Matrix3<f64>) -> Result<(Vector3<f64>, Matrix3<f64>), InputError> {
    let eigen = tensor.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let mut moments = Vector3::from_fn(|k, _| eigen.eigenvalues[order[k]]);
    let mut axes = Matrix3::from_fn(|i, k| eigen.eigenvectors[(i, order[k])]);
    if axes.determinant() < 0.0 {
        axes.column_mut(2).neg_mut();
    }
    let largest = moments[2];
    let zero = ZERO_MOMENT_TOLERANCE * largest;
    let zeros = moments.iter().filter(|&&m| m.abs() <= zero).count();
    // `largest <= 0.0` is false for NaN, which finite_matrix has refused.
    if largest <= 0.0 || moments[0] < -zero || zeros > 1 {
        let [a, b, c] = [moments[0], moments[1], moments[2]].map(num);
        return Err(InputError::new(
            "inertia",
            format!(
                "must be symmetric positive-definite (or have one zero moment, a linear \
                 body), got principal moments [{a}, {b}, {c}]"
            ),
        ));
    }
    if moments[0].abs() <= zero {
        moments[0] = 0.0;
    }
    Ok((moments, axes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::site::LennardJones;

    fn point(position: [f64; 3], mass: f64) -> Site {
        Site {
            position: Vector3::from(position),
            mass,
            ..Site::default()
        }
    }

    /// A water-like triangle of site masses: the centre is the centre of
    /// mass, the moments are those of the closed form for its principal
    /// axes, and the recorded rotation maps each body-frame site back onto
    /// its input position.
    #[test]
    fn principal_frame_of_a_triangle_matches_the_closed_form() {
        // Masses 16 at (0,0,0.1), 1 at (+-0.8, 0, -0.5): principal axes are
        // x, y, z; about the centre of mass z_c = (1.6 - 1.0) / 18.
        let sites = vec![
            point([0.0, 0.0, 0.1], 16.0),
            point([0.8, 0.0, -0.5], 1.0),
            point([-0.8, 0.0, -0.5], 1.0),
        ];
        let spec = BodyTypeSpec {
            sites: sites.clone(),
            ..BodyTypeSpec::default()
        };
        let body = BodyType::new(&spec).unwrap();
        let zc: f64 = (1.6 - 1.0) / 18.0;
        let izz = 2.0 * 0.64;
        let ixx = 16.0 * (0.1 - zc).powi(2) + 2.0 * (-0.5 - zc).powi(2);
        let iyy = ixx + izz;
        let mut expected = [ixx, izz, iyy];
        expected.sort_by(f64::total_cmp);
        assert!((body.mass - 18.0).abs() < 1e-14);
        assert!((body.centre - Vector3::new(0.0, 0.0, zc)).norm() < 1e-15);
        for (moment, exact) in body.moments.iter().zip(expected) {
            assert!((moment - exact).abs() < 1e-13, "{:?}", body.moments);
        }
        for (given, built) in sites.iter().zip(&body.sites) {
            let back = body.principal_axes.body_to_space(&built.position) + body.centre;
            assert!((back - given.position).norm() < 1e-14);
        }
    }

    /// A given non-diagonal tensor: the moments are its eigenvalues (a
    /// rotated diagonal one), and the rotation diagonalises it.
    #[test]
    fn a_given_tensor_is_diagonalised() {
        let q = Quat::new(0.9, 0.2, -0.3, 0.4).try_normalize().unwrap();
        let r = q.body_to_space_matrix();
        let tensor = r * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)) * r.transpose();
        let spec = BodyTypeSpec {
            sites: vec![point([0.0; 3], 0.0)],
            mass: Some(2.0),
            inertia: Some(tensor),
        };
        let body = BodyType::new(&spec).unwrap();
        assert!((body.moments - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-13);
        let axes = body.principal_axes.body_to_space_matrix();
        let diagonal = axes.transpose() * tensor * axes;
        assert!((diagonal - Matrix3::from_diagonal(&body.moments)).amax() < 1e-13);
    }

    /// Two collinear sites: a linear body with two rotational degrees of
    /// freedom and moments (0, I, I), `I = m d^2 / 2` for masses m at +-d/2.
    #[test]
    fn collinear_sites_make_a_linear_body() {
        let spec = BodyTypeSpec {
            sites: vec![point([0.3, 0.4, 0.0], 1.0), point([-0.3, -0.4, 0.0], 1.0)],
            ..BodyTypeSpec::default()
        };
        let body = BodyType::new(&spec).unwrap();
        assert_eq!(body.moments[0], 0.0);
        assert!((body.moments[1] - 0.5).abs() < 1e-14 && (body.moments[2] - 0.5).abs() < 1e-14);
        assert_eq!(body.rotational_degrees(), 2);
        assert_eq!(body.conserved_spin(), None);
        // Given a zero moment, sites on the axis (or at the centre) are
        // accepted, rounding included: one site off by 1e-9 of the reach.
        let given = |sites: Vec<Site>| BodyTypeSpec {
            sites,
            mass: Some(1.0),
            inertia: Some(Matrix3::from_diagonal(&Vector3::new(0.0, 1.0, 1.0))),
        };
        assert!(BodyType::new(&given(vec![point([0.0; 3], 0.0)])).is_ok());
        let on_axis = vec![point([-1.0, 0.0, 0.0], 0.0), point([2.0, 1e-9, 0.0], 0.0)];
        assert!(BodyType::new(&given(on_axis)).is_ok());
        let off_axis = vec![point([-1.0, 0.0, 0.0], 0.0), point([2.0, 0.0, 1e-5], 0.0)];
        assert!(BodyType::new(&given(off_axis)).is_err());
    }

    /// A dipolar sphere keeps its spin about the dipole; a dipole off the
    /// symmetry axis of a symmetric top, or a bent molecule, does not.
    #[test]
    fn the_spin_of_a_dipolar_sphere_is_conserved_and_no_other() {
        let body = |dipole: [f64; 3], inertia: [f64; 3]| {
            BodyType::new(&BodyTypeSpec {
                sites: vec![Site {
                    dipole: Some(Vector3::from(dipole)),
                    ..point([0.0; 3], 0.0)
                }],
                mass: Some(1.0),
                inertia: Some(Matrix3::from_diagonal(&Vector3::from(inertia))),
            })
            .unwrap()
        };
        let spin = body([0.0, 0.0, 2.0], [0.1; 3]).conserved_spin().unwrap();
        assert_eq!((spin.axis, spin.moment), (Vector3::z(), 0.1));
        // Symmetric about z, dipole along z: conserved; along x: not.
        assert!(body([0.0, 0.0, 1.0], [0.1, 0.1, 0.3])
            .conserved_spin()
            .is_some());
        assert!(body([1.0, 0.0, 0.0], [0.1, 0.1, 0.3])
            .conserved_spin()
            .is_none());
        let bent = BodyTypeSpec {
            sites: vec![point([0.0, 0.0, 0.1], 16.0), point([0.8, 0.0, -0.5], 1.0)],
            ..BodyTypeSpec::default()
        };
        let two = BodyType::new(&bent).unwrap();
        // Two sites: a linear body, its axis already without a moment.
        assert_eq!((two.rotational_degrees(), two.conserved_spin()), (2, None));
    }

    /// Bad input is refused with the field named.
    #[test]
    fn bad_bodies_are_refused_naming_the_field() {
        let message = |spec: BodyTypeSpec| BodyType::new(&spec).unwrap_err().to_string();
        assert_eq!(
            message(BodyTypeSpec::default()),
            "sites: a body needs at least one site"
        );
        let one = |inertia: Matrix3<f64>| BodyTypeSpec {
            sites: vec![point([0.0; 3], 1.0)],
            inertia: Some(inertia),
            ..BodyTypeSpec::default()
        };
        let skew = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(message(one(skew)).starts_with("inertia: must be symmetric, got [0][1]"));
        let indefinite = Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 2.0));
        assert_eq!(
            message(one(indefinite)),
            "inertia: must be symmetric positive-definite (or have one zero moment, a linear \
             body), got principal moments [-1, 1, 2]"
        );
        let point_body = BodyTypeSpec {
            sites: vec![point([0.0; 3], 1.0)],
            ..BodyTypeSpec::default()
        };
        assert!(message(point_body).contains("got principal moments [0, 0, 0]"));
        let mut nan = one(Matrix3::identity());
        nan.sites[0].lennard_jones = Some(LennardJones {
            epsilon: 1.0,
            sigma: f64::NAN,
        });
        assert_eq!(
            message(nan),
            "sites[0].lennard_jones.sigma: must be finite, got NaN"
        );
        // A bent molecule given a numerically zero moment (a typo, or a
        // planar body's I3 - I1 - I2 taken for I1).
        let planar = BodyTypeSpec {
            sites: vec![
                point([0.0, 0.0, 0.0], 0.0),
                point([0.8, 0.6, 0.0], 0.0),
                point([-0.8, 0.6, 0.0], 0.0),
            ],
            mass: Some(18.0),
            inertia: Some(Matrix3::from_diagonal(&Vector3::new(1e-17, 1.2, 1.9))),
        };
        assert_eq!(
            message(planar),
            "inertia: has a zero principal moment (a linear body), but sites[1] lies 0.6 off \
             its axis: a planar or bent body needs three nonzero moments"
        );
        let massless = BodyTypeSpec {
            sites: vec![point([0.0; 3], 0.0)],
            inertia: Some(Matrix3::identity()),
            ..BodyTypeSpec::default()
        };
        assert_eq!(
            message(massless),
            "mass: must be given when the sites have no mass"
        );
    }
}
