//! Pair kernels: the fields each rotor feels from the others.
//!
//! For every rotor the kernels accumulate the two quantities conjugate to its
//! space-frame multipoles: the field `E_i = -dV/dmu_i` and the symmetric
//! matrix `W_i = dV/dTheta_i` (equal to `-1/3` of the field gradient, in the
//! Buckingham convention). The pair energies are the standard Cartesian
//! interaction tensors `T_ab.. = d_a d_b .. (1/r)` (Buckingham; Stone, "The
//! Theory of Intermolecular Forces", ch. 3) contracted with traceless
//! multipoles, `n = r/|r|` along the pair, `r` its length:
//!
//! * dipole-dipole: `V = [mu_i.mu_j - 3 (mu_i.n)(mu_j.n)] / r^3`
//! * dipole `a`, quadrupole `b`, `n` from `b` to `a`:
//!   `V = [2 mu_a.Theta_b n - 5 (n.Theta_b n)(mu_a.n)] / r^4`
//! * quadrupole-quadrupole:
//!   `V = [105 (n.Theta_i n)(n.Theta_j n) - 60 (Theta_i n).(Theta_j n) + 6 Theta_i:Theta_j] / (9 r^5)`
//!
//! Every term is bilinear in the two rotors' multipoles, so the pair energy is
//! `1/2 sum_i (-mu_i.E_i + Theta_i:W_i)` and needs no work per pair.
//!
//! The kernels are generic over the multipole kinds present, so a dipole-only
//! system never runs quadrupole code.

use super::pairs::PairTable;
use nalgebra::{Matrix3, Vector3};
use std::ops::Range;

/// Which multipoles the system carries (chosen once per evaluation).
pub(crate) trait MultipoleKind: Send + Sync {
    const DIPOLES: bool;
    const QUADRUPOLES: bool;
}

/// Dipoles only.
pub(crate) struct Dipoles;
/// Quadrupoles only.
pub(crate) struct Quadrupoles;
/// Both (a rotor lacking one carries zeros).
pub(crate) struct DipolesAndQuadrupoles;

impl MultipoleKind for Dipoles {
    const DIPOLES: bool = true;
    const QUADRUPOLES: bool = false;
}
impl MultipoleKind for Quadrupoles {
    const DIPOLES: bool = false;
    const QUADRUPOLES: bool = true;
}
impl MultipoleKind for DipolesAndQuadrupoles {
    const DIPOLES: bool = true;
    const QUADRUPOLES: bool = true;
}

/// Space-frame multipoles of every rotor in one configuration; a vector is
/// empty when the system has no multipole of that kind. Dipoles are padded
/// to four lanes.
#[derive(Clone, Debug, Default)]
pub(crate) struct SpaceMultipoles {
    pub dipoles: Vec<[f64; 4]>,
    pub quadrupoles: Vec<Matrix3<f64>>,
}

/// The conjugate fields of every rotor (same layout as [`SpaceMultipoles`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct SiteFields {
    /// `E_i = -dV/dmu_i`.
    pub field: Vec<[f64; 4]>,
    /// `W_i = dV/dTheta_i` (symmetric).
    pub quadrupole_conjugate: Vec<Matrix3<f64>>,
}

impl SiteFields {
    /// Zero fields for `n` rotors of kind `K`.
    pub fn zeros<K: MultipoleKind>(n: usize) -> Self {
        SiteFields {
            field: if K::DIPOLES {
                vec![[0.0; 4]; n]
            } else {
                Vec::new()
            },
            quadrupole_conjugate: if K::QUADRUPOLES {
                vec![Matrix3::zeros(); n]
            } else {
                Vec::new()
            },
        }
    }

    /// Adds `other`'s entries from rotor `from` on (the rotors it may have touched).
    pub fn add_from(&mut self, other: &SiteFields, from: usize) {
        for (a, b) in self.field.iter_mut().zip(&other.field).skip(from) {
            for k in 0..4 {
                a[k] += b[k];
            }
        }
        for (a, b) in self
            .quadrupole_conjugate
            .iter_mut()
            .zip(&other.quadrupole_conjugate)
            .skip(from)
        {
            *a += b;
        }
    }
}

/// Accumulates into `out` the fields of all pairs `(i, j)` with `i` in `rows`
/// (both the field at `i` and at `j`).
pub(crate) fn accumulate_pair_fields<K: MultipoleKind>(
    pairs: &PairTable,
    rows: Range<usize>,
    multipoles: &SpaceMultipoles,
    out: &mut SiteFields,
) {
    for i in rows {
        let range = pairs.start[i]..pairs.start[i + 1];
        let partners = &pairs.partner[range.clone()];
        let geometry_index = &pairs.geometry_index[range];
        let mut field_i = [0.0; 4];
        let mut conjugate_i = Matrix3::zeros();
        for (&j, &g) in partners.iter().zip(geometry_index) {
            let j = j as usize;
            let geometry = &pairs.geometry[g as usize];
            if K::DIPOLES {
                let t = &geometry.dipole_tensor;
                let (mu_i, mu_j) = (&multipoles.dipoles[i], &multipoles.dipoles[j]);
                let field_j = &mut out.field[j];
                for k in 0..4 {
                    field_i[k] += t[0][k] * mu_j[0] + t[1][k] * mu_j[1] + t[2][k] * mu_j[2];
                    field_j[k] += t[0][k] * mu_i[0] + t[1][k] * mu_i[1] + t[2][k] * mu_i[2];
                }
            }
            if K::DIPOLES && K::QUADRUPOLES {
                let inv_r = geometry.inv_r;
                let inv_r4 = (inv_r * inv_r) * (inv_r * inv_r);
                let n = geometry.unit;
                let (de_i, dw_j) = dipole_quadrupole(
                    &vec3(&multipoles.dipoles[i]),
                    &multipoles.quadrupoles[j],
                    &-n,
                    inv_r4,
                );
                let (de_j, dw_i) = dipole_quadrupole(
                    &vec3(&multipoles.dipoles[j]),
                    &multipoles.quadrupoles[i],
                    &n,
                    inv_r4,
                );
                for k in 0..3 {
                    field_i[k] += de_i[k];
                    out.field[j][k] += de_j[k];
                }
                conjugate_i += dw_i;
                out.quadrupole_conjugate[j] += dw_j;
            }
            if K::QUADRUPOLES {
                let inv_r = geometry.inv_r;
                let inv_r5 = (inv_r * inv_r) * (inv_r * inv_r) * inv_r;
                let (dw_i, dw_j) = quadrupole_quadrupole(
                    &multipoles.quadrupoles[i],
                    &multipoles.quadrupoles[j],
                    &geometry.unit,
                    inv_r5,
                );
                conjugate_i += dw_i;
                out.quadrupole_conjugate[j] += dw_j;
            }
        }
        if K::DIPOLES {
            for k in 0..4 {
                out.field[i][k] += field_i[k];
            }
        }
        if K::QUADRUPOLES {
            out.quadrupole_conjugate[i] += conjugate_i;
        }
    }
}

fn vec3(v: &[f64; 4]) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

/// `a b^T + b a^T`.
fn sym2(a: &Vector3<f64>, b: &Vector3<f64>) -> Matrix3<f64> {
    a * b.transpose() + b * a.transpose()
}

/// Dipole `mu` and quadrupole `theta`, `n` the unit vector from the quadrupole
/// to the dipole, `inv_r4 = 1/r^4`: returns (field at the dipole,
/// `dV/dTheta` at the quadrupole) of
/// `V = [2 mu.Theta n - 5 (n.Theta n)(mu.n)] / r^4`.
fn dipole_quadrupole(
    mu: &Vector3<f64>,
    theta: &Matrix3<f64>,
    n: &Vector3<f64>,
    inv_r4: f64,
) -> (Vector3<f64>, Matrix3<f64>) {
    let theta_n = theta * n;
    let n_theta_n = n.dot(&theta_n);
    let field = (n * (5.0 * n_theta_n) - theta_n * 2.0) * inv_r4;
    let conjugate = (sym2(mu, n) - n * n.transpose() * (5.0 * mu.dot(n))) * inv_r4;
    (field, conjugate)
}

/// Quadrupoles `theta_i`, `theta_j` along unit vector `n`, `inv_r5 = 1/r^5`:
/// returns `dV/dTheta_i`, `dV/dTheta_j` of
/// `V = [105 (n.Ti n)(n.Tj n) - 60 (Ti n).(Tj n) + 6 Ti:Tj] / (9 r^5)`.
fn quadrupole_quadrupole(
    theta_i: &Matrix3<f64>,
    theta_j: &Matrix3<f64>,
    n: &Vector3<f64>,
    inv_r5: f64,
) -> (Matrix3<f64>, Matrix3<f64>) {
    let scale = inv_r5 / 9.0;
    let nn = n * n.transpose();
    let (a, b) = (theta_i * n, theta_j * n);
    let conjugate = |other_n: &Vector3<f64>, other: &Matrix3<f64>| {
        (nn * (105.0 * n.dot(other_n)) - sym2(n, other_n) * 30.0 + other * 6.0) * scale
    };
    (conjugate(&b, theta_j), conjugate(&a, theta_i))
}
