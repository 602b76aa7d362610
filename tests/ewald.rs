//! The Ewald sums (direct and FFT lattice) against closed forms and against
//! each other: the Lorentz energy of aligned cubic dipole lattices, the
//! vacuum surface term, the FFT lattice sum against the direct sum (Ewald)
//! and against the pair kernel (truncated), the accuracy estimate against
//! the converged sum, and bad input. (Independence of the splitting
//! parameter: `src/potential/multipole/ewald.rs`; eq 13 = projected eq 14
//! and the gradient for the Ewald sums: `tests/multipoles.rs`.)

mod multipole_support;

use multipole_support::*;
use nalgebra::{Matrix3, Vector3};
use quatrot::internals::from_name;
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::multipole::MAX_FFT_BYTES;
use quatrot::potential::{
    Accuracy, Boundary, ExternalFields, MultipolePotential, PeriodicSum, Potential, SumMethod,
    SumPath, Surface,
};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// Lattice sums of ~1e3-1e4 terms whose absolute sum is ~20 times their
/// total (the shells of a cubic lattice cancel), each rounded to ~1e-16:
/// ~1e-14 measured; relative to the total.
const LATTICE_ROUND_OFF: f64 = 1e-13;
/// Two sums converged below round-off (accuracy 1e-15) by different paths
/// (FFT and direct, or FFT and pair list): round-off of each, relative to
/// the scale of the compared quantity.
const PATHS_ROUND_OFF: f64 = 1e-12;
/// The accuracy at which the closed forms and path comparisons run, so that
/// the truncation (< 1e-15 by the estimate) is below round-off.
const CONVERGED: f64 = 1e-15;

fn ewald(box_lengths: Vector3<f64>, accuracy: f64, surface: Surface) -> Boundary {
    Boundary::Periodic {
        box_lengths,
        sum: PeriodicSum::Ewald {
            accuracy: Accuracy::new(accuracy).expect("in (0, 1)"),
            surface,
        },
    }
}

fn dipole_rotor(site: Vector3<f64>, mu: Vector3<f64>) -> Rotor {
    Rotor {
        site,
        inertia: Inertia::Spherical(1.0),
        dipole_body: Some(mu),
        quadrupole_body: None,
    }
}

struct Evaluation {
    energy: f64,
    gradient: Vec<Quat>,
    torques: Vec<Vector3<f64>>,
}

fn evaluate(p: &MultipolePotential, q: &[Quat]) -> Evaluation {
    let mut gradient = vec![Quat::ZERO; q.len()];
    let mut torques = vec![Vector3::zeros(); q.len()];
    let energy = p.evaluate(q, Some(&mut gradient), Some(&mut torques));
    Evaluation {
        energy,
        gradient,
        torques,
    }
}

/// Largest difference of two evaluations relative to their scales: energy
/// relative to `energy_scale`, gradients and torques relative to their
/// largest entries.
fn difference(a: &Evaluation, b: &Evaluation, energy_scale: f64) -> [f64; 3] {
    let g_scale = b.gradient.iter().map(|g| g.norm()).fold(0.0, f64::max);
    let t_scale = b.torques.iter().map(|t| t.norm()).fold(0.0, f64::max);
    let g = a
        .gradient
        .iter()
        .zip(&b.gradient)
        .map(|(x, y)| (*x - *y).norm())
        .fold(0.0, f64::max);
    let t = a
        .torques
        .iter()
        .zip(&b.torques)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    [
        (a.energy - b.energy).abs() / energy_scale,
        g / g_scale,
        t / t_scale,
    ]
}

/// A simple-cubic lattice of `cells` (any three counts) with spacing `a`.
fn simple_cubic(cells: [usize; 3], a: f64) -> (Vec<Vector3<f64>>, Vector3<f64>) {
    let mut sites = Vec::new();
    for x in 0..cells[0] {
        for y in 0..cells[1] {
            for z in 0..cells[2] {
                sites.push(Vector3::new(x as f64, y as f64, z as f64) * a);
            }
        }
    }
    let box_lengths = Vector3::new(cells[0] as f64, cells[1] as f64, cells[2] as f64) * a;
    (sites, box_lengths)
}

/// The lattices of the closed-form tests: sc in a cubic and in an
/// orthorhombic box, bcc and fcc, various spacings.
/// A named set of sites in its box.
type Sites = (&'static str, Vec<Vector3<f64>>, Vector3<f64>);

fn cubic_lattices() -> Vec<Sites> {
    let (sc, sc_box) = simple_cubic([5, 5, 5], 1.0);
    let (slab, slab_box) = simple_cubic([6, 4, 3], 1.1);
    let bcc = Lattice::cubic(LatticeKind::Bcc, 3, 1.3).unwrap();
    let fcc = Lattice::cubic(LatticeKind::Fcc, 3, 1.6).unwrap();
    vec![
        ("sc 5^3", sc, sc_box),
        ("sc 6x4x3", slab, slab_box),
        ("bcc 3^3", bcc.sites, bcc.box_lengths),
        ("fcc 3^3", fcc.sites, fcc.box_lengths),
    ]
}

/// A fully aligned sc, bcc or fcc dipole lattice with a conducting surface
/// has the energy per dipole `-(2 pi / 3) n mu^2` (the Lorentz field
/// `4 pi P / 3`: the lattice sum over a sphere vanishes by cubic symmetry),
/// and in vacuum 0 (the depolarising field of the sphere cancels it); both
/// paths, any dipole direction.
#[test]
fn aligned_cubic_dipole_lattices_have_the_lorentz_energy() {
    let mu = Vector3::new(0.3, -0.5, 0.8);
    for (name, sites, box_lengths) in cubic_lattices() {
        let rotors: Vec<Rotor> = sites.iter().map(|s| dipole_rotor(*s, mu)).collect();
        let n = rotors.len() as f64;
        let density = n / box_lengths.product();
        let lorentz = -(2.0 * PI / 3.0) * density * mu.norm_squared();
        let q = vec![Quat::IDENTITY; rotors.len()];
        for (method, path) in [
            (SumMethod::Auto, SumPath::EwaldLatticeFft),
            (SumMethod::Direct, SumPath::EwaldDirect),
        ] {
            let conducting = MultipolePotential::with_method(
                &rotors,
                ewald(box_lengths, CONVERGED, Surface::Conducting),
                ExternalFields::NONE,
                method,
            )
            .unwrap();
            assert_eq!(conducting.sum_path(), path);
            let per_dipole = conducting.energy(&q) / n;
            let error = (per_dipole - lorentz).abs() / lorentz.abs();
            assert!(
                error < LATTICE_ROUND_OFF,
                "{name}, {path:?}: {per_dipole} vs {lorentz} ({error:e})"
            );
            let vacuum = MultipolePotential::with_method(
                &rotors,
                ewald(box_lengths, CONVERGED, Surface::Vacuum),
                ExternalFields::NONE,
                method,
            )
            .unwrap();
            let per_dipole = vacuum.energy(&q) / n;
            assert!(
                per_dipole.abs() < LATTICE_ROUND_OFF * lorentz.abs(),
                "{name}, {path:?}, vacuum: {per_dipole}"
            );
        }
    }
}

/// Vacuum minus conducting is `2 pi |M|^2 / (3 V)` for any orientations
/// (random dipoles, with quadrupoles too, which add nothing), and every
/// torque differs by `mu_i x (-4 pi M / (3 V))`; on a lattice (FFT) and on
/// irregular sites (direct).
#[test]
fn vacuum_minus_conducting_is_the_surface_term() {
    let mut r = rng(31);
    let fcc = Lattice::cubic(LatticeKind::Fcc, 2, 1.5).unwrap();
    let box_lengths = Vector3::new(3.0, 2.6, 3.3);
    let irregular: Vec<Vector3<f64>> = (0..20)
        .map(|_| {
            let u = random_vector(&mut r, 0.5) + Vector3::repeat(0.5);
            u.component_mul(&box_lengths)
        })
        .collect();
    for (name, sites, box_lengths, path) in [
        (
            "fcc lattice",
            fcc.sites.clone(),
            fcc.box_lengths,
            SumPath::EwaldLatticeFft,
        ),
        ("irregular", irregular, box_lengths, SumPath::EwaldDirect),
    ] {
        let rotors: Vec<Rotor> = sites
            .iter()
            .map(|s| random_rotor(&mut r, *s, true, true))
            .collect();
        let q: Vec<Quat> = rotors.iter().map(|_| random_orientation(&mut r)).collect();
        let build = |surface| {
            MultipolePotential::new(
                &rotors,
                ewald(box_lengths, CONVERGED, surface),
                ExternalFields::NONE,
            )
            .unwrap()
        };
        let (conducting, vacuum) = (build(Surface::Conducting), build(Surface::Vacuum));
        assert_eq!(conducting.sum_path(), path, "{name}");
        let (c, v) = (evaluate(&conducting, &q), evaluate(&vacuum, &q));
        let dipoles: Vec<Vector3<f64>> = rotors
            .iter()
            .zip(&q)
            .map(|(rotor, qi)| qi.body_to_space_matrix() * rotor.dipole_body.unwrap())
            .collect();
        let total: Vector3<f64> = dipoles.iter().sum();
        let volume = box_lengths.product();
        let surface = 2.0 * PI * total.norm_squared() / (3.0 * volume);
        let error = (v.energy - c.energy - surface).abs() / surface;
        assert!(
            error < LATTICE_ROUND_OFF * (c.energy.abs() / surface).max(1.0),
            "{name}: {} vs {surface} ({error:e})",
            v.energy - c.energy
        );
        let field = -total * (4.0 * PI / (3.0 * volume));
        let t_scale = c.torques.iter().map(|t| t.norm()).fold(0.0, f64::max);
        for ((tv, tc), mu) in v.torques.iter().zip(&c.torques).zip(&dipoles) {
            let expected = mu.cross(&field);
            assert!(
                (tv - tc - expected).norm() < PATHS_ROUND_OFF * t_scale,
                "{name}: torque difference {:?} vs {expected:?}",
                tv - tc
            );
        }
    }
}

/// The lattices of the path comparisons: random multipoles of every kind,
/// with vacancies, on sc, bcc and fcc, cells from 0.55 to 7.5 long.
fn lattice_systems() -> Vec<(&'static str, Vec<Rotor>, Vector3<f64>)> {
    let mut r = rng(41);
    let mut out = Vec::new();
    let fcc = Lattice::cubic(LatticeKind::Fcc, 2, 1.4).unwrap();
    out.push((
        "fcc, dipoles and quadrupoles",
        fcc.sites
            .iter()
            .map(|s| random_rotor(&mut r, *s, true, true))
            .collect(),
        fcc.box_lengths,
    ));
    let bcc = Lattice::cubic(LatticeKind::Bcc, 3, 1.2).unwrap();
    out.push((
        "bcc, quadrupoles",
        bcc.sites
            .iter()
            .map(|s| random_rotor(&mut r, *s, false, true))
            .collect(),
        bcc.box_lengths,
    ));
    // Cells longer than 2 pi: reciprocal steps 2 pi / c below 1.
    let (sc, sc_box) = simple_cubic([4, 5, 3], 7.5);
    let mixed = [(true, false), (false, true), (true, true)];
    out.push((
        "sc 4x5x3 of spacing 7.5, mixed multipoles, two vacancies",
        sc.iter()
            .enumerate()
            .filter(|(k, _)| *k != 7 && *k != 33)
            .map(|(k, s)| {
                let (d, q) = mixed[k % 3];
                random_rotor(&mut r, *s, d, q)
            })
            .collect(),
        sc_box,
    ));
    let (sc, sc_box) = simple_cubic([6, 6, 6], 1.0);
    out.push((
        "sc 6^3, dipoles",
        sc.iter()
            .map(|s| random_rotor(&mut r, *s, true, false))
            .collect(),
        sc_box,
    ));
    // Cells shorter than the length unit: a lattice sum that mixed up
    // lengths and inverse lengths (r / c against r c) would agree at 1.
    let small = Lattice::cubic(LatticeKind::Bcc, 3, 0.55).unwrap();
    out.push((
        "bcc 3^3 of spacing 0.55, dipoles and quadrupoles",
        small
            .sites
            .iter()
            .map(|s| random_rotor(&mut r, *s, true, true))
            .collect(),
        small.box_lengths,
    ));
    out
}

/// The FFT lattice sum equals the direct Ewald sum to round-off (energy,
/// eq 14 gradient, torques), both converged below round-off, in both
/// surfaces.
#[test]
fn lattice_fft_equals_the_direct_ewald_sum() {
    let mut r = rng(43);
    for (name, rotors, box_lengths) in lattice_systems() {
        let q: Vec<Quat> = rotors.iter().map(|_| random_orientation(&mut r)).collect();
        for surface in [Surface::Conducting, Surface::Vacuum] {
            let boundary = ewald(box_lengths, CONVERGED, surface);
            let fft = MultipolePotential::new(&rotors, boundary, ExternalFields::NONE).unwrap();
            assert_eq!(fft.sum_path(), SumPath::EwaldLatticeFft, "{name}");
            let direct = MultipolePotential::with_method(
                &rotors,
                boundary,
                ExternalFields::NONE,
                SumMethod::Direct,
            )
            .unwrap();
            let (a, b) = (evaluate(&fft, &q), evaluate(&direct, &q));
            let scale = energy_scale(&rotors, &q, box_lengths);
            let d = difference(&a, &b, scale);
            assert!(
                d.iter().all(|x| *x < PATHS_ROUND_OFF),
                "{name}, {surface:?}: energy, gradient, torque differences {d:?}"
            );
        }
    }
}

/// In cutoff mode the FFT lattice sum equals the pair kernel (the truncated
/// sum of earlier versions) to round-off, with a cutoff inside the box and
/// one beyond half of it.
#[test]
fn lattice_fft_equals_the_pair_kernel_with_a_cutoff() {
    let mut r = rng(47);
    let (sc, sc_box) = simple_cubic([10, 10, 10], 1.0);
    let lattice_dipoles: Vec<Rotor> = sc.iter().map(|s| dipole_rotor(*s, Vector3::z())).collect();
    let mut systems = vec![("sc 10^3 dipoles, cutoff 3.1", lattice_dipoles, sc_box, 3.1)];
    for (name, rotors, box_lengths) in lattice_systems() {
        systems.push((name, rotors, box_lengths, 0.8 * box_lengths.max()));
    }
    for (name, rotors, box_lengths, cutoff) in systems {
        let q: Vec<Quat> = rotors.iter().map(|_| random_orientation(&mut r)).collect();
        let boundary = Boundary::periodic_cutoff(box_lengths, cutoff);
        let pairs = MultipolePotential::new(&rotors, boundary, ExternalFields::NONE).unwrap();
        assert_eq!(pairs.sum_path(), SumPath::CutoffPairs);
        let fft = MultipolePotential::with_method(
            &rotors,
            boundary,
            ExternalFields::NONE,
            SumMethod::LatticeFft,
        )
        .unwrap();
        assert_eq!(fft.sum_path(), SumPath::CutoffLatticeFft);
        let (a, b) = (evaluate(&fft, &q), evaluate(&pairs, &q));
        let d = difference(&a, &b, energy_scale(&rotors, &q, box_lengths));
        assert!(
            d.iter().all(|x| *x < PATHS_ROUND_OFF),
            "{name}: energy, gradient, torque differences {d:?}"
        );
    }
}

/// The energy scale of the accuracy (see `ewald_parameters`):
/// `sum_i (|mu_i|^2 n + |Theta_i|^2 n^(5/3))`.
fn energy_scale(rotors: &[Rotor], q: &[Quat], box_lengths: Vector3<f64>) -> f64 {
    let n = rotors.len() as f64 / box_lengths.product();
    rotors
        .iter()
        .zip(q)
        .map(|(rotor, _)| {
            rotor.dipole_body.map_or(0.0, |m| m.norm_squared()) * n
                + rotor.quadrupole_body.map_or(0.0, |t| t.norm_squared()) * n.powf(5.0 / 3.0)
        })
        .sum()
}

/// `n` rotors at random sites of the box, carrying dipoles, quadrupoles or
/// both in turn.
fn irregular_mixed(r: &mut ChaCha8Rng, n: usize, box_lengths: Vector3<f64>) -> Vec<Rotor> {
    (0..n)
        .map(|k| {
            let site = (random_vector(r, 0.5) + Vector3::repeat(0.5)).component_mul(&box_lengths);
            random_rotor(r, site, k % 3 != 1, k % 3 != 0)
        })
        .collect()
}

/// The torque scale of the accuracy, `max |mu|^2 n + |Theta|^2 n^(5/3)` at
/// number density `n`.
fn torque_scale(rotors: &[Rotor], n: f64) -> f64 {
    rotors
        .iter()
        .map(|rotor| {
            rotor.dipole_body.map_or(0.0, |m| m.norm_squared()) * n
                + rotor.quadrupole_body.map_or(0.0, |t| t.norm_squared()) * n.powf(5.0 / 3.0)
        })
        .fold(0.0, f64::max)
}

/// The requested accuracy bounds the measured error against the converged
/// sum (energy relative to the energy scale, torques relative to the
/// torque scale `max |mu|^2 n + |Theta|^2 n^(5/3)`), from 1e-4 to 1e-12,
/// on both paths; the ratios measured/requested are printed (the estimates
/// are upper bounds, ~10-1000 times the measured errors).
#[test]
fn requested_accuracy_bounds_the_error_against_the_converged_sum() {
    let mut r = rng(53);
    let box_lengths = Vector3::new(4.2, 3.7, 4.6);
    let irregular = irregular_mixed(&mut r, 60, box_lengths);
    let mut systems = lattice_systems();
    systems.push(("60 irregular sites, mixed", irregular, box_lengths));
    let (sc, sc_box) = simple_cubic([6, 6, 6], 1.0);
    systems.push((
        "sc 6^3, aligned dipoles",
        sc.iter().map(|s| dipole_rotor(*s, Vector3::z())).collect(),
        sc_box,
    ));
    for (name, rotors, box_lengths) in systems {
        let q: Vec<Quat> = if name.contains("aligned") {
            vec![Quat::IDENTITY; rotors.len()]
        } else {
            rotors.iter().map(|_| random_orientation(&mut r)).collect()
        };
        let n = rotors.len() as f64 / box_lengths.product();
        let torque_scale = torque_scale(&rotors, n);
        let energy_scale = energy_scale(&rotors, &q, box_lengths);
        for method in [SumMethod::Auto, SumMethod::Direct] {
            let build = |accuracy| {
                MultipolePotential::with_method(
                    &rotors,
                    ewald(box_lengths, accuracy, Surface::Conducting),
                    ExternalFields::NONE,
                    method,
                )
                .unwrap()
            };
            let converged = evaluate(&build(CONVERGED), &q);
            for accuracy in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
                let p = build(accuracy);
                let e = evaluate(&p, &q);
                let energy_error = (e.energy - converged.energy).abs() / energy_scale;
                let torque_error = e
                    .torques
                    .iter()
                    .zip(&converged.torques)
                    .map(|(a, b)| (a - b).norm())
                    .fold(0.0, f64::max)
                    / torque_scale;
                println!(
                    "{name}, {:?}, accuracy {accuracy:e}: energy error {energy_error:.2e} \
                     ({:.2e} of requested), torque error {torque_error:.2e} ({:.2e})",
                    p.sum_path(),
                    energy_error / accuracy,
                    torque_error / accuracy
                );
                assert!(
                    energy_error <= accuracy && torque_error <= accuracy,
                    "{name}, {:?}, accuracy {accuracy:e}: energy {energy_error:e}, torque {torque_error:e}",
                    p.sum_path()
                );
            }
        }
    }
}

/// Bad input is refused with an error naming the field: an accuracy outside
/// (0, 1), a surface that is neither, an FFT lattice sum asked for sites
/// that are not a lattice or too large to fit in memory, coincident sites
/// on the FFT path.
#[test]
fn bad_ewald_input_names_the_field() {
    let (sites, box_lengths) = simple_cubic([3, 3, 3], 1.0);
    let rotors: Vec<Rotor> = sites
        .iter()
        .map(|s| dipole_rotor(*s, Vector3::z()))
        .collect();
    let build = |rotors: &[Rotor], boundary, method| {
        MultipolePotential::with_method(rotors, boundary, ExternalFields::NONE, method).unwrap_err()
    };
    for accuracy in [0.0, 1.0, -1e-3, 2.0, f64::NAN, f64::INFINITY] {
        let e = Accuracy::new(accuracy).unwrap_err();
        assert_eq!(e.path, "accuracy", "{e}");
        assert!(e.message.contains("must be in (0, 1)"), "{e}");
    }
    let e = from_name::<Surface>("surface", "metal").unwrap_err();
    assert_eq!(
        e.to_string(),
        "surface: must be \"conducting\" or \"vacuum\", got \"metal\""
    );
    assert_eq!(from_name("surface", "vacuum"), Ok(Surface::Vacuum));
    let e = from_name::<SumMethod>("method", "fast").unwrap_err();
    assert_eq!(
        e.to_string(),
        "method: must be \"auto\", \"direct\", \"lattice_fft\" or \"pme\", got \"fast\""
    );
    let e = build(
        &rotors,
        ewald(Vector3::new(3.0, -3.0, 3.0), 1e-6, Surface::Conducting),
        SumMethod::Auto,
    );
    assert_eq!(e.path, "box_lengths[1]", "{e}");
    let mut displaced = rotors.clone();
    displaced[4].site.x += 0.01;
    let e = build(
        &displaced,
        ewald(box_lengths, 1e-6, Surface::Conducting),
        SumMethod::LatticeFft,
    );
    assert_eq!(e.path, "method", "{e}");
    let e = build(&rotors, Boundary::Open, SumMethod::LatticeFft);
    assert_eq!(e.path, "method", "{e}");
    let mut doubled = rotors.clone();
    doubled[5].site = doubled[2].site + Vector3::new(0.0, 0.0, 3.0);
    let e = build(
        &doubled,
        ewald(box_lengths, 1e-6, Surface::Conducting),
        SumMethod::Auto,
    );
    assert_eq!(e.path, "rotors[2].site and rotors[5].site", "{e}");
    // 50^3 fcc cells with dipoles and quadrupoles: ~1.2 GB of kernel.
    let fcc = Lattice::cubic(LatticeKind::Fcc, 50, 1.0).unwrap();
    let theta = Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0));
    let big: Vec<Rotor> = fcc
        .sites
        .iter()
        .map(|s| Rotor {
            quadrupole_body: Some(theta),
            ..dipole_rotor(*s, Vector3::z())
        })
        .collect();
    let e = build(
        &big,
        ewald(fcc.box_lengths, 1e-6, Surface::Conducting),
        SumMethod::Auto,
    );
    assert_eq!(e.path, "rotors", "{e}");
    assert!(
        e.message
            .contains(&format!("{:.2} GB", MAX_FFT_BYTES as f64 / 1e9)),
        "{e}"
    );
}

/// The direct Ewald sum's real-space list holds every pair within the real
/// cutoff, periodic images and a site's own images included, each once: on
/// a simple-cubic lattice of spacing 1, `n N / 2` pairs with `N` the lattice
/// points within `r_c` of the origin (counted here, the origin left out).
#[test]
fn direct_ewald_real_space_pairs_are_the_lattice_points_within_the_cutoff() {
    let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 4, 1.0).unwrap();
    let rotors: Vec<Rotor> = lattice
        .sites
        .iter()
        .map(|s| dipole_rotor(*s, Vector3::z()))
        .collect();
    for accuracy in [1e-4, 1e-8] {
        let boundary = Boundary::Periodic {
            box_lengths: lattice.box_lengths,
            sum: PeriodicSum::Ewald {
                accuracy: Accuracy::new(accuracy).expect("in (0, 1)"),
                surface: Surface::Conducting,
            },
        };
        let p = MultipolePotential::with_method(
            &rotors,
            boundary,
            ExternalFields::NONE,
            SumMethod::Direct,
        )
        .unwrap();
        let rc = p.ewald_parameters().unwrap().real_cutoff;
        let reach = rc.ceil() as i32;
        let mut within = 0;
        for x in -reach..=reach {
            for y in -reach..=reach {
                for z in -reach..=reach {
                    let r2 = (x * x + y * y + z * z) as f64;
                    within += usize::from(r2 > 0.0 && r2 < rc * rc);
                }
            }
        }
        assert!(
            within > 6,
            "accuracy {accuracy}: r_c {rc} reaches past the neighbours"
        );
        assert_eq!(
            p.pair_count(),
            rotors.len() * within / 2,
            "accuracy {accuracy}, r_c {rc}"
        );
    }
}

/// `method = "pme"` through the rotor potential: at each requested
/// accuracy, on irregular sites with mixed multipoles and on the lattices,
/// the RMS torque error against the converged direct sum (relative to the
/// torque scale) and the energy error (relative to the energy scale) are
/// within the request (the mesh estimate is an RMS one: `estimate` in
/// `mesh_ewald`); the path and its parameters are reported.
#[test]
fn pme_reaches_the_requested_accuracy_against_the_converged_sum() {
    let mut r = rng(59);
    let box_lengths = Vector3::new(6.2, 5.7, 6.6);
    let irregular = irregular_mixed(&mut r, 120, box_lengths);
    let mut systems = lattice_systems();
    systems.push(("120 irregular sites, mixed", irregular, box_lengths));
    for (name, rotors, box_lengths) in systems {
        let q: Vec<Quat> = rotors.iter().map(|_| random_orientation(&mut r)).collect();
        let n = rotors.len() as f64 / box_lengths.product();
        let torque_scale = torque_scale(&rotors, n);
        let energy_scale = energy_scale(&rotors, &q, box_lengths);
        let build = |accuracy, method| {
            MultipolePotential::with_method(
                &rotors,
                ewald(box_lengths, accuracy, Surface::Conducting),
                ExternalFields::NONE,
                method,
            )
        };
        let converged = evaluate(&build(CONVERGED, SumMethod::Direct).unwrap(), &q);
        for accuracy in [1e-3, 1e-5, 1e-7] {
            let p = match build(accuracy, SumMethod::Pme) {
                Ok(p) => p,
                // A box too small for the real-space cutoff: refused by name.
                Err(e) => {
                    assert_eq!(e.path, "box_lengths", "{name}: {e}");
                    println!("{name}, accuracy {accuracy:e}: {e}");
                    continue;
                }
            };
            assert_eq!(p.sum_path(), SumPath::EwaldPme);
            let e = evaluate(&p, &q);
            let energy_error = (e.energy - converged.energy).abs() / energy_scale;
            let squares: f64 = e
                .torques
                .iter()
                .zip(&converged.torques)
                .map(|(a, b)| (a - b).norm_squared())
                .sum();
            let torque_error = (squares / q.len() as f64).sqrt() / torque_scale;
            println!(
                "{name}, PME, accuracy {accuracy:e}: energy error {energy_error:.2e} ({:.2e} of \
                 requested), RMS torque error {torque_error:.2e} ({:.2e}), {:?}",
                energy_error / accuracy,
                torque_error / accuracy,
                p.mesh_parameters()
            );
            assert!(
                energy_error <= accuracy && torque_error <= accuracy,
                "{name}, accuracy {accuracy:e}: energy {energy_error:e}, torque {torque_error:e}"
            );
        }
    }
}
