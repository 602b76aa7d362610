//! The point-multipole potential, term by term: analytic gradient (eq 14) vs
//! central differences, torques vs rotations, eq 13 vs projected eq 14,
//! Euler's theorem for the unprojected eq 14, rotational invariance,
//! conservation of angular momentum, and closed forms (dipole pairs,
//! Buckingham's linear quadrupoles, point-charge clusters).

mod multipole_support;

use multipole_support::*;
use nalgebra::{Matrix3, SymmetricEigen, Unit, Vector3};
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::multipole::convention::{
    buckingham_quadrupole, quadrupole_from_openmm, quadrupole_to_openmm,
};
use quatrot::potential::{
    Accuracy, Boundary, ExternalFields, MultipolePotential, PeriodicSum, Potential, SumMethod,
    Surface,
};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;

/// Central differences with h = 1e-6: truncation ~h^2 V''' and round-off ~eps V / h, both < 1e-8.
const FD_TOLERANCE: f64 = 1e-7;
/// Step of the central differences (quaternion components, rotation angles, site coordinates).
const FD_STEP: f64 = 1e-6;
/// Two analytic evaluations of the same quantity differ only by round-off.
const ROUND_OFF_TOLERANCE: f64 = 1e-12;
/// Round-off accumulated over sums of ~100 pair terms and quaternion products
/// (relative to the largest term; ~100 ulp).
const SUM_ROUND_OFF_TOLERANCE: f64 = 1e-10;
/// Point-charge clusters of size d = 0.01 at separation ~2, Richardson-extrapolated
/// in d (error ~(d/r)^4 ~ 1e-9), with round-off from charges ~1e4 (~1e-7).
const CHARGE_CLUSTER_TOLERANCE: f64 = 1e-5;

struct Case {
    name: &'static str,
    rotors: Vec<Rotor>,
    boundary: Boundary,
    external: ExternalFields,
    orientations: Vec<Quat>,
    /// `sum_i Q_i.dV/dQ_i = degree * V` (Euler's theorem), for single-term cases.
    euler_degree: Option<f64>,
    /// How a periodic sum is taken.
    method: SumMethod,
}

impl Case {
    fn potential(&self) -> MultipolePotential {
        MultipolePotential::with_method(&self.rotors, self.boundary, self.external, self.method)
            .expect(self.name)
    }
    /// Open and free of external fields: total angular momentum is conserved.
    fn isolated(&self) -> bool {
        self.boundary == Boundary::Open && self.external == ExternalFields::NONE
    }
}

fn open_case(
    name: &'static str,
    seed: u64,
    kinds: &[(bool, bool)],
    external: ExternalFields,
    euler_degree: Option<f64>,
) -> Case {
    let mut r = rng(seed);
    let sites = cluster_sites(&mut r, kinds.len());
    let rotors = sites
        .into_iter()
        .zip(kinds)
        .map(|(s, &(d, q))| random_rotor(&mut r, s, d, q))
        .collect();
    let orientations = kinds.iter().map(|_| random_orientation(&mut r)).collect();
    Case {
        name,
        rotors,
        boundary: Boundary::Open,
        external,
        orientations,
        euler_degree,
        method: SumMethod::Auto,
    }
}

fn all_cases() -> Vec<Case> {
    let mut r = rng(7);
    let field = ExternalFields {
        field: Some(random_vector(&mut r, 1.0)),
        field_gradient: None,
    };
    let gradient = ExternalFields {
        field: None,
        field_gradient: Some(random_quadrupole(&mut r, 1.0)),
    };
    let both_fields = ExternalFields {
        field: field.field,
        field_gradient: gradient.field_gradient,
    };
    let lattice = Lattice::cubic(LatticeKind::Fcc, 2, 1.6).unwrap();
    let periodic_rotors: Vec<_> = lattice
        .sites
        .iter()
        .map(|s| random_rotor(&mut r, *s, true, true))
        .collect();
    let periodic = Case {
        name: "periodic fcc, all terms",
        orientations: periodic_rotors
            .iter()
            .map(|_| random_orientation(&mut r))
            .collect(),
        rotors: periodic_rotors.clone(),
        boundary: Boundary::periodic_cutoff(lattice.box_lengths, 1.5),
        external: both_fields,
        euler_degree: None,
        method: SumMethod::Auto,
    };
    let ewald = |surface| Boundary::Periodic {
        box_lengths: lattice.box_lengths,
        sum: PeriodicSum::Ewald {
            accuracy: Accuracy::new(1e-10).expect("in (0, 1)"),
            surface,
        },
    };
    let periodic_ewald_fft = Case {
        name: "periodic fcc, Ewald by FFT, vacuum, all terms",
        orientations: periodic.orientations.clone(),
        rotors: periodic_rotors.clone(),
        boundary: ewald(Surface::Vacuum),
        external: both_fields,
        euler_degree: None,
        method: SumMethod::Auto,
    };
    let periodic_pme = Case {
        name: "periodic fcc, PME, vacuum, all terms",
        orientations: periodic.orientations.clone(),
        rotors: periodic_rotors.clone(),
        boundary: Boundary::Periodic {
            box_lengths: lattice.box_lengths,
            sum: PeriodicSum::Ewald {
                // The PME energy is differentiable at any accuracy: the
                // coarsest mesh keeps the finite differences quick.
                accuracy: Accuracy::new(1e-3).expect("in (0, 1)"),
                surface: Surface::Vacuum,
            },
        },
        external: both_fields,
        euler_degree: None,
        method: SumMethod::Pme,
    };
    let periodic_ewald_direct = Case {
        name: "periodic fcc, direct Ewald, conducting",
        orientations: periodic.orientations.clone(),
        rotors: periodic_rotors,
        boundary: ewald(Surface::Conducting),
        external: ExternalFields::NONE,
        euler_degree: None,
        method: SumMethod::Direct,
    };
    // Irregular sites with mixed multipoles: the direct Ewald sum.
    let box_lengths = Vector3::new(2.9, 3.3, 2.5);
    let scattered: Vec<Rotor> = (0..7)
        .map(|k| {
            let site =
                (random_vector(&mut r, 0.5) + Vector3::repeat(0.5)).component_mul(&box_lengths);
            random_rotor(&mut r, site, k % 3 != 2, k % 3 != 0)
        })
        .collect();
    let scattered_ewald = Case {
        name: "periodic scattered, Ewald, vacuum",
        orientations: scattered
            .iter()
            .map(|_| random_orientation(&mut r))
            .collect(),
        rotors: scattered,
        boundary: Boundary::Periodic {
            box_lengths,
            sum: PeriodicSum::Ewald {
                accuracy: Accuracy::new(1e-10).expect("in (0, 1)"),
                surface: Surface::Vacuum,
            },
        },
        external: ExternalFields::NONE,
        euler_degree: None,
        method: SumMethod::Auto,
    };
    let none = ExternalFields::NONE;
    vec![
        open_case("dipole-dipole", 1, &[(true, false); 6], none, Some(4.0)),
        open_case(
            "dipole-quadrupole",
            2,
            &[(true, false), (false, true)],
            none,
            Some(6.0),
        ),
        open_case(
            "quadrupole-quadrupole",
            3,
            &[(false, true); 6],
            none,
            Some(8.0),
        ),
        open_case("field", 4, &[(true, false)], field, Some(2.0)),
        open_case("field gradient", 5, &[(false, true)], gradient, Some(4.0)),
        open_case(
            "mixed cluster",
            6,
            &[
                (true, true),
                (true, false),
                (false, true),
                (true, true),
                (true, true),
            ],
            none,
            None,
        ),
        open_case(
            "mixed cluster in fields",
            8,
            &[(true, true), (true, false), (false, true), (true, true)],
            both_fields,
            None,
        ),
        periodic,
        periodic_ewald_fft,
        periodic_ewald_direct,
        periodic_pme,
        scattered_ewald,
    ]
}

fn gradient_of(p: &MultipolePotential, q: &[Quat]) -> Vec<Quat> {
    let mut g = vec![Quat::ZERO; q.len()];
    p.accumulate_gradient(q, &mut g);
    g
}

fn torques_of(p: &MultipolePotential, q: &[Quat]) -> Vec<Vector3<f64>> {
    let mut t = vec![Vector3::zeros(); q.len()];
    p.accumulate_torques(q, &mut t);
    t
}

/// Eq 14: the analytic dV/dq_k equals central differences of the energy
/// polynomial, every component of every rotor, for every term.
#[test]
fn gradient_matches_central_differences() {
    for case in all_cases() {
        let p = case.potential();
        let q = &case.orientations;
        let g = gradient_of(&p, q);
        let scale = g.iter().map(|x| x.norm()).fold(1.0, f64::max);
        for (i, gi) in g.iter().enumerate() {
            for (k, &analytic) in gi.0.iter().enumerate() {
                let shifted = |h: f64| {
                    let mut qs = q.clone();
                    qs[i].0[k] += h;
                    p.energy(&qs)
                };
                let fd = (shifted(FD_STEP) - shifted(-FD_STEP)) / (2.0 * FD_STEP);
                let err = (fd - analytic).abs() / scale;
                assert!(
                    err < FD_TOLERANCE,
                    "{}: rotor {i} q{k}: fd {fd} vs {} (rel {err:e})",
                    case.name,
                    analytic
                );
            }
        }
    }
}

/// The torques generate the energy change of small space-frame rotations:
/// rotating every rotor by eps*u_i changes V by -eps sum_i torque_i.u_i.
#[test]
fn torques_match_directional_difference() {
    for case in all_cases() {
        let p = case.potential();
        let q = &case.orientations;
        let t = torques_of(&p, q);
        let mut r = rng(11);
        let dirs: Vec<_> = q.iter().map(|_| random_vector(&mut r, 1.0)).collect();
        let rotated = |eps: f64| {
            let qs: Vec<_> = q
                .iter()
                .zip(&dirs)
                .map(|(qi, u)| Quat::exp(&(u * eps)) * *qi)
                .collect();
            p.energy(&qs)
        };
        let fd = (rotated(FD_STEP) - rotated(-FD_STEP)) / (2.0 * FD_STEP);
        let predicted: f64 = -t.iter().zip(&dirs).map(|(ti, u)| ti.dot(u)).sum::<f64>();
        let scale: f64 = t
            .iter()
            .zip(&dirs)
            .map(|(ti, u)| ti.norm() * u.norm())
            .sum::<f64>()
            .max(1.0);
        let err = (fd - predicted).abs() / scale;
        assert!(
            err < FD_TOLERANCE,
            "{}: dV {fd} vs -sum torque.u {predicted} (rel {err:e})",
            case.name
        );
    }
}

/// Eq 13 vs eq 14 after the note's projection: for every rotor,
/// `-dV/dQ + (Q.dV/dQ) Q = 2 N_s*Q` with `N_s = (0, torque_space)`; every
/// term, the truncated periodic sum and the Ewald sums (FFT, direct and
/// PME, conducting and vacuum).
#[test]
fn projected_eq14_equals_eq13() {
    for case in all_cases() {
        let p = case.potential();
        let q = &case.orientations;
        let g = gradient_of(&p, q);
        let t = torques_of(&p, q);
        for i in 0..q.len() {
            let projected = -g[i] + q[i] * q[i].dot(&g[i]);
            let eq13 = Quat::pure(&t[i]) * q[i] * 2.0;
            let scale = g[i].norm().max(1.0);
            let err = (projected - eq13).norm() / scale;
            assert!(
                err < SUM_ROUND_OFF_TOLERANCE,
                "{}: rotor {i}: {projected:?} vs {eq13:?}",
                case.name
            );
        }
    }
}

/// The literal eq 14, N = -dV/dQ, is not a torque: V is homogeneous in each Q
/// (degree 2 per dipole, 4 per quadrupole), so by Euler's theorem
/// `sum_i Q_i.dV/dQ_i = k V != 0`, whereas eq 13's `2 N_s*Q` is orthogonal to Q.
#[test]
fn unprojected_eq14_has_euler_component_along_q() {
    for case in all_cases() {
        let Some(degree) = case.euler_degree else {
            continue;
        };
        let p = case.potential();
        let q = &case.orientations;
        let g = gradient_of(&p, q);
        let v = p.energy(q);
        let along_q: f64 = q.iter().zip(&g).map(|(qi, gi)| qi.dot(gi)).sum();
        assert!(
            v.abs() > 1e-3,
            "{}: choose a configuration with V != 0",
            case.name
        );
        let err = (along_q - degree * v).abs() / v.abs();
        assert!(
            err < SUM_ROUND_OFF_TOLERANCE,
            "{}: Q.dV/dQ {along_q} vs {degree} V = {}",
            case.name,
            degree * v
        );
        let t = torques_of(&p, q);
        let eq13_along_q: f64 = q
            .iter()
            .zip(&t)
            .map(|(qi, ti)| (Quat::pure(ti) * *qi * 2.0).dot(qi))
            .sum();
        assert!(eq13_along_q.abs() < SUM_ROUND_OFF_TOLERANCE * v.abs().max(1.0));
    }
}

/// Rotating the sites, the orientations and the external fields together
/// leaves the energy unchanged (open boundaries).
#[test]
fn energy_is_invariant_under_global_rotation() {
    let mut r = rng(12);
    for case in all_cases()
        .into_iter()
        .filter(|c| c.boundary == Boundary::Open)
    {
        let p0 = case.potential();
        let v0 = p0.energy(&case.orientations);
        let turn = random_orientation(&mut r);
        let rot = turn.body_to_space_matrix();
        let rotors: Vec<_> = case
            .rotors
            .iter()
            .map(|ro| Rotor {
                site: rot * ro.site,
                ..ro.clone()
            })
            .collect();
        let external = ExternalFields {
            field: case.external.field.map(|e| rot * e),
            field_gradient: case
                .external
                .field_gradient
                .map(|g| rot * g * rot.transpose()),
        };
        let q: Vec<_> = case.orientations.iter().map(|qi| turn * *qi).collect();
        let v1 = MultipolePotential::new(&rotors, case.boundary, external)
            .unwrap()
            .energy(&q);
        let err = (v1 - v0).abs() / v0.abs().max(1.0);
        assert!(err < ROUND_OFF_TOLERANCE, "{}: {v0} vs {v1}", case.name);
    }
}

/// An isolated cluster conserves angular momentum: the torques plus the
/// moments of the pair forces (here from central differences of the energy
/// with respect to the sites) sum to zero.
#[test]
fn isolated_cluster_conserves_angular_momentum() {
    for case in all_cases().into_iter().filter(Case::isolated) {
        let p = case.potential();
        let q = &case.orientations;
        let torques = torques_of(&p, q);
        let mut total = torques.iter().sum::<Vector3<f64>>();
        let mut scale: f64 = torques.iter().map(|t| t.norm()).sum();
        for (i, rotor) in case.rotors.iter().enumerate() {
            let force = Vector3::from_fn(|a, _| {
                let moved = |h: f64| {
                    let mut rotors = case.rotors.clone();
                    rotors[i].site[a] += h;
                    MultipolePotential::new(&rotors, case.boundary, case.external)
                        .unwrap()
                        .energy(q)
                };
                -(moved(FD_STEP) - moved(-FD_STEP)) / (2.0 * FD_STEP)
            });
            let moment = rotor.site.cross(&force);
            scale += moment.norm();
            total += moment;
        }
        assert!(
            total.norm() < FD_TOLERANCE * scale.max(1.0),
            "{}: sum = {total:?}",
            case.name
        );
    }
}

fn pair(
    site_b: Vector3<f64>,
    a: (Option<Vector3<f64>>, Option<Matrix3<f64>>),
    b: (Option<Vector3<f64>>, Option<Matrix3<f64>>),
) -> f64 {
    let rotor = |site, (d, q): (Option<Vector3<f64>>, Option<Matrix3<f64>>)| Rotor {
        site,
        inertia: Inertia::Spherical(1.0),
        dipole_body: d,
        quadrupole_body: q,
    };
    let rotors = [rotor(Vector3::zeros(), a), rotor(site_b, b)];
    MultipolePotential::new(&rotors, Boundary::Open, ExternalFields::NONE)
        .unwrap()
        .energy(&[Quat::IDENTITY; 2])
}

/// Two dipoles |mu| at distance r: head-to-tail -2 mu^2/r^3, side by side
/// parallel +mu^2/r^3, antiparallel -mu^2/r^3.
#[test]
fn dipole_pair_closed_forms() {
    let (mu, r) = (1.3, 1.7);
    let ez = Vector3::z() * mu;
    let head_to_tail = pair(
        Vector3::new(0.0, 0.0, r),
        (Some(ez), None),
        (Some(ez), None),
    );
    let side_by_side = pair(
        Vector3::new(r, 0.0, 0.0),
        (Some(ez), None),
        (Some(ez), None),
    );
    let antiparallel = pair(
        Vector3::new(r, 0.0, 0.0),
        (Some(ez), None),
        (Some(-ez), None),
    );
    let u = mu * mu / r.powi(3);
    for (got, want) in [
        (head_to_tail, -2.0 * u),
        (side_by_side, u),
        (antiparallel, -u),
    ] {
        assert!(
            (got - want).abs() < ROUND_OFF_TOLERANCE * u,
            "{got} vs {want}"
        );
    }
}

/// Two linear quadrupoles (Theta = Theta0 (3/2 e e^T - 1/2 I)) against
/// Buckingham's closed form
/// `3/4 Ta Tb / r^5 [1 - 5ca^2 - 5cb^2 - 15 ca^2 cb^2 + 2 (4 ca cb - sa sb cos phi)^2]`.
#[test]
fn linear_quadrupoles_match_buckingham_formula() {
    let mut r = rng(21);
    for _ in 0..20 {
        let (ta, tb, dist) = (
            1.0 + r.random_f(),
            -0.5 - r.random_f(),
            1.0 + 2.0 * r.random_f(),
        );
        let angles: [f64; 4] = std::array::from_fn(|_| 2.0 * std::f64::consts::PI * r.random_f());
        let axis = |theta: f64, phi: f64| {
            Vector3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        let (ea, eb) = (axis(angles[0], angles[1]), axis(angles[2], angles[3]));
        let linear =
            |t: f64, e: Vector3<f64>| (e * e.transpose() * 1.5 - Matrix3::identity() * 0.5) * t;
        let got = pair(
            Vector3::new(0.0, 0.0, dist),
            (None, Some(linear(ta, ea))),
            (None, Some(linear(tb, eb))),
        );
        let (ca, cb) = (ea.z, eb.z);
        let (sa, sb) = ((1.0 - ca * ca).sqrt(), (1.0 - cb * cb).sqrt());
        let cos_phi = if sa * sb > 0.0 {
            (ea.x * eb.x + ea.y * eb.y) / (sa * sb)
        } else {
            0.0
        };
        let want = 0.75 * ta * tb / dist.powi(5)
            * (1.0 - 5.0 * ca * ca - 5.0 * cb * cb - 15.0 * ca * ca * cb * cb
                + 2.0 * (4.0 * ca * cb - sa * sb * cos_phi).powi(2));
        assert!(
            (got - want).abs() < SUM_ROUND_OFF_TOLERANCE * want.abs().max(1e-3),
            "{got} vs {want}"
        );
    }
}

trait RandomF {
    fn random_f(&mut self) -> f64;
}
impl RandomF for rand_chacha::ChaCha8Rng {
    fn random_f(&mut self) -> f64 {
        rand::RngExt::random::<f64>(self)
    }
}

/// Point charges reproducing a dipole (+-q at +-d/2) and a Buckingham
/// quadrupole (triples q, -2q, q along each eigenvector: no dipole, no octupole).
fn charge_cluster(
    centre: Vector3<f64>,
    mu: Vector3<f64>,
    theta: Matrix3<f64>,
    d: f64,
) -> Vec<(f64, Vector3<f64>)> {
    let mut charges = Vec::new();
    if mu.norm() > 0.0 {
        let q = mu.norm() / d;
        let half = mu.normalize() * (0.5 * d);
        charges.extend([(q, centre + half), (-q, centre - half)]);
    }
    let eigen = SymmetricEigen::new(theta);
    for k in 0..3 {
        // q s^2 (3 e e^T - I) per triple, with q s^2 = lambda / 3.
        let e: Vector3<f64> = eigen.eigenvectors.column(k).into();
        let q = eigen.eigenvalues[k] / (3.0 * d * d);
        charges.extend([(q, centre + e * d), (q, centre - e * d), (-2.0 * q, centre)]);
    }
    charges
}

fn coulomb(a: &[(f64, Vector3<f64>)], b: &[(f64, Vector3<f64>)]) -> f64 {
    a.iter()
        .flat_map(|(qa, ra)| b.iter().map(move |(qb, rb)| qa * qb / (ra - rb).norm()))
        .sum()
}

/// Every pair term, at random orientations, equals the Coulomb energy of
/// point-charge clusters with the same multipoles (Richardson-extrapolated to
/// zero cluster size): an independent check of the interaction tensors and of
/// the Buckingham convention.
#[test]
fn pair_terms_match_point_charge_clusters() {
    let mut r = rng(31);
    for (da, qa, db, qb) in [
        (true, false, true, false),
        (true, false, false, true),
        (false, true, true, false),
        (false, true, false, true),
        (true, true, true, true),
    ] {
        let site_b = random_vector(&mut r, 1.0).normalize() * 2.0;
        let ra = random_rotor(&mut r, Vector3::zeros(), da, qa);
        let rb = random_rotor(&mut r, site_b, db, qb);
        let q = [random_orientation(&mut r), random_orientation(&mut r)];
        let v = MultipolePotential::new(
            &[ra.clone(), rb.clone()],
            Boundary::Open,
            ExternalFields::NONE,
        )
        .unwrap()
        .energy(&q);
        let space = |ro: &Rotor, qi: &Quat| {
            let rot = qi.body_to_space_matrix();
            (
                rot * ro.dipole_body.unwrap_or_default(),
                rot * ro.quadrupole_body.unwrap_or_default() * rot.transpose(),
            )
        };
        let ((mua, tha), (mub, thb)) = (space(&ra, &q[0]), space(&rb, &q[1]));
        let at = |d: f64| {
            coulomb(
                &charge_cluster(Vector3::zeros(), mua, tha, d),
                &charge_cluster(site_b, mub, thb, d),
            )
        };
        let d = 0.01;
        let extrapolated = (4.0 * at(d / 2.0) - at(d)) / 3.0;
        let err = (v - extrapolated).abs() / v.abs();
        assert!(
            err < CHARGE_CLUSTER_TOLERANCE,
            "({da},{qa},{db},{qb}): {v} vs charges {extrapolated} (rel {err:e})"
        );
    }
}

/// The Buckingham convention in a uniform field gradient: the energy of a
/// neutral charge cluster in `phi(r) = -E0.r - 1/2 r^T G r` (G traceless,
/// exact) equals `-mu.E0 - 1/3 Theta:G` with Theta = buckingham_quadrupole.
#[test]
fn field_gradient_energy_matches_point_charges() {
    let mut r = rng(41);
    let mut charges: Vec<(f64, Vector3<f64>)> = (0..5)
        .map(|_| (r.random_f() - 0.5, random_vector(&mut r, 0.5)))
        .collect();
    let net: f64 = charges.iter().map(|c| c.0).sum();
    charges.push((-net, random_vector(&mut r, 0.5)));
    let mu: Vector3<f64> = charges.iter().map(|(q, x)| x * *q).sum();
    let theta = buckingham_quadrupole(&charges);
    let e0 = random_vector(&mut r, 1.0);
    let g = random_quadrupole(&mut r, 1.0);
    let exact: f64 = charges
        .iter()
        .map(|(q, x)| q * (-e0.dot(x) - 0.5 * x.dot(&(g * x))))
        .sum();
    let rotor = Rotor {
        site: Vector3::zeros(),
        inertia: Inertia::Spherical(1.0),
        dipole_body: Some(mu),
        quadrupole_body: Some(theta),
    };
    let external = ExternalFields {
        field: Some(e0),
        field_gradient: Some(g),
    };
    let v = MultipolePotential::new(&[rotor], Boundary::Open, external)
        .unwrap()
        .energy(&[Quat::IDENTITY]);
    assert!(
        (v - exact).abs() < ROUND_OFF_TOLERANCE * exact.abs().max(1.0),
        "{v} vs {exact}"
    );
}

/// OpenMM's AmoebaMultipoleForce takes Theta/3; the two conversions invert each other.
#[test]
fn openmm_quadrupole_conversion_is_a_factor_three() {
    let theta = random_quadrupole(&mut rng(51), 1.0);
    assert_eq!(quadrupole_to_openmm(&theta) * 3.0, theta);
    assert!(
        (quadrupole_from_openmm(&quadrupole_to_openmm(&theta)) - theta)
            .abs()
            .max()
            < 1e-15
    );
}

/// The 10^3 periodic sc lattice with cutoff 3.1 has 61,000 pairs sharing
/// 122 geometries; as an open cluster, 499,500 pairs.
#[test]
fn periodic_lattice_pair_count() {
    let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 10, 1.0).unwrap();
    let rotors: Vec<_> = lattice
        .sites
        .iter()
        .map(|s| Rotor {
            site: *s,
            inertia: Inertia::Spherical(1.0),
            dipole_body: Some(Vector3::x()),
            quadrupole_body: None,
        })
        .collect();
    let p = MultipolePotential::new(
        &rotors,
        Boundary::periodic_cutoff(lattice.box_lengths, 3.1),
        ExternalFields::NONE,
    )
    .unwrap();
    assert_eq!(p.pair_count(), 61_000);
    assert_eq!(p.geometry_count(), 122);
    // An open cluster of the same sites: every pair once, n (n - 1) / 2.
    let open = MultipolePotential::new(&rotors, Boundary::Open, ExternalFields::NONE).unwrap();
    assert_eq!(open.pair_count(), 1000 * 999 / 2);
    assert_eq!(
        Lattice::cubic(LatticeKind::Bcc, 3, 1.0)
            .unwrap()
            .sites
            .len(),
        54
    );
    assert_eq!(
        Lattice::cubic(LatticeKind::Fcc, 3, 1.0)
            .unwrap()
            .sites
            .len(),
        108
    );
}

/// The energy of a perfect periodic lattice is the same seen from every site:
/// with all dipoles parallel, every rotor feels the same field (zero by cubic
/// symmetry on sc shells, so the scale is that of one pair, 1).
#[test]
fn periodic_lattice_fields_are_translation_invariant() {
    for kind in [LatticeKind::SimpleCubic, LatticeKind::Bcc, LatticeKind::Fcc] {
        let lattice = Lattice::cubic(kind, 4, 1.0).unwrap();
        let rotors: Vec<_> = lattice
            .sites
            .iter()
            .map(|s| Rotor {
                site: *s,
                inertia: Inertia::Spherical(1.0),
                dipole_body: Some(Vector3::new(0.3, -0.2, 0.9)),
                quadrupole_body: None,
            })
            .collect();
        let p = MultipolePotential::new(
            &rotors,
            Boundary::periodic_cutoff(lattice.box_lengths, 1.9),
            ExternalFields::NONE,
        )
        .unwrap();
        let q = vec![
            Quat::from_axis_angle(&Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)), 0.7);
            rotors.len()
        ];
        let g = gradient_of(&p, &q);
        for gi in &g {
            assert!(
                (*gi - g[0]).norm() < SUM_ROUND_OFF_TOLERANCE * g[0].norm().max(1.0),
                "{kind:?}"
            );
        }
    }
}

/// Bad inputs are refused with a message naming the input and the value.
#[test]
fn bad_inputs_name_the_problem() {
    let ok = Rotor {
        site: Vector3::zeros(),
        inertia: Inertia::Spherical(1.0),
        dipole_body: Some(Vector3::x()),
        quadrupole_body: None,
    };
    let far = Rotor {
        site: Vector3::new(1.0, 0.0, 0.0),
        ..ok.clone()
    };
    let err = |rotors: &[Rotor], b: Boundary, e: ExternalFields| {
        MultipolePotential::new(rotors, b, e)
            .unwrap_err()
            .to_string()
    };
    let periodic = |cutoff| Boundary::periodic_cutoff(Vector3::new(10.0, 8.0, 12.0), cutoff);
    // A cutoff beyond half the box is a lattice sum over images; one far
    // beyond it would hold too many pairs.
    assert!(MultipolePotential::new(
        &[ok.clone(), far.clone()],
        periodic(5.0),
        ExternalFields::NONE
    )
    .is_ok());
    let huge = err(
        &[ok.clone(), far.clone()],
        periodic(1e4),
        ExternalFields::NONE,
    );
    assert!(
        huge.starts_with("cutoff: 10000 gives about ")
            && huge.ends_with(" interacting pairs (periodic images included) for 2 rotors, more than the limit 100000000"),
        "{huge}"
    );
    assert_eq!(
        err(
            &[ok.clone(), ok.clone()],
            Boundary::Open,
            ExternalFields::NONE
        ),
        "rotors[0].site and rotors[1].site: coincide (distance 0e0, periodic images included)"
    );
    let traced = Rotor {
        quadrupole_body: Some(Matrix3::identity()),
        ..far.clone()
    };
    assert_eq!(
        err(&[ok.clone(), traced], Boundary::Open, ExternalFields::NONE),
        "rotors[1].quadrupole_body: must be traceless, got trace 3"
    );
    let asym = ExternalFields {
        field: None,
        field_gradient: Some(Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)),
    };
    assert!(err(&[ok.clone(), far.clone()], Boundary::Open, asym)
        .starts_with("field_gradient: must be symmetric"));
    assert_eq!(
        err(
            &[ok, far],
            Boundary::periodic_cutoff(Vector3::new(1.0, 0.0, 1.0), 0.1),
            ExternalFields::NONE
        ),
        "box_lengths[1]: must be > 0, got 0"
    );
}

/// `energy_and_gradient` (the one-pass form the benchmarks and library users
/// call) gives the energy of `energy` and adds the gradient of
/// `accumulate_gradient` into what the buffer holds: every multipole case
/// (its own implementation), free rotors and a potential that keeps the
/// trait's default (`V = sum_i q0_i^2 q1_i`, gradient `(2 q0 q1, q0^2, 0, 0)`).
#[test]
fn energy_and_gradient_equals_the_separate_evaluations() {
    struct Cubic;
    impl Potential for Cubic {
        fn energy(&self, q: &[Quat]) -> f64 {
            q.iter().map(|q| q.0[0] * q.0[0] * q.0[1]).sum()
        }
        fn accumulate_gradient(&self, q: &[Quat], g: &mut [Quat]) {
            for (q, g) in q.iter().zip(g) {
                *g += Quat::new(2.0 * q.0[0] * q.0[1], q.0[0] * q.0[0], 0.0, 0.0);
            }
        }
        fn accumulate_torques(&self, _: &[Quat], _: &mut [Vector3<f64>]) {}
    }
    let mut r = rng(91);
    let check = |name: &str, p: &dyn Potential, q: &[Quat], r: &mut rand_chacha::ChaCha8Rng| {
        let start: Vec<Quat> = q.iter().map(|_| random_orientation(r)).collect();
        let mut both = start.clone();
        let energy = p.energy_and_gradient(q, &mut both);
        let mut alone = vec![Quat::ZERO; q.len()];
        p.accumulate_gradient(q, &mut alone);
        let expected = p.energy(q);
        assert!(
            (energy - expected).abs() <= 1e-14 * expected.abs(),
            "{name}: energy {energy} vs {expected}"
        );
        let scale = alone.iter().map(|g| g.norm()).fold(1.0, f64::max);
        for (k, ((b, a), s)) in both.iter().zip(&alone).zip(&start).enumerate() {
            let d = (*b - (*a + *s)).norm();
            assert!(d <= 1e-14 * scale, "{name}: rotor {k}: gradient off by {d}");
        }
    };
    for case in all_cases() {
        check(case.name, &case.potential(), &case.orientations, &mut r);
    }
    let q: Vec<Quat> = (0..4).map(|_| random_orientation(&mut r)).collect();
    assert!(
        Cubic.energy(&q).abs() > 0.01,
        "a test potential with an energy"
    );
    check("trait default", &Cubic, &q, &mut r);
    check("free rotors", &quatrot::potential::Free, &q, &mut r);
}

/// Free rotors: no energy, nothing added to the gradient or the torques, and
/// never a torque (so every axis's spin is conserved).
#[test]
fn free_rotors_feel_nothing() {
    let mut r = rng(92);
    let q: Vec<Quat> = (0..3).map(|_| random_orientation(&mut r)).collect();
    let free = quatrot::potential::Free;
    assert_eq!(free.energy(&q), 0.0);
    let start = Quat::new(0.1, -0.2, 0.3, 0.4);
    let mut gradient = vec![start; 3];
    free.accumulate_gradient(&q, &mut gradient);
    assert_eq!(gradient, vec![start; 3]);
    let mut torques = vec![Vector3::new(1.0, 2.0, 3.0); 3];
    free.accumulate_torques(&q, &mut torques);
    assert_eq!(torques, vec![Vector3::new(1.0, 2.0, 3.0); 3]);
    assert_eq!(free.torque_axes(1), quatrot::potential::TorqueAxes::Never);
}
