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
//! system never runs quadrupole code. Dipole-only lattices use the kernel of
//! [`super::row_quads`] instead, when it pays (decided at construction).

#[cfg(test)]
use super::pairs::PairTable;
use super::pairs::{PairGeometry, PairRows};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use std::ops::Range;

/// Rotors per rayon task when blocks of fields are summed.
const ROTORS_PER_MERGE: usize = 1024;

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

/// Four `f64` lanes (a 3-vector padded with a zero) aligned to 32 bytes, so
/// that a four-lane load or store never straddles two cache lines (the pair
/// loop ran about 10 % slower on unaligned field buffers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct Lanes(pub [f64; 4]);

impl std::ops::Deref for Lanes {
    type Target = [f64; 4];
    fn deref(&self) -> &[f64; 4] {
        &self.0
    }
}

impl std::ops::DerefMut for Lanes {
    fn deref_mut(&mut self) -> &mut [f64; 4] {
        &mut self.0
    }
}

/// Space-frame multipoles of every rotor in one configuration; a vector is
/// empty when the system has no multipole of that kind. Dipoles are padded
/// to four lanes.
#[derive(Clone, Debug, Default)]
pub(crate) struct SpaceMultipoles {
    pub dipoles: Vec<Lanes>,
    pub quadrupoles: Vec<Matrix3<f64>>,
}

/// The conjugate fields of every rotor (same layout as [`SpaceMultipoles`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct SiteFields {
    /// `E_i = -dV/dmu_i`.
    pub field: Vec<Lanes>,
    /// `W_i = dV/dTheta_i` (symmetric).
    pub quadrupole_conjugate: Vec<Matrix3<f64>>,
}

impl SiteFields {
    /// Zero fields for `n` rotors of kind `K`.
    pub fn zeros<K: MultipoleKind>(n: usize) -> Self {
        SiteFields {
            field: if K::DIPOLES {
                vec![Lanes::default(); n]
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

    /// The sum of the fields of blocks of rows, `(first row, fields)` in
    /// block order: each rotor's entry is the first block's plus each later
    /// block's whose first row is at or before the rotor (the rotors a
    /// block may have touched), added in block order; one parallel pass
    /// over the rotors. No blocks give zero fields for `n` rotors.
    pub fn sum_blocks<K: MultipoleKind>(blocks: Vec<(usize, SiteFields)>, n: usize) -> SiteFields {
        let mut blocks = blocks.into_iter();
        let Some((_, mut total)) = blocks.next() else {
            return SiteFields::zeros::<K>(n);
        };
        let rest: Vec<(usize, SiteFields)> = blocks.collect();
        add_blocks(
            &mut total.field,
            &rest,
            |f| &f.field,
            |a, b| {
                for k in 0..4 {
                    a[k] += b[k];
                }
            },
        );
        add_blocks(
            &mut total.quadrupole_conjugate,
            &rest,
            |f| &f.quadrupole_conjugate,
            |a, b| *a += b,
        );
        total
    }
}

/// Adds to each rotor's entry of `total` the entries (`entries`) of the
/// blocks of `rest` whose first row is at or before the rotor, in block
/// order; one parallel pass over the rotors.
fn add_blocks<T: Send + Sync>(
    total: &mut [T],
    rest: &[(usize, SiteFields)],
    entries: impl Fn(&SiteFields) -> &[T] + Sync,
    add: impl Fn(&mut T, &T) + Sync,
) {
    total
        .par_iter_mut()
        .with_min_len(ROTORS_PER_MERGE)
        .enumerate()
        .for_each(|(i, a)| {
            for (_, other) in rest.iter().filter(|(first, _)| *first <= i) {
                add(a, &entries(other)[i]);
            }
        });
}

/// Accumulates into `out` the fields of all pairs `(i, j)` with `i` in `rows`
/// (both the field at `i` and at `j`; a periodic self pair `j == i` adds both
/// ends to rotor `i`, as the derivative of the self term requires).
/// Dispatches once to a build of the loop for AVX and FMA when the CPU has
/// them (four-lane dipole tensors then take one instruction per lane group);
/// the results differ only by rounding.
pub(crate) fn accumulate_pair_fields<K: MultipoleKind, R: PairRows>(
    pairs: &R,
    rows: Range<usize>,
    multipoles: &SpaceMultipoles,
    out: &mut SiteFields,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports AVX and FMA, checked just above.
        unsafe { pair_fields_avx_fma::<K, R>(pairs, rows, multipoles, out) };
        return;
    }
    pair_fields::<K, Separate, R>(pairs, rows, multipoles, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
fn pair_fields_avx_fma<K: MultipoleKind, R: PairRows>(
    pairs: &R,
    rows: Range<usize>,
    multipoles: &SpaceMultipoles,
    out: &mut SiteFields,
) {
    pair_fields::<K, Fused, R>(pairs, rows, multipoles, out);
}

/// `a * b + c`, fused into one rounding or not.
pub(crate) trait MulAdd {
    fn mul_add(a: f64, b: f64, c: f64) -> f64;
}
/// Separate multiply and add (no FMA instruction available).
pub(crate) struct Separate;
/// One fused multiply-add (only where the FMA instruction is enabled).
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) struct Fused;
impl MulAdd for Separate {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}
impl MulAdd for Fused {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// `acc += t mu` for a dipole tensor stored as four-lane columns. The product
/// is formed first and added once, so consecutive calls on one accumulator
/// wait on one addition each, not on three chained multiply-adds.
#[inline(always)]
fn add_tensor_times<M: MulAdd>(acc: &mut [f64; 4], t: &[[f64; 4]; 3], mu: &[f64; 4]) {
    for k in 0..4 {
        acc[k] += M::mul_add(t[2][k], mu[2], M::mul_add(t[1][k], mu[1], t[0][k] * mu[0]));
    }
}

#[inline(always)]
pub(crate) fn pair_fields<K: MultipoleKind, M: MulAdd, R: PairRows>(
    pairs: &R,
    rows: Range<usize>,
    multipoles: &SpaceMultipoles,
    out: &mut SiteFields,
) {
    let (dipoles, quadrupoles) = (&multipoles.dipoles[..], &multipoles.quadrupoles[..]);
    let (field, conjugate) = (&mut out.field[..], &mut out.quadrupole_conjugate[..]);
    let mut scratch = R::Scratch::default();
    for i in rows {
        let (partners, geometry_index, geometry) = pairs.row(i, &mut scratch);
        let mut field_i = [0.0; 4];
        let mut conjugate_i = Matrix3::zeros();
        if K::DIPOLES && !K::QUADRUPOLES {
            dipole_row::<M>(
                &mut field_i,
                &dipoles[i],
                partners,
                geometry_index,
                geometry,
                dipoles,
                field,
            );
        }
        // Systems with quadrupoles (dipole-only systems never enter here).
        if K::QUADRUPOLES {
            for (&j, &g) in partners.iter().zip(geometry_index) {
                let j = j as usize;
                let geometry = &geometry[g as usize];
                if K::DIPOLES {
                    let t = &geometry.dipole_tensor;
                    add_tensor_times::<M>(&mut field_i, t, &dipoles[j]);
                    add_tensor_times::<M>(&mut field[j], t, &dipoles[i]);
                    let inv_r = geometry.inv_r;
                    let inv_r4 = (inv_r * inv_r) * (inv_r * inv_r);
                    let n = geometry.unit;
                    let (de_i, dw_j) =
                        dipole_quadrupole(&vec3(&dipoles[i]), &quadrupoles[j], &-n, inv_r4);
                    let (de_j, dw_i) =
                        dipole_quadrupole(&vec3(&dipoles[j]), &quadrupoles[i], &n, inv_r4);
                    for k in 0..3 {
                        field_i[k] += de_i[k];
                        field[j][k] += de_j[k];
                    }
                    conjugate_i += dw_i;
                    conjugate[j] += dw_j;
                }
                let inv_r = geometry.inv_r;
                let inv_r5 = (inv_r * inv_r) * (inv_r * inv_r) * inv_r;
                let (dw_i, dw_j) =
                    quadrupole_quadrupole(&quadrupoles[i], &quadrupoles[j], &geometry.unit, inv_r5);
                conjugate_i += dw_i;
                conjugate[j] += dw_j;
            }
        }
        if K::DIPOLES {
            for (total, part) in field[i].iter_mut().zip(field_i) {
                *total += part;
            }
        }
        if K::QUADRUPOLES {
            conjugate[i] += conjugate_i;
        }
    }
}

/// The dipole-dipole fields of one row of pairs `(i, j)`: adds the field at
/// `i` into `field_i` and the field at each `j` into `field`. Two partial sums
/// for `field_i` (even and odd pairs) halve its chain of dependent additions.
#[inline(always)]
fn dipole_row<M: MulAdd>(
    field_i: &mut [f64; 4],
    mu_i: &[f64; 4],
    partners: &[u32],
    geometry_index: &[u32],
    geometry: &[PairGeometry],
    dipoles: &[Lanes],
    field: &mut [Lanes],
) {
    let mu_i = *mu_i;
    let (mut even, mut odd) = ([0.0; 4], [0.0; 4]);
    let mut pair = |sum: &mut [f64; 4], j: u32, g: u32| {
        let j = j as usize;
        let t = &geometry[g as usize].dipole_tensor;
        add_tensor_times::<M>(sum, t, &dipoles[j]);
        add_tensor_times::<M>(&mut field[j], t, &mu_i);
    };
    let (js, gs) = (partners.chunks_exact(2), geometry_index.chunks_exact(2));
    let (j_last, g_last) = (js.remainder(), gs.remainder());
    for (j2, g2) in js.zip(gs) {
        pair(&mut even, j2[0], g2[0]);
        pair(&mut odd, j2[1], g2[1]);
    }
    if let (Some(&j), Some(&g)) = (j_last.first(), g_last.first()) {
        pair(&mut even, j, g);
    }
    for k in 0..4 {
        field_i[k] += even[k] + odd[k];
    }
}

fn vec3(v: &[f64; 4]) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

/// `alpha n n^T + beta (n v^T + v n^T) + gamma m` for symmetric `m`,
/// computed on the six independent entries.
#[inline(always)]
fn symmetric_combination(
    n: &Vector3<f64>,
    v: &Vector3<f64>,
    (alpha, beta, gamma): (f64, f64, f64),
    m: &Matrix3<f64>,
) -> Matrix3<f64> {
    let entry = |a: usize, b: usize| {
        n[a] * (alpha * n[b] + beta * v[b]) + beta * v[a] * n[b] + gamma * m[(a, b)]
    };
    let (xy, xz, yz) = (entry(0, 1), entry(0, 2), entry(1, 2));
    Matrix3::new(
        entry(0, 0),
        xy,
        xz,
        xy,
        entry(1, 1),
        yz,
        xz,
        yz,
        entry(2, 2),
    )
}

/// Dipole `mu` and quadrupole `theta`, `n` the unit vector from the quadrupole
/// to the dipole, `inv_r4 = 1/r^4`: returns (field at the dipole,
/// `dV/dTheta` at the quadrupole) of
/// `V = [2 mu.Theta n - 5 (n.Theta n)(mu.n)] / r^4`.
#[inline(always)]
fn dipole_quadrupole(
    mu: &Vector3<f64>,
    theta: &Matrix3<f64>,
    n: &Vector3<f64>,
    inv_r4: f64,
) -> (Vector3<f64>, Matrix3<f64>) {
    let theta_n = theta * n;
    let n_theta_n = n.dot(&theta_n);
    let field = (n * (5.0 * n_theta_n) - theta_n * 2.0) * inv_r4;
    let weights = (-5.0 * mu.dot(n) * inv_r4, inv_r4, 0.0);
    let conjugate = symmetric_combination(n, mu, weights, &Matrix3::zeros());
    (field, conjugate)
}

/// Quadrupoles `theta_i`, `theta_j` along unit vector `n`, `inv_r5 = 1/r^5`:
/// returns `dV/dTheta_i`, `dV/dTheta_j` of
/// `V = [105 (n.Ti n)(n.Tj n) - 60 (Ti n).(Tj n) + 6 Ti:Tj] / (9 r^5)`.
#[inline(always)]
fn quadrupole_quadrupole(
    theta_i: &Matrix3<f64>,
    theta_j: &Matrix3<f64>,
    n: &Vector3<f64>,
    inv_r5: f64,
) -> (Matrix3<f64>, Matrix3<f64>) {
    let scale = inv_r5 / 9.0;
    let (a, b) = (theta_i * n, theta_j * n);
    let conjugate = |other_n: &Vector3<f64>, other: &Matrix3<f64>| {
        let weights = (105.0 * n.dot(other_n) * scale, -30.0 * scale, 6.0 * scale);
        symmetric_combination(n, other_n, weights, other)
    };
    (conjugate(&b, theta_j), conjugate(&a, theta_i))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The build with separate multiply and add (used on CPUs without FMA)
    /// and the fused build give the same fields up to rounding, for every kind.
    #[test]
    fn separate_and_fused_builds_agree() {
        let sites: Vec<Vector3<f64>> = (0..12)
            .map(|k| {
                Vector3::new(
                    (k % 3) as f64,
                    ((k / 3) % 2) as f64 * 1.1,
                    (k / 6) as f64 * 0.9,
                )
            })
            .collect();
        let pairs = PairTable::build(&sites, None).unwrap();
        let multipoles = SpaceMultipoles {
            dipoles: (0..12)
                .map(|k| Lanes([(k as f64).sin(), (k as f64).cos(), 0.3, 0.0]))
                .collect(),
            quadrupoles: (0..12)
                .map(|k| {
                    let a = (k as f64) * 0.37;
                    Matrix3::new(
                        a.sin(),
                        0.2,
                        a.cos(),
                        0.2,
                        -0.5,
                        0.1,
                        a.cos(),
                        0.1,
                        0.5 - a.sin(),
                    )
                })
                .collect(),
        };
        fn both<K: MultipoleKind>(
            pairs: &PairTable,
            m: &SpaceMultipoles,
        ) -> (SiteFields, SiteFields) {
            let n = m.dipoles.len();
            let (mut plain, mut fused) = (SiteFields::zeros::<K>(n), SiteFields::zeros::<K>(n));
            pair_fields::<K, Separate, _>(pairs, 0..n, m, &mut plain);
            pair_fields::<K, Fused, _>(pairs, 0..n, m, &mut fused);
            (plain, fused)
        }
        let check = |(plain, fused): (SiteFields, SiteFields)| {
            for (a, b) in plain.field.iter().zip(&fused.field) {
                for k in 0..4 {
                    assert!((a[k] - b[k]).abs() < 1e-12 * (1.0 + a[k].abs()));
                }
            }
            for (a, b) in plain
                .quadrupole_conjugate
                .iter()
                .zip(&fused.quadrupole_conjugate)
            {
                assert!((a - b).amax() < 1e-12 * (1.0 + a.amax()));
            }
        };
        check(both::<Dipoles>(&pairs, &multipoles));
        check(both::<Quadrupoles>(&pairs, &multipoles));
        check(both::<DipolesAndQuadrupoles>(&pairs, &multipoles));
    }

    /// A self-image pair `(i, i)` with offset `n` (a rotor and its own
    /// periodic image) gives rotor `i` the fields of both images, at `+n` and
    /// at `-n`: the same as two ghost rotors carrying its multipoles there.
    #[test]
    fn self_image_pair_counts_both_images() {
        // The two sums differ only in the order of additions.
        const ROUNDING: f64 = 1e-14;
        let n = Vector3::new(0.6, -1.1, 0.8);
        let ghosts = PairTable::build(&[Vector3::zeros(), n, -n], None).unwrap();
        // Row 0 of the ghost table: partner 1 at +n (geometry 0), partner 2 at -n.
        assert_eq!(ghosts.partner[..2], [1, 2]);
        let self_pair = PairTable {
            start: vec![0, 1],
            partner: vec![0],
            geometry_index: vec![ghosts.geometry_index[0]],
            geometry: ghosts.geometry.clone(),
        };
        let theta = Matrix3::new(0.3, 0.2, -0.1, 0.2, -0.7, 0.4, -0.1, 0.4, 0.4);
        let mu = Lanes([0.2, -0.5, 0.9, 0.0]);
        let one = SpaceMultipoles {
            dipoles: vec![mu],
            quadrupoles: vec![theta],
        };
        let three = SpaceMultipoles {
            dipoles: vec![mu; 3],
            quadrupoles: vec![theta; 3],
        };
        fn check<K: MultipoleKind>(
            self_pair: (&PairTable, &SpaceMultipoles),
            ghosts: (&PairTable, &SpaceMultipoles),
        ) {
            let mut own = SiteFields::zeros::<K>(1);
            pair_fields::<K, Separate, _>(self_pair.0, 0..1, self_pair.1, &mut own);
            let mut reference = SiteFields::zeros::<K>(3);
            pair_fields::<K, Separate, _>(ghosts.0, 0..3, ghosts.1, &mut reference);
            if K::DIPOLES {
                let (a, b) = (own.field[0], reference.field[0]);
                let scale = b.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
                assert!(scale > 0.1);
                for k in 0..4 {
                    assert!((a[k] - b[k]).abs() <= ROUNDING * scale, "{a:?} {b:?}");
                }
            }
            if K::QUADRUPOLES {
                let (a, b) = (
                    own.quadrupole_conjugate[0],
                    reference.quadrupole_conjugate[0],
                );
                assert!(b.amax() > 0.1);
                assert!((a - b).amax() <= ROUNDING * b.amax(), "{a} {b}");
            }
        }
        let args = ((&self_pair, &one), (&ghosts, &three));
        check::<Dipoles>(args.0, args.1);
        check::<Quadrupoles>(args.0, args.1);
        check::<DipolesAndQuadrupoles>(args.0, args.1);
    }
}
