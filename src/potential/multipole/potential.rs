//! [`MultipolePotential`]: point multipoles on fixed sites, as polynomials of
//! the quaternions.

use super::auto_choice::AutoChoice;
use super::field_sum::FieldSum;
use super::kernels::{
    accumulate_pair_fields, Dipoles, DipolesAndQuadrupoles, Lanes, MultipoleKind, Quadrupoles,
    SiteFields, SpaceMultipoles,
};
use super::lattice_grid::LatticeGrid;
use super::mesh_ewald::{ForcedMesh, MeshEstimate, MeshParameters};
use super::pairs::{balanced_blocks, PairRows};
use super::sum_method::{SumMethod, SumPath};
use super::{Boundary, EwaldParameters, ExternalFields, PotentialError};
use crate::potential::{multipole_torque_axes, Potential, TorqueAxes};
use crate::quaternion::Quat;
use crate::rotor::Rotor;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Rotors per rayon task in the per-rotor loops (below this, threads cost more than they save).
const ROTORS_PER_TASK: usize = 256;

/// Which kernels a system needs, fixed at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Carried {
    Nothing,
    Dipoles,
    Quadrupoles,
    Both,
}

/// Point dipoles and quadrupoles on fixed sites, with optional uniform
/// external fields.
///
/// The energy is a polynomial in the quaternion components: the space-frame
/// multipoles are `mu_s = A(Q)^T mu_b` and `Theta_s = A(Q)^T Theta_b A(Q)`
/// with `A` of eq 7 (for a non-unit `Q`, `A` is `|Q|^2` times a rotation, and
/// the polynomial is what is differentiated), so `V` is homogeneous of degree
/// 2 in a rotor's `Q` for its dipole terms and 4 for its quadrupole terms.
/// The gradient of eq 14 is `dV/dq_k = dA/dq_k : B` with
/// `B = -mu_b E^T + 2 Theta_b A W`, where `E = -dV/dmu_s` and
/// `W = dV/dTheta_s` are the conjugate fields; the space-frame torque is
/// `mu_s x E - 2 vec(Theta_s W)` with `vec(M)_c = eps_abc M_ab`.
///
/// Periodic boxes are summed with a plain cutoff or by Ewald (see
/// [`super::PeriodicSum`]): on any sites directly or by smooth particle-mesh
/// Ewald, on a lattice by FFT ([`SumMethod`], [`SumPath`]); any way the sum gives the fields `E` and `W` at the
/// sites, and the gradient and torques follow from them as above.
///
/// Units are reduced with `4 pi eps0 = 1`. Left out: charges, octupoles and
/// higher, polarisation, damping at short range.
///
/// ```
/// use nalgebra::Vector3;
/// use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
/// use quatrot::rotor::{Inertia, Rotor};
/// use quatrot::Quat;
///
/// // Two unit dipoles head to tail at distance 2: V = -2 / 2^3.
/// let rotor = |z: f64| Rotor {
///     site: Vector3::new(0.0, 0.0, z),
///     inertia: Inertia::Spherical(1.0),
///     dipole_body: Some(Vector3::z()),
///     quadrupole_body: None,
/// };
/// let p = MultipolePotential::new(&[rotor(0.0), rotor(2.0)], Boundary::Open, ExternalFields::NONE)?;
/// let q = [Quat::IDENTITY, -Quat::IDENTITY]; // -Q is the same orientation
/// assert!((p.energy(&q) + 0.25).abs() < 1e-15);
/// // Aligned dipoles feel no torque.
/// let mut torques = [Vector3::zeros(); 2];
/// p.accumulate_torques(&q, &mut torques);
/// assert!(torques.iter().all(|t| t.norm() < 1e-15));
/// # Ok::<(), quatrot::potential::PotentialError>(())
/// ```
#[derive(Clone, Debug)]
pub struct MultipolePotential {
    carried: Carried,
    dipoles_body: Vec<Vector3<f64>>,
    quadrupoles_body: Vec<Matrix3<f64>>,
    sum: FieldSum,
    choice: Option<AutoChoice>,
    external: ExternalFields,
}

impl MultipolePotential {
    /// Builds the pair list and the pair geometry once. Checks every input:
    /// finite sites and multipoles, symmetric traceless body quadrupoles
    /// (Buckingham convention, see [`super::convention`]; [`Rotor::check`]),
    /// distinct sites, a valid box and cutoff ([`Boundary::validate`]),
    /// finite symmetric external fields ([`ExternalFields::validate`]).
    pub fn new(
        rotors: &[Rotor],
        boundary: Boundary,
        external: ExternalFields,
    ) -> Result<MultipolePotential, PotentialError> {
        Self::with_method(rotors, boundary, external, SumMethod::Auto)
    }

    /// [`Self::new`] with the way of summing chosen (see [`SumMethod`]).
    pub fn with_method(
        rotors: &[Rotor],
        boundary: Boundary,
        external: ExternalFields,
        method: SumMethod,
    ) -> Result<MultipolePotential, PotentialError> {
        Self::with_forced_mesh(rotors, boundary, external, method, &ForcedMesh::default())
    }

    /// [`Self::with_method`] with parameters of the mesh Ewald sum `forced`
    /// (only with [`SumMethod::Pme`]; the others chosen for the accuracy).
    pub fn with_forced_mesh(
        rotors: &[Rotor],
        boundary: Boundary,
        external: ExternalFields,
        method: SumMethod,
        forced: &ForcedMesh,
    ) -> Result<MultipolePotential, PotentialError> {
        boundary.validate(rotors.len())?;
        external.validate()?;
        for (i, rotor) in rotors.iter().enumerate() {
            rotor.check().map_err(|e| e.at(&format!("rotors[{i}]")))?;
        }
        let has_dipoles = rotors.iter().any(|r| r.dipole_body.is_some());
        let has_quadrupoles = rotors.iter().any(|r| r.quadrupole_body.is_some());
        let carried = match (has_dipoles, has_quadrupoles) {
            (false, false) => Carried::Nothing,
            (true, false) => Carried::Dipoles,
            (false, true) => Carried::Quadrupoles,
            (true, true) => Carried::Both,
        };
        let sites: Vec<_> = if carried == Carried::Nothing {
            Vec::new()
        } else {
            rotors.iter().map(|r| r.site).collect()
        };
        let (sum, choice) = FieldSum::build(
            &sites,
            boundary,
            (method, forced),
            (has_dipoles, has_quadrupoles),
        )?;
        // Each carried kind for every rotor (zero where a rotor has none).
        let body = |carried: bool| rotors.iter().filter(move |_| carried);
        Ok(MultipolePotential {
            carried,
            dipoles_body: body(has_dipoles)
                .map(|r| r.dipole_body.unwrap_or_default())
                .collect(),
            quadrupoles_body: body(has_quadrupoles)
                .map(|r| r.quadrupole_body.unwrap_or_default())
                .collect(),
            sum,
            choice,
            external,
        })
    }

    /// Number of interacting pairs of the pair list, each counted once (the
    /// real-space pairs of a direct Ewald sum; 0 for an FFT lattice sum and
    /// the mesh Ewald sum).
    pub fn pair_count(&self) -> usize {
        self.sum.pair_count()
    }

    /// Number of distinct pair geometries stored (shared by equal offsets;
    /// 0 unless the pair list of a truncated periodic sum is used: open
    /// clusters compute theirs row by row).
    pub fn geometry_count(&self) -> usize {
        self.sum.geometry_count()
    }

    /// The way the pair fields are summed.
    pub fn sum_path(&self) -> SumPath {
        self.sum.path()
    }

    /// The lattice of the box the FFT lattice sum runs on (`None` for the other sums).
    pub fn lattice(&self) -> Option<&LatticeGrid> {
        self.sum.lattice()
    }

    /// The Ewald parameters chosen for the requested accuracy (`None`
    /// without an Ewald sum).
    pub fn ewald_parameters(&self) -> Option<EwaldParameters> {
        self.sum.ewald_parameters()
    }

    /// What `method = "auto"` compared when it chose between the direct
    /// Ewald sum and PME on sites that are not a lattice (`None` for every
    /// other path and method).
    pub fn auto_choice(&self) -> Option<&AutoChoice> {
        self.choice.as_ref()
    }

    /// The mesh Ewald parameters chosen for the requested accuracy and
    /// their estimated errors (`None` without the mesh Ewald sum).
    pub fn mesh_parameters(&self) -> Option<(MeshParameters, MeshEstimate)> {
        self.sum.mesh_parameters()
    }

    /// One evaluation: returns the energy and, when asked, adds the eq 14
    /// gradient `dV/dq_k` and the space-frame torques into the given slices.
    /// The pair loop is split into as many blocks of rows as the current
    /// rayon pool has threads, each with its own field buffer, and the blocks
    /// are summed in block order: results are bitwise reproducible for a given
    /// thread count (different counts differ by rounding only; dipole-only
    /// lattices, summed row by row, do not depend on the count at all).
    ///
    /// # Panics
    /// If a slice length differs from the number of rotors (a programming
    /// error: the bindings check shapes before calling).
    pub fn evaluate(
        &self,
        orientations: &[Quat],
        gradient: Option<&mut [Quat]>,
        torques_space: Option<&mut [Vector3<f64>]>,
    ) -> f64 {
        self.evaluate_with(orientations, gradient, torques_space, true)
    }

    /// [`Self::evaluate`], the energy summed only when `energy` (otherwise
    /// 0 is returned): the steps of the integrators need no energy.
    fn evaluate_with(
        &self,
        orientations: &[Quat],
        gradient: Option<&mut [Quat]>,
        torques_space: Option<&mut [Vector3<f64>]>,
        energy: bool,
    ) -> f64 {
        let (q, g, t, e) = (orientations, gradient, torques_space, energy);
        match self.carried {
            Carried::Nothing => 0.0,
            Carried::Dipoles => self.evaluate_kind::<Dipoles>(q, g, t, e),
            Carried::Quadrupoles => self.evaluate_kind::<Quadrupoles>(q, g, t, e),
            Carried::Both => self.evaluate_kind::<DipolesAndQuadrupoles>(q, g, t, e),
        }
    }

    fn rotor_count(&self) -> usize {
        self.dipoles_body.len().max(self.quadrupoles_body.len())
    }

    /// One evaluation in three parallel passes and the pair sum: the
    /// space-frame multipoles (per rotor), the pair fields (the sum's own
    /// sections), the energy when asked (in rotor order, on one thread), and
    /// one per-rotor pass that adds the external fields and writes the
    /// gradient and the torques ([`Self::add_per_rotor`]).
    fn evaluate_kind<K: MultipoleKind>(
        &self,
        orientations: &[Quat],
        gradient: Option<&mut [Quat]>,
        torques: Option<&mut [Vector3<f64>]>,
        energy: bool,
    ) -> f64 {
        let n = self.rotor_count();
        assert_eq!(orientations.len(), n, "orientations: one per rotor");
        let multipoles = self.space_multipoles::<K>(orientations);
        let fields = self.pair_fields::<K>(&multipoles);
        let energy = if energy {
            self.energy::<K>(&multipoles, &fields)
        } else {
            0.0
        };
        let gradient = gradient.inspect(|g| assert_eq!(g.len(), n, "gradient: one per rotor"));
        let torques = torques.inspect(|t| assert_eq!(t.len(), n, "torques_space: one per rotor"));
        self.add_per_rotor::<K>(orientations, &multipoles, &fields, gradient, torques);
        energy
    }

    /// `mu_s = A^T mu_b` and `Theta_s = A^T Theta_b A` for every rotor.
    fn space_multipoles<K: MultipoleKind>(&self, orientations: &[Quat]) -> SpaceMultipoles {
        let mut out = SpaceMultipoles::default();
        if K::DIPOLES {
            out.dipoles = orientations
                .par_iter()
                .with_min_len(ROTORS_PER_TASK)
                .zip(&self.dipoles_body)
                .map(|(q, mu_b)| {
                    let mu_s = q.space_to_body_matrix().tr_mul(mu_b);
                    Lanes([mu_s.x, mu_s.y, mu_s.z, 0.0])
                })
                .collect();
        }
        if K::QUADRUPOLES {
            out.quadrupoles = orientations
                .par_iter()
                .with_min_len(ROTORS_PER_TASK)
                .zip(&self.quadrupoles_body)
                .map(|(q, theta_b)| {
                    let a = q.space_to_body_matrix();
                    a.tr_mul(theta_b) * a
                })
                .collect();
        }
        out
    }

    /// The pair fields. Dipole-only systems regrouped in quads of rows: each
    /// thread writes its own rows. Otherwise one block of rows of the half
    /// list per rayon thread, each with its own buffer, summed in block order.
    fn pair_fields<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles) -> SiteFields {
        let (pairs, row_quads) = match &self.sum {
            FieldSum::Pairs { pairs, row_quads } => (pairs, row_quads),
            FieldSum::Open(pairs) => return self.half_list_fields::<K, _>(pairs, multipoles),
            FieldSum::Ewald(ewald) => return ewald.fields::<K>(multipoles),
            FieldSum::LatticeFft(fft) => return fft.fields::<K>(multipoles),
            FieldSum::Mesh(mesh) => return mesh.fields::<K>(multipoles),
        };
        let n = self.rotor_count();
        if let (true, false, Some(quads)) = (K::DIPOLES, K::QUADRUPOLES, row_quads) {
            let mut fields = SiteFields::zeros::<K>(n);
            let dipoles = quads.extend(&multipoles.dipoles);
            let per_thread = quads.quads().div_ceil(rayon::current_num_threads());
            fields
                .field
                .par_chunks_mut(4 * per_thread.max(1))
                .enumerate()
                .for_each(|(k, rows)| quads.fields(&dipoles, k * per_thread.max(1), rows));
            return fields;
        }
        self.half_list_fields::<K, _>(pairs, multipoles)
    }

    /// The pair fields of a half list: one block of rows per rayon thread,
    /// each with its own buffer, summed in block order.
    fn half_list_fields<K: MultipoleKind, R: PairRows>(
        &self,
        pairs: &R,
        multipoles: &SpaceMultipoles,
    ) -> SiteFields {
        let n = self.rotor_count();
        let blocks = balanced_blocks(pairs.starts(), rayon::current_num_threads());
        let partial: Vec<(usize, SiteFields)> = blocks
            .into_par_iter()
            .map(|rows| {
                let mut fields = SiteFields::zeros::<K>(n);
                let first = rows.start;
                accumulate_pair_fields::<K, R>(pairs, rows, multipoles, &mut fields);
                (first, fields)
            })
            .collect();
        SiteFields::sum_blocks::<K>(partial, n)
    }

    /// The energy `1/2 sum (-mu.E + Theta:W)` of the pair fields plus the
    /// external terms `-mu.E0 - 1/3 Theta:G0`, summed in rotor order.
    fn energy<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles, fields: &SiteFields) -> f64 {
        let mut energy = 0.0;
        if K::DIPOLES {
            let pair: f64 = multipoles
                .dipoles
                .iter()
                .zip(&fields.field)
                .map(|(mu, e)| mu[0] * e[0] + mu[1] * e[1] + mu[2] * e[2])
                .sum();
            energy -= 0.5 * pair;
            if let Some(e0) = self.external.field {
                let total_dipole = multipoles.dipoles.iter().fold(Vector3::zeros(), |acc, mu| {
                    acc + Vector3::new(mu[0], mu[1], mu[2])
                });
                energy -= total_dipole.dot(&e0);
            }
        }
        if K::QUADRUPOLES {
            let pair: f64 = multipoles
                .quadrupoles
                .iter()
                .zip(&fields.quadrupole_conjugate)
                .map(|(theta, w)| theta.dot(w))
                .sum();
            energy += 0.5 * pair;
            if let Some(g0) = self.external.field_gradient {
                let total: Matrix3<f64> = multipoles.quadrupoles.iter().sum();
                energy += total.dot(&external_conjugate(&g0));
            }
        }
        energy
    }

    /// One parallel pass over the rotors: the external fields (`E0`, and
    /// `W0 = -G0/3`) added to each rotor's pair fields, then
    /// `dV/dq_k = dA/dq_k : B` (eq 14), `B = -mu_b E^T + 2 Theta_b A W`,
    /// added to `gradient` and `mu_s x E - 2 vec(Theta_s W)` to `torques`.
    fn add_per_rotor<K: MultipoleKind>(
        &self,
        orientations: &[Quat],
        multipoles: &SpaceMultipoles,
        fields: &SiteFields,
        gradient: Option<&mut [Quat]>,
        torques: Option<&mut [Vector3<f64>]>,
    ) {
        let e0 = self.external.field.filter(|_| K::DIPOLES);
        let w0 = self
            .external
            .field_gradient
            .filter(|_| K::QUADRUPOLES)
            .map(|g0| external_conjugate(&g0));
        let field = |i: usize| {
            let e = &fields.field[i];
            match e0 {
                Some(e0) => Vector3::new(e[0] + e0[0], e[1] + e0[1], e[2] + e0[2]),
                None => Vector3::new(e[0], e[1], e[2]),
            }
        };
        let conjugate = |i: usize| match w0 {
            Some(w0) => fields.quadrupole_conjugate[i] + w0,
            None => fields.quadrupole_conjugate[i],
        };
        let gradient_of = |i: usize| {
            let q = &orientations[i];
            let mut b = Matrix3::zeros();
            if K::DIPOLES {
                b -= self.dipoles_body[i] * field(i).transpose();
            }
            if K::QUADRUPOLES {
                let a = q.space_to_body_matrix();
                b += self.quadrupoles_body[i] * a * conjugate(i) * 2.0;
            }
            let d = q.space_to_body_matrix_derivatives();
            Quat(std::array::from_fn(|k| d[k].dot(&b)))
        };
        let add_torque = |i: usize, torque: &mut Vector3<f64>| {
            if K::DIPOLES {
                let mu = &multipoles.dipoles[i];
                *torque += Vector3::new(mu[0], mu[1], mu[2]).cross(&field(i));
            }
            if K::QUADRUPOLES {
                let m = multipoles.quadrupoles[i] * conjugate(i);
                *torque -= Vector3::new(m.m23 - m.m32, m.m31 - m.m13, m.m12 - m.m21) * 2.0;
            }
        };
        match (gradient, torques) {
            (Some(gradient), Some(torques)) => gradient
                .par_iter_mut()
                .zip(torques)
                .with_min_len(ROTORS_PER_TASK)
                .enumerate()
                .for_each(|(i, (g, t))| {
                    *g += gradient_of(i);
                    add_torque(i, t);
                }),
            (Some(gradient), None) => gradient
                .par_iter_mut()
                .with_min_len(ROTORS_PER_TASK)
                .enumerate()
                .for_each(|(i, g)| *g += gradient_of(i)),
            (None, Some(torques)) => torques
                .par_iter_mut()
                .with_min_len(ROTORS_PER_TASK)
                .enumerate()
                .for_each(|(i, t)| add_torque(i, t)),
            (None, None) => {}
        }
    }
}

/// `W0 = -G0/3` of the field gradient `G0` (symmetrised).
fn external_conjugate(g0: &Matrix3<f64>) -> Matrix3<f64> {
    (g0 + g0.transpose()) / -6.0
}

impl Potential for MultipolePotential {
    fn energy(&self, orientations: &[Quat]) -> f64 {
        self.evaluate(orientations, None, None)
    }

    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) {
        let _ = self.evaluate_with(orientations, Some(gradient), None, false);
    }

    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]) {
        let _ = self.evaluate_with(orientations, None, Some(torques_space), false);
    }

    fn energy_and_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) -> f64 {
        self.evaluate(orientations, Some(gradient), None)
    }

    /// From the rotor's body multipoles ([`multipole_torque_axes`]): pair
    /// terms and uniform fields alike exert no torque about an axis of
    /// symmetry of all its multipoles.
    fn torque_axes(&self, rotor: usize) -> TorqueAxes {
        multipole_torque_axes(
            self.dipoles_body.get(rotor),
            self.quadrupoles_body.get(rotor),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::Inertia;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    /// The quad kernel sums each row in another order than the half list
    /// (~100 terms of a few ulps each, then the per-rotor products).
    const SUMMATION_ORDER: f64 = 1e-13;

    /// The 10^3 periodic lattice of dipoles in a uniform field: the quad
    /// kernel (selected) and the half list kernel give the same energy,
    /// gradient and torques at random orientations; the quad kernel's results
    /// are bitwise the same on one and on two threads.
    #[test]
    fn quad_kernel_matches_the_half_list_with_a_field() {
        let rotors: Vec<Rotor> = (0..1000)
            .map(|k| Rotor {
                site: Vector3::new((k / 100) as f64, ((k / 10) % 10) as f64, (k % 10) as f64),
                inertia: Inertia::Spherical(1.0),
                dipole_body: Some(Vector3::new(0.3, -0.2, 1.0)),
                quadrupole_body: None,
            })
            .collect();
        let boundary = Boundary::periodic_cutoff(Vector3::repeat(10.0), 3.1);
        let external = ExternalFields {
            field: Some(Vector3::new(0.4, -1.3, 0.7)),
            field_gradient: None,
        };
        let quads = MultipolePotential::new(&rotors, boundary, external).unwrap();
        let FieldSum::Pairs {
            pairs, row_quads, ..
        } = &quads.sum
        else {
            panic!("a pair sum");
        };
        assert!(row_quads.is_some());
        let half_list = MultipolePotential {
            sum: FieldSum::Pairs {
                pairs: pairs.clone(),
                row_quads: None,
            },
            ..quads.clone()
        };
        let mut rng = ChaCha20Rng::seed_from_u64(8);
        let q: Vec<Quat> = (0..1000)
            .map(|_| {
                let v: [f64; 4] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
                let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                Quat(v.map(|x| x / norm))
            })
            .collect();
        let run = |p: &MultipolePotential, threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut gradient = vec![Quat::ZERO; 1000];
            let mut torques = vec![Vector3::zeros(); 1000];
            let energy = pool.install(|| p.evaluate(&q, Some(&mut gradient), Some(&mut torques)));
            (energy, gradient, torques)
        };
        let (e, g, t) = run(&quads, 1);
        let (e_ref, g_ref, t_ref) = run(&half_list, 1);
        assert!(
            (e - e_ref).abs() <= SUMMATION_ORDER * e_ref.abs(),
            "{e} {e_ref}"
        );
        let g_scale = g_ref
            .iter()
            .flat_map(|g| g.0)
            .fold(0.0, |m: f64, x| m.max(x.abs()));
        for (a, b) in g.iter().zip(&g_ref) {
            for k in 0..4 {
                assert!((a.0[k] - b.0[k]).abs() <= SUMMATION_ORDER * g_scale);
            }
        }
        let t_scale = t_ref.iter().map(|t| t.amax()).fold(0.0, f64::max);
        for (a, b) in t.iter().zip(&t_ref) {
            assert!((a - b).amax() <= SUMMATION_ORDER * t_scale);
        }
        let (e2, g2, t2) = run(&quads, 2);
        assert_eq!(e.to_bits(), e2.to_bits());
        assert!(g.iter().zip(&g2).all(|(a, b)| a.0 == b.0));
        assert_eq!(t, t2);
    }
}
