//! The direct Ewald sum on any sites in an orthorhombic box: real-space
//! pairs within `r_c` (the pair list of [`super::pairs`], every image
//! included), the reciprocal-space sum over the wave vectors `|k| <= k_c` by
//! structure factors, the self term and the optional vacuum surface term
//! (formulas in [`super::ewald_terms`]). Cost per evaluation: the real-space
//! pairs plus `2 N` products per wave vector; `alpha` balances the two
//! (`N^(3/2)` overall).

use super::boundary::{BYTES_PER_PAIR, MAX_PAIRS};
use super::ewald_parameters::{Cost, EwaldParameters};
use super::ewald_terms::{
    mode_weight, pair_fields, radial, self_conjugate_per_quadrupole, self_field_per_dipole,
    surface_field_per_dipole,
};
use super::kernels::{MultipoleKind, SiteFields, SpaceMultipoles};
use super::pairs::{balanced_blocks, PairRows, PairTable};
use super::{PotentialError, Surface};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use rustfft::num_complex::Complex;
use std::f64::consts::PI;

/// The most reciprocal-space wave vectors (half space) a direct sum may use.
pub const MAX_WAVE_VECTORS: usize = 10_000_000;

/// Sites per rayon task in the reciprocal-space passes.
const SITES_PER_TASK: usize = 64;

/// One reciprocal-space wave vector `k = 2 pi (h / L_x, k / L_y, l / L_z)` of
/// the half space (its opposite is folded in by the factor 2 of `weight`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct WaveVector {
    pub index: [i32; 3],
    pub k: Vector3<f64>,
    /// `-1/3 k k^T` as (xx, yy, zz, xy, xz, yz).
    kk: [f64; 6],
    /// `(8 pi / V) exp(-k^2 / 4 alpha^2) / k^2`.
    pub weight: f64,
}

/// The direct Ewald sum of one set of sites (built once; see the module doc).
#[derive(Clone, Debug)]
pub(crate) struct EwaldSum {
    parameters: EwaldParameters,
    surface: Surface,
    volume: f64,
    box_lengths: Vector3<f64>,
    sites: Vec<Vector3<f64>>,
    real: PairTable,
    /// `(r_j - r_i, B_0..B_4)` of each real-space geometry.
    real_geometry: Vec<(Vector3<f64>, [f64; 5])>,
    waves: Vec<WaveVector>,
    max_index: [i32; 3],
}

impl EwaldSum {
    /// The cost model of a direct sum of `sites` sites in `box_lengths`
    /// (the real-space pairs balanced against the wave vectors).
    pub fn cost(sites: usize, box_lengths: &Vector3<f64>) -> Cost {
        Cost::Direct {
            sites: sites as f64,
            volume: box_lengths.product(),
        }
    }

    /// The sum with the parameters chosen for its accuracy
    /// ([`super::PeriodicSum::choose`] with [`Self::cost`]; the tests and the
    /// converged references give their own). Refuses sums that
    /// [`Self::check_size`] refuses, and coincident sites (periodic images
    /// included).
    pub fn with_parameters(
        sites: &[Vector3<f64>],
        box_lengths: Vector3<f64>,
        parameters: EwaldParameters,
        surface: Surface,
    ) -> Result<Self, PotentialError> {
        let max_index = Self::check_size(sites.len(), &box_lengths, &parameters)?;
        let rc = parameters.real_cutoff;
        let kc = parameters.reciprocal_cutoff;
        let volume = box_lengths.product();
        let real = PairTable::build(sites, Some((box_lengths, rc)))?;
        let real_geometry = real
            .geometry
            .iter()
            .map(|g| (g.unit / g.inv_r, radial(parameters.alpha, 1.0 / g.inv_r)))
            .collect();
        let waves = wave_vectors(&box_lengths, max_index, parameters.alpha, kc);
        Ok(EwaldSum {
            parameters,
            surface,
            volume,
            box_lengths,
            sites: sites.to_vec(),
            real,
            real_geometry,
            waves,
            max_index,
        })
    }

    /// The half-index box of the wave vectors of a direct sum of `sites`
    /// sites in `box_lengths` with `parameters`, after checking its size
    /// without building it: refuses sums larger than [`MAX_PAIRS`] pairs or
    /// [`MAX_WAVE_VECTORS`] wave vectors or than the memory limit of
    /// [`crate::memory`] (pair list, wave vectors and the structure factors
    /// of an evaluation; path `accuracy`, which sets the sizes).
    pub fn check_size(
        sites: usize,
        box_lengths: &Vector3<f64>,
        parameters: &EwaldParameters,
    ) -> Result<[i32; 3], PotentialError> {
        let n = sites as f64;
        let volume = box_lengths.product();
        let rc = parameters.real_cutoff;
        let estimate = n * n * (2.0 * PI / 3.0) * rc.powi(3) / volume;
        if estimate > MAX_PAIRS as f64 {
            return Err(PotentialError::new(
                "rotors",
                format!(
                    "the direct Ewald sum of {sites} rotors would hold about {estimate:.2e} \
                     real-space pairs (cutoff {rc:.3}, periodic images included), more than \
                     the limit {MAX_PAIRS}"
                ),
            ));
        }
        let kc = parameters.reciprocal_cutoff;
        let max_index = [0, 1, 2].map(|a| (kc * box_lengths[a] / (2.0 * PI)).floor() as i32);
        let count: f64 = max_index.iter().map(|&m| (2 * m + 1) as f64).product();
        if count / 2.0 > MAX_WAVE_VECTORS as f64 {
            return Err(PotentialError::new(
                "accuracy",
                format!(
                    "needs about {:.2e} reciprocal-space wave vectors (cutoff {kc:.3}), more \
                     than the limit {MAX_WAVE_VECTORS}",
                    count / 2.0
                ),
            ));
        }
        let waves_count = count / 2.0;
        let chunks = (n / SITES_PER_TASK as f64).ceil() + 1.0;
        let bytes = estimate * BYTES_PER_PAIR
            + waves_count * (size_of::<WaveVector>() as f64 + chunks * 16.0);
        crate::memory::check("accuracy", bytes).map_err(|e| {
            PotentialError::new(
                "accuracy",
                format!(
                    "the direct Ewald sum of {sites} rotors (about {estimate:.2e} real-space pairs, \
                     cutoff {rc:.3}, and {waves_count:.2e} wave vectors) {}",
                    e.message
                ),
            )
        })?;
        Ok(max_index)
    }

    pub fn parameters(&self) -> EwaldParameters {
        self.parameters
    }

    /// Number of real-space pairs (each counted once).
    pub fn real_pairs(&self) -> usize {
        self.real.len()
    }

    /// The fields of every site: real space, reciprocal space, self and surface.
    pub fn fields<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles) -> SiteFields {
        let n = self.sites.len();
        let mut fields = self.real_space::<K>(multipoles);
        let reciprocal = self.reciprocal_space::<K>(multipoles);
        let a3 = self_field_per_dipole(self.parameters.alpha);
        let a5 = self_conjugate_per_quadrupole(self.parameters.alpha);
        let surface = match self.surface {
            Surface::Conducting => Vector3::zeros(),
            Surface::Vacuum if K::DIPOLES => {
                let total = multipoles.dipoles.iter().fold(Vector3::zeros(), |acc, mu| {
                    acc + Vector3::new(mu[0], mu[1], mu[2])
                });
                total * surface_field_per_dipole(self.volume)
            }
            Surface::Vacuum => Vector3::zeros(),
        };
        for i in 0..n {
            if K::DIPOLES {
                let mu = &multipoles.dipoles[i];
                for k in 0..3 {
                    fields.field[i][k] += reciprocal.field[i][k] + a3 * mu[k] + surface[k];
                }
            }
            if K::QUADRUPOLES {
                fields.quadrupole_conjugate[i] +=
                    reciprocal.quadrupole_conjugate[i] + multipoles.quadrupoles[i] * a5;
            }
        }
        fields
    }

    /// The real-space pairs, one block of rows per rayon thread (each with
    /// its own buffer, summed in block order).
    fn real_space<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles) -> SiteFields {
        let n = self.sites.len();
        let blocks = balanced_blocks(self.real.starts(), rayon::current_num_threads());
        let partial: Vec<(usize, SiteFields)> = blocks
            .into_par_iter()
            .map(|rows| {
                let first = rows.start;
                let mut out = SiteFields::zeros::<K>(n);
                for i in rows {
                    for p in self.real.start[i]..self.real.start[i + 1] {
                        let j = self.real.partner[p] as usize;
                        let (r, b) = &self.real_geometry[self.real.geometry_index[p] as usize];
                        let source = |s: usize| {
                            (
                                K::DIPOLES.then(|| {
                                    let mu = &multipoles.dipoles[s];
                                    Vector3::new(mu[0], mu[1], mu[2])
                                }),
                                K::QUADRUPOLES.then(|| multipoles.quadrupoles[s]),
                            )
                        };
                        let (mu_j, theta_j) = source(j);
                        let (e_i, w_i) = pair_fields(&-r, b, mu_j.as_ref(), theta_j.as_ref());
                        let (mu_i, theta_i) = source(i);
                        let (e_j, w_j) = pair_fields(r, b, mu_i.as_ref(), theta_i.as_ref());
                        add(&mut out, i, &e_i, &w_i, K::DIPOLES, K::QUADRUPOLES);
                        add(&mut out, j, &e_j, &w_j, K::DIPOLES, K::QUADRUPOLES);
                    }
                }
                (first, out)
            })
            .collect();
        SiteFields::sum_blocks::<K>(partial, n)
    }

    /// The phases `exp(i 2 pi m x_a / L_a)` of one site for `m` in
    /// `-max..=max` along each axis (index `m + max`).
    /// Structure factors `S(k) = sum_j c_j(k) exp(-i k.r_j)`, then the fields
    /// `E_i = sum_k w k Im[S exp(i k.r_i)]`, `W_i = sum_k w (-1/3 k k^T) Re[...]`.
    fn reciprocal_space<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles) -> SiteFields {
        let n = self.sites.len();
        let coefficient = |j: usize, wave: &WaveVector| {
            let mut c = Complex::new(0.0, 0.0);
            if K::DIPOLES {
                let mu = &multipoles.dipoles[j];
                c.im -= mu[0] * wave.k.x + mu[1] * wave.k.y + mu[2] * wave.k.z;
            }
            if K::QUADRUPOLES {
                c.re += wave.k.dot(&(multipoles.quadrupoles[j] * wave.k)) * (-1.0 / 3.0);
            }
            c
        };
        let chunks: Vec<Vec<Complex<f64>>> = (0..n)
            .collect::<Vec<_>>()
            .par_chunks(SITES_PER_TASK)
            .map(|chunk| {
                let mut s = vec![Complex::new(0.0, 0.0); self.waves.len()];
                for &j in chunk {
                    let phases = phases(&self.sites[j], &self.box_lengths, self.max_index);
                    for (s, wave) in s.iter_mut().zip(&self.waves) {
                        *s += coefficient(j, wave)
                            * phase(&phases, self.max_index, wave.index).conj();
                    }
                }
                s
            })
            .collect();
        let mut structure = vec![Complex::new(0.0, 0.0); self.waves.len()];
        for chunk in &chunks {
            for (s, c) in structure.iter_mut().zip(chunk) {
                *s += c;
            }
        }
        let mut out = SiteFields::zeros::<K>(n);
        let per_site: Vec<([f64; 3], [f64; 6])> = (0..n)
            .into_par_iter()
            .with_min_len(SITES_PER_TASK)
            .map(|i| {
                let phases = phases(&self.sites[i], &self.box_lengths, self.max_index);
                let (mut e, mut w) = ([0.0; 3], [0.0; 6]);
                for (s, wave) in structure.iter().zip(&self.waves) {
                    let t = s * phase(&phases, self.max_index, wave.index);
                    if K::DIPOLES {
                        let f = wave.weight * t.im;
                        for (e, k) in e.iter_mut().zip(wave.k.iter()) {
                            *e += f * k;
                        }
                    }
                    if K::QUADRUPOLES {
                        let f = wave.weight * t.re;
                        for (w, kk) in w.iter_mut().zip(&wave.kk) {
                            *w += f * kk;
                        }
                    }
                }
                (e, w)
            })
            .collect();
        for (i, (e, w)) in per_site.into_iter().enumerate() {
            if K::DIPOLES {
                out.field[i].0[..3].copy_from_slice(&e);
            }
            if K::QUADRUPOLES {
                out.quadrupole_conjugate[i] =
                    Matrix3::new(w[0], w[3], w[4], w[3], w[1], w[5], w[4], w[5], w[2]);
            }
        }
        out
    }
}

fn add(
    out: &mut SiteFields,
    i: usize,
    e: &Vector3<f64>,
    w: &Matrix3<f64>,
    dipoles: bool,
    quadrupoles: bool,
) {
    if dipoles {
        for k in 0..3 {
            out.field[i][k] += e[k];
        }
    }
    if quadrupoles {
        out.quadrupole_conjugate[i] += w;
    }
}

/// `exp(i 2 pi p r_a / L_a)` of `site` for `p` from `-max_index[a]` to
/// `max_index[a]` along each axis `a`.
pub(crate) fn phases(
    site: &Vector3<f64>,
    box_lengths: &Vector3<f64>,
    max_index: [i32; 3],
) -> [Vec<Complex<f64>>; 3] {
    [0, 1, 2].map(|a| {
        let m = max_index[a];
        let step = Complex::from_polar(1.0, 2.0 * PI * site[a] / box_lengths[a]);
        let mut out = vec![Complex::new(1.0, 0.0); (2 * m + 1) as usize];
        for p in 1..=m as usize {
            out[m as usize + p] = out[m as usize + p - 1] * step;
            out[m as usize - p] = out[m as usize + p].conj();
        }
        out
    })
}

/// `exp(i k.r)` of the wave vector `index` from the [`phases`] of `r`.
pub(crate) fn phase(
    phases: &[Vec<Complex<f64>>; 3],
    max_index: [i32; 3],
    index: [i32; 3],
) -> Complex<f64> {
    let at = |a: usize| phases[a][(index[a] + max_index[a]) as usize];
    at(0) * at(1) * at(2)
}

/// The half space of wave vectors `0 < |k| <= kc` (first nonzero index positive).
pub(crate) fn wave_vectors(
    box_lengths: &Vector3<f64>,
    max_index: [i32; 3],
    alpha: f64,
    kc: f64,
) -> Vec<WaveVector> {
    let volume = box_lengths.product();
    let mut out = Vec::new();
    let [mx, my, mz] = max_index;
    for h in 0..=mx {
        for k in -my..=my {
            for l in -mz..=mz {
                if [h, k, l] <= [0, 0, 0] {
                    continue;
                }
                let kv = Vector3::new(
                    2.0 * PI * h as f64 / box_lengths.x,
                    2.0 * PI * k as f64 / box_lengths.y,
                    2.0 * PI * l as f64 / box_lengths.z,
                );
                let k2 = kv.norm_squared();
                if k2 > kc * kc {
                    continue;
                }
                let third = -1.0 / 3.0;
                out.push(WaveVector {
                    index: [h, k, l],
                    k: kv,
                    kk: [
                        third * kv.x * kv.x,
                        third * kv.y * kv.y,
                        third * kv.z * kv.z,
                        third * kv.x * kv.y,
                        third * kv.x * kv.z,
                        third * kv.y * kv.z,
                    ],
                    weight: 8.0 * PI / volume * mode_weight(alpha, k2),
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::multipole::kernels::{DipolesAndQuadrupoles, Lanes};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    /// Ewald sums converged far below round-off (`s = 7` in both spaces:
    /// `exp(-49)`) of the same sites differ only by the rounding of sums of
    /// ~1e4 terms that cancel to a few percent of their absolute sum.
    const ROUND_OFF: f64 = 1e-13;

    /// `V = 1/2 sum_i (-mu_i . E_i + Theta_i : W_i)` from the site fields.
    fn energy(multipoles: &SpaceMultipoles, f: &SiteFields) -> f64 {
        (0..f.field.len())
            .map(|i| {
                let mu = &multipoles.dipoles[i];
                let e = &f.field[i];
                -(mu[0] * e[0] + mu[1] * e[1] + mu[2] * e[2])
                    + multipoles.quadrupoles[i].dot(&f.quadrupole_conjugate[i])
            })
            .sum::<f64>()
            * 0.5
    }

    /// The Ewald sum does not depend on the splitting parameter: energies
    /// and fields of irregular sites with dipoles and quadrupoles at three
    /// `alpha`, with converged cutoffs, in both surfaces.
    #[test]
    fn converged_sum_does_not_depend_on_alpha() {
        let mut rng = ChaCha20Rng::seed_from_u64(14);
        let box_lengths = Vector3::new(3.1, 2.7, 3.6);
        let n = 24;
        let sites: Vec<Vector3<f64>> = (0..n)
            .map(|_| Vector3::from_fn(|a, _| rng.random_range(0.0..box_lengths[a])))
            .collect();
        let unit = |rng: &mut ChaCha20Rng| Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let multipoles = SpaceMultipoles {
            dipoles: (0..n)
                .map(|_| {
                    let mu = unit(&mut rng);
                    Lanes([mu.x, mu.y, mu.z, 0.0])
                })
                .collect(),
            quadrupoles: (0..n)
                .map(|_| {
                    let m = Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                    let s = (m + m.transpose()) * 0.5;
                    s - Matrix3::identity() * (s.trace() / 3.0)
                })
                .collect(),
        };
        let energy = |f: &SiteFields| energy(&multipoles, f);
        for surface in [Surface::Conducting, Surface::Vacuum] {
            let evaluate = |alpha: f64| {
                let parameters = EwaldParameters::converged(alpha);
                let sum =
                    EwaldSum::with_parameters(&sites, box_lengths, parameters, surface).unwrap();
                sum.fields::<DipolesAndQuadrupoles>(&multipoles)
            };
            let reference = evaluate(1.0);
            let v_ref = energy(&reference);
            let e_scale = reference
                .field
                .iter()
                .flat_map(|e| e.0)
                .fold(0.0, |m: f64, x| m.max(x.abs()));
            let w_scale = reference
                .quadrupole_conjugate
                .iter()
                .map(|w| w.amax())
                .fold(0.0, f64::max);
            for alpha in [0.7, 1.4] {
                let other = evaluate(alpha);
                let v = energy(&other);
                assert!(
                    (v - v_ref).abs() < ROUND_OFF * v_ref.abs(),
                    "{surface:?} alpha {alpha}: {v} vs {v_ref}"
                );
                for i in 0..n {
                    for k in 0..3 {
                        let d = (other.field[i][k] - reference.field[i][k]).abs();
                        assert!(d < ROUND_OFF * e_scale, "field {i} {k}: {d:e}");
                    }
                    let d =
                        (other.quadrupole_conjugate[i] - reference.quadrupole_conjugate[i]).amax();
                    assert!(d < ROUND_OFF * w_scale, "W {i}: {d:e}");
                }
            }
        }
    }

    /// The reciprocal sum runs over the closed sphere `0 < |k| <= k_c` and
    /// nothing else (module doc): two dipoles in a 2 x 2.5 x 3 box with
    /// `k_c = 2 pi / L_x` exactly, so that `(+-1, 0, 0)` lie on the sphere
    /// and the other vectors of the index box `{-1, 0, 1}^3` outside it.
    /// With no real-space pair (`r_c` below every distance) and conducting
    /// surroundings the energy is the textbook dipolar Ewald sum (Allen &
    /// Tildesley, Gaussian units), reciprocal term summed here over the
    /// whole sphere: `(2 pi / V) sum_k exp(-k^2 / 4 alpha^2) / k^2
    /// |sum_j (mu_j . k) exp(i k . r_j)|^2 - (2 alpha^3 / 3 sqrt(pi)) sum_j
    /// mu_j^2`. Both sums are a few terms of order 1: round-off.
    #[test]
    fn reciprocal_sum_runs_over_the_closed_sphere_of_wave_vectors() {
        let box_lengths = Vector3::new(2.0, 2.5, 3.0);
        let sites = [Vector3::new(0.3, 0.4, 0.5), Vector3::new(1.3, 1.5, 2.1)];
        let dipoles = [Vector3::new(0.3, -0.8, 0.5), Vector3::new(-0.6, 0.2, 0.9)];
        let (alpha, kc) = (1.5, 2.0 * PI / box_lengths.x);
        let parameters = EwaldParameters {
            alpha,
            real_cutoff: 0.2,
            reciprocal_cutoff: kc,
            real_estimate: 0.0,
            reciprocal_estimate: 0.0,
        };
        let sum = EwaldSum::with_parameters(&sites, box_lengths, parameters, Surface::Conducting)
            .unwrap();
        assert_eq!(sum.real_pairs(), 0);
        let multipoles = SpaceMultipoles {
            dipoles: dipoles
                .iter()
                .map(|m| Lanes([m.x, m.y, m.z, 0.0]))
                .collect(),
            quadrupoles: vec![Matrix3::zeros(); 2],
        };
        let v = energy(
            &multipoles,
            &sum.fields::<DipolesAndQuadrupoles>(&multipoles),
        );
        let mut reciprocal = 0.0;
        let mut inside = 0;
        for index in
            (-1..=1).flat_map(|h| (-1..=1).flat_map(move |k| (-1..=1).map(move |l| [h, k, l])))
        {
            let k = Vector3::from_fn(|a, _| 2.0 * PI * index[a] as f64 / box_lengths[a]);
            let k2 = k.norm_squared();
            if k2 == 0.0 || k2 > kc * kc {
                continue;
            }
            inside += 1;
            let s: Complex<f64> = (0..2)
                .map(|j| Complex::from_polar(dipoles[j].dot(&k), k.dot(&sites[j])))
                .sum();
            reciprocal += (-k2 / (4.0 * alpha * alpha)).exp() / k2 * s.norm_sqr();
        }
        assert_eq!(inside, 6, "(+-1, 0, 0), (0, +-1, 0), (0, 0, +-1)");
        let volume = box_lengths.product();
        let self_term = -2.0 * alpha.powi(3) / (3.0 * PI.sqrt())
            * dipoles.iter().map(|m| m.norm_squared()).sum::<f64>();
        let expected = 2.0 * PI / volume * reciprocal + self_term;
        assert!((v - expected).abs() < 1e-14, "{v} vs {expected}");
    }

    /// The wave vectors are enumerated over the index box `|h_a| <= k_c L_a
    /// / 2 pi`, `n = prod (2 m_a + 1) / 2` of them in the half space (the
    /// sphere is found inside it), and [`MAX_WAVE_VECTORS`] bounds that
    /// half-space count: in a unit cube `m = 108` (`n = 5.1e6`, above half
    /// the limit: a count of the whole box would refuse it) is built, `m =
    /// 136` (`n = 1.017e7`) is refused before it is built, with its size.
    /// (`n` is an odd number halved, never equal to the limit.)
    #[test]
    fn the_wave_vector_limit_bounds_the_half_index_box() {
        let sites = [Vector3::new(0.1, 0.2, 0.3), Vector3::new(0.6, 0.7, 0.8)];
        let build = |m: f64| {
            let parameters = EwaldParameters {
                alpha: 1.0,
                real_cutoff: 0.2,
                reciprocal_cutoff: 2.0 * PI * (m + 0.5),
                real_estimate: 0.0,
                reciprocal_estimate: 0.0,
            };
            let half_box = (2.0 * m + 1.0_f64).powi(3) / 2.0;
            let sum = EwaldSum::with_parameters(
                &sites,
                Vector3::repeat(1.0),
                parameters,
                Surface::Conducting,
            );
            (half_box, sum.map(|s| s.waves.len()))
        };
        let (half_box, built) = build(108.0);
        assert!(half_box > MAX_WAVE_VECTORS as f64 / 2.0 && half_box < MAX_WAVE_VECTORS as f64);
        let waves = built.unwrap();
        // The sphere fills pi/6 of the index box.
        assert!(
            (waves as f64 / half_box - PI / 6.0).abs() < 1e-2,
            "{waves} of {half_box}"
        );
        let (half_box, refused) = build(136.0);
        assert!(half_box > MAX_WAVE_VECTORS as f64);
        let e = refused.unwrap_err();
        assert_eq!(e.path, "accuracy", "{e}");
        assert!(
            e.message.contains(&format!(
                "needs about {half_box:.2e} reciprocal-space wave vectors"
            )),
            "{e}"
        );
    }
}
