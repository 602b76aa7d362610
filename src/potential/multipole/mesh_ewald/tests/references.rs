//! The mesh Ewald sum against independent references.

use super::{fine, flat3, flat33, relative_rms, Configuration, FINE};
use crate::potential::multipole::mesh_ewald::{MeshEwald, MeshParameters, SiteResponse, Sources};
use crate::potential::multipole::Surface;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Dipoles, quadrupoles and their mixture against the direct Ewald sum
/// converged to round-off: energy, fields `E` and `W`, both surfaces.
#[test]
fn dipoles_and_quadrupoles_match_the_converged_direct_sum() {
    let box_lengths = Vector3::new(4.0, 3.6, 4.4);
    for (seed, kinds) in [
        (1, (false, true, false)),
        (2, (false, false, true)),
        (3, (false, true, true)),
    ] {
        let c = Configuration::random(seed, 40, box_lengths, kinds);
        for surface in [Surface::Conducting, Surface::Vacuum] {
            let (energy, e, w) = c.direct(surface);
            let out = c.mesh(fine(&box_lengths, 4.5), surface);
            let de = (out.energy - energy).abs() / energy.abs();
            assert!(
                de < FINE,
                "{kinds:?} {surface:?}: energy {} vs {energy}",
                out.energy
            );
            if kinds.1 {
                let r = relative_rms(&flat3(&out.field), &flat3(&e));
                assert!(r < FINE, "{kinds:?} {surface:?}: field {r:e}");
            }
            let r = relative_rms(&flat33(&out.quadrupole_conjugate), &flat33(&w));
            assert!(r < FINE, "{kinds:?} {surface:?}: W {r:e}");
        }
    }
}

/// At a fixed accuracy the result does not depend on the splitting: three
/// `alpha` (with `r_c` and the mesh scaled to keep the accuracy) agree with
/// the converged direct sum and so with each other.
#[test]
fn fixed_accuracy_results_do_not_depend_on_alpha() {
    let box_lengths = Vector3::repeat(4.2);
    let c = Configuration::random(4, 50, box_lengths, (false, true, true));
    let (energy, e, _) = c.direct(Surface::Conducting);
    for alpha_rc in [4.0, 4.5, 5.0] {
        let out = c.mesh(fine(&box_lengths, alpha_rc), Surface::Conducting);
        let de = (out.energy - energy).abs() / energy.abs();
        let r = relative_rms(&flat3(&out.field), &flat3(&e));
        assert!(
            de < FINE && r < FINE,
            "alpha r_c {alpha_rc}: energy {de:e}, field {r:e}"
        );
    }
}

/// The textbook Ewald sum of point charges (Allen & Tildesley, eq 6.4,
/// Gaussian units), written out here: `V = 1/2 sum_(i,j,n)' q_i q_j
/// erfc(alpha r)/r + (2 pi / V) sum_(k != 0) exp(-k^2 / 4 alpha^2) / k^2
/// |sum_j q_j exp(i k.r_j)|^2 - alpha / sqrt(pi) sum_j q_j^2`, with its
/// forces, converged far below round-off.
pub(crate) fn textbook_charges(c: &Configuration) -> (f64, Vec<Vector3<f64>>) {
    let q = c.charges.as_ref().unwrap();
    let n = q.len();
    let l = c.box_lengths;
    let alpha = 1.0;
    let (images, modes) = (3_i32, 12_i32);
    let mut energy = 0.0;
    let mut force = vec![Vector3::zeros(); n];
    for i in 0..n {
        for j in 0..n {
            for a in -images..=images {
                for b in -images..=images {
                    for d in -images..=images {
                        let shift = Vector3::new(a as f64 * l.x, b as f64 * l.y, d as f64 * l.z);
                        if i == j && (a, b, d) == (0, 0, 0) {
                            continue;
                        }
                        let r = c.positions[i] - c.positions[j] + shift;
                        let x = r.norm();
                        energy += 0.5 * q[i] * q[j] * libm::erfc(alpha * x) / x;
                        let dv = -q[i]
                            * q[j]
                            * (libm::erfc(alpha * x) / (x * x)
                                + 2.0 * alpha / PI.sqrt() * (-alpha * alpha * x * x).exp() / x);
                        force[i] -= r * (dv / x);
                    }
                }
            }
        }
    }
    let volume = l.product();
    for h in -modes..=modes {
        for k in -modes..=modes {
            for m in -modes..=modes {
                if (h, k, m) == (0, 0, 0) {
                    continue;
                }
                let index = [h, k, m];
                let kv = Vector3::from_fn(|a, _| 2.0 * PI * index[a] as f64 / l[a]);
                let k2 = kv.norm_squared();
                let weight = 4.0 * PI / volume * (-k2 / (4.0 * alpha * alpha)).exp() / k2;
                let (mut re, mut im) = (0.0, 0.0);
                for (q, r) in q.iter().zip(&c.positions) {
                    let phase = kv.dot(r);
                    re += q * phase.cos();
                    im += q * phase.sin();
                }
                energy += 0.5 * weight * (re * re + im * im);
                for i in 0..n {
                    let phase = kv.dot(&c.positions[i]);
                    // d/dr_i of |S|^2 = 2 q_i k (cos(k.r_i) Im S - sin(k.r_i) Re S)
                    let g = q[i] * (phase.cos() * im - phase.sin() * re);
                    force[i] -= kv * (weight * g);
                }
            }
        }
    }
    energy -= alpha / PI.sqrt() * q.iter().map(|q| q * q).sum::<f64>();
    (energy, force)
}

/// A neutral random configuration of charges against the textbook sum:
/// energy and forces.
#[test]
fn charges_match_the_textbook_ewald_sum() {
    let box_lengths = Vector3::new(3.0, 3.4, 2.8);
    let c = Configuration::random(5, 30, box_lengths, (true, false, false));
    let (energy, force) = textbook_charges(&c);
    let out = c.mesh(fine(&box_lengths, 4.5), Surface::Conducting);
    let de = (out.energy - energy).abs() / energy.abs();
    let r = relative_rms(&flat3(&out.force), &flat3(&force));
    assert!(
        de < FINE && r < FINE,
        "energy {} vs {energy} ({de:e}), force {r:e}",
        out.energy
    );
}

/// Madelung constants (Glasser & Zucker, "Lattice sums", Theoretical
/// Chemistry: Advances and Perspectives 5, 67 (1980), with the
/// nearest-neighbour distance `r_0` as unit): NaCl 1.747564594633182,
/// CsCl 1.762674773070988. The conventional cubic cells (8 and 2 ions) give
/// `V / (ion pairs) = -M / r_0`.
#[test]
fn rock_salt_and_caesium_chloride_reproduce_their_madelung_constants() {
    let a = 2.0;
    let box_lengths = Vector3::repeat(a);
    let parameters = fine(&box_lengths, 5.5);
    let nacl: Vec<(Vector3<f64>, f64)> = (0..8)
        .map(|k| {
            let n = [k & 1, (k >> 1) & 1, (k >> 2) & 1];
            let r = Vector3::from_fn(|i, _| n[i] as f64 * 0.5 * a);
            (
                r,
                if (n[0] + n[1] + n[2]) % 2 == 0 {
                    1.0
                } else {
                    -1.0
                },
            )
        })
        .collect();
    let cscl = vec![(Vector3::zeros(), 1.0), (Vector3::repeat(0.5 * a), -1.0)];
    for (ions, madelung, r0) in [
        (nacl, 1.747564594633182, 0.5 * a),
        (cscl, 1.762674773070988, 3f64.sqrt() * 0.5 * a),
    ] {
        let positions: Vec<Vector3<f64>> = ions.iter().map(|i| i.0).collect();
        let charges: Vec<f64> = ions.iter().map(|i| i.1).collect();
        let mut sum =
            MeshEwald::new(ions.len(), box_lengths, parameters, Surface::Conducting).unwrap();
        let mut out = SiteResponse::zeros(ions.len());
        let sources = Sources {
            positions: &positions,
            charges: Some(&charges),
            dipoles: None,
            quadrupoles: None,
        };
        sum.evaluate(&sources, &mut out).unwrap();
        let per_pair = out.energy / (ions.len() as f64 / 2.0);
        let expected = -madelung / r0;
        assert!(
            (per_pair - expected).abs() < 1e-9 * expected.abs(),
            "{per_pair} vs {expected}"
        );
        // Every ion sits at a centre of symmetry: no force.
        assert!(out.force.iter().all(|f| f.norm() < 1e-9), "{:?}", out.force);
    }
}

/// Aligned dipoles on a simple cubic lattice: the lattice sum of a sphere
/// vanishes by cubic symmetry, so the energy per dipole is 0 in vacuum and
/// `-(2 pi / 3) n mu^2` in conducting surroundings (`n` the density).
#[test]
fn aligned_cubic_dipole_lattice_has_its_closed_form_energy() {
    let (cells, spacing) = (4, 0.9);
    let side = cells as f64 * spacing;
    let positions: Vec<Vector3<f64>> = (0..cells * cells * cells)
        .map(|k| {
            Vector3::new(
                (k % cells) as f64,
                ((k / cells) % cells) as f64,
                (k / (cells * cells)) as f64,
            ) * spacing
        })
        .collect();
    let n = positions.len();
    let mu = Vector3::new(0.3, -0.5, 0.8);
    let dipoles = vec![mu; n];
    let sources = Sources {
        positions: &positions,
        charges: None,
        dipoles: Some(&dipoles),
        quadrupoles: None,
    };
    let density = n as f64 / side.powi(3);
    let box_lengths = Vector3::repeat(side);
    for (surface, expected) in [
        (Surface::Vacuum, 0.0),
        (
            Surface::Conducting,
            -2.0 * PI / 3.0 * density * mu.norm_squared(),
        ),
    ] {
        let mut sum = MeshEwald::new(n, box_lengths, fine(&box_lengths, 4.5), surface).unwrap();
        let mut out = SiteResponse::zeros(n);
        sum.evaluate(&sources, &mut out).unwrap();
        let per_dipole = out.energy / n as f64;
        assert!(
            (per_dipole - expected).abs() < FINE * mu.norm_squared() * density,
            "{surface:?}: {per_dipole} vs {expected}"
        );
    }
}

/// Vacuum minus conducting is `2 pi |M|^2 / (3 V)`, `M = sum (q_i r_i +
/// mu_i)` over the wrapped sites, for a mixture given outside the box
/// (every term but the surface is the same arithmetic: round-off).
#[test]
fn vacuum_minus_conducting_is_the_surface_term_of_the_wrapped_sites() {
    let box_lengths = Vector3::new(3.0, 3.2, 3.4);
    let mut c = Configuration::random(6, 20, box_lengths, (true, true, true));
    let wrapped: Vec<Vector3<f64>> = c.positions.clone();
    for (k, r) in c.positions.iter_mut().enumerate() {
        r[k % 3] += box_lengths[k % 3] * if k % 2 == 0 { 2.0 } else { -1.0 };
    }
    let parameters = fine(&box_lengths, 4.0);
    let vacuum = c.mesh(parameters, Surface::Vacuum);
    let conducting = c.mesh(parameters, Surface::Conducting);
    let q = c.charges.as_ref().unwrap();
    let m: Vector3<f64> = (0..20)
        .map(|i| wrapped[i] * q[i] + c.dipoles.as_ref().unwrap()[i])
        .sum();
    let expected = 2.0 * PI * m.norm_squared() / (3.0 * box_lengths.product());
    let got = vacuum.energy - conducting.energy;
    assert!(
        (got - expected).abs() < 1e-12 * expected,
        "{got} vs {expected}"
    );
}

/// The site forces are minus the gradient of the PME energy (mesh part
/// included): central differences of the energy of a mixture of charges,
/// dipoles and quadrupoles (step 1e-5; order 6 keeps the third derivatives
/// of the splines continuous), and of the converged direct energy for
/// dipoles and quadrupoles.
#[test]
fn forces_are_minus_the_gradient_of_the_energy() {
    let box_lengths = Vector3::new(3.0, 3.2, 3.4);
    let c = Configuration::random(7, 16, box_lengths, (true, true, true));
    let parameters = MeshParameters {
        order: 6,
        ..fine(&box_lengths, 4.0)
    };
    let out = c.mesh(parameters, Surface::Vacuum);
    let energy_at = |i: usize, a: usize, h: f64| {
        let mut moved = c.clone();
        moved.positions[i][a] += h;
        moved.mesh(parameters, Surface::Vacuum).energy
    };
    let h = 1e-5;
    let scale = out.force.iter().map(|f| f.amax()).fold(0.0, f64::max);
    for i in [0, 5, 11] {
        for a in 0..3 {
            let fd = -(energy_at(i, a, h) - energy_at(i, a, -h)) / (2.0 * h);
            assert!(
                (fd - out.force[i][a]).abs() < 1e-7 * scale,
                "site {i} axis {a}: {fd} vs {}",
                out.force[i][a]
            );
        }
    }
    // Against the converged direct sum, dipoles and quadrupoles.
    let c = Configuration::random(8, 16, box_lengths, (false, true, true));
    let out = c.mesh(fine(&box_lengths, 4.5), Surface::Conducting);
    let scale = out.force.iter().map(|f| f.amax()).fold(0.0, f64::max);
    for i in [2, 9] {
        for a in 0..3 {
            let direct_at = |h: f64| {
                let mut moved = c.clone();
                moved.positions[i][a] += h;
                moved.direct(Surface::Conducting).0
            };
            let fd = -(direct_at(h) - direct_at(-h)) / (2.0 * h);
            assert!(
                (fd - out.force[i][a]).abs() < 1e-5 * scale,
                "site {i} axis {a}: {fd} vs {}",
                out.force[i][a]
            );
        }
    }
}
