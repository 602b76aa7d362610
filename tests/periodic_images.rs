//! The periodic lattice sum with every image inside the cutoff (cutoffs
//! beyond half the box), checked against references that do not use it: the
//! same system replicated into a supercell where each pair has one image, a
//! direct sum over explicit lattice vectors for a lone rotor, and pair counts
//! against lattice vectors counted in the cutoff sphere.

mod multipole_support;

use multipole_support::*;
use nalgebra::Vector3;
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use quatrot::rotor::Rotor;
use quatrot::Quat;

/// The same pair terms summed in another order and grouping (~120 terms of
/// order 1 per rotor; ~100 ulp), relative to the scale of the sum.
const SUM_ORDER_TOLERANCE: f64 = 1e-12;
/// Central differences with h = 1e-6: truncation ~h^2 V''' and round-off ~eps V / h, both < 1e-8.
const FD_TOLERANCE: f64 = 1e-7;
/// Step of the central differences (quaternion components and rotation angles).
const FD_STEP: f64 = 1e-6;
/// The cutoff of the built-in lattice scenes (spacing 1).
const CUTOFF: f64 = 3.1;

fn periodic(box_lengths: Vector3<f64>, cutoff: f64) -> Boundary {
    Boundary::periodic_cutoff(box_lengths, cutoff)
}

struct Evaluation {
    energy: f64,
    gradient: Vec<Quat>,
    torques: Vec<Vector3<f64>>,
}

fn evaluate(rotors: &[Rotor], boundary: Boundary, q: &[Quat]) -> Evaluation {
    let p = MultipolePotential::new(rotors, boundary, ExternalFields::NONE).unwrap();
    let mut gradient = vec![Quat::ZERO; q.len()];
    let mut torques = vec![Vector3::zeros(); q.len()];
    let energy = p.evaluate(q, Some(&mut gradient), Some(&mut torques));
    Evaluation {
        energy,
        gradient,
        torques,
    }
}

/// A small periodic cell whose cutoff exceeds half its box.
struct Cell {
    name: &'static str,
    rotors: Vec<Rotor>,
    box_lengths: Vector3<f64>,
    orientations: Vec<Quat>,
}

fn cells() -> Vec<Cell> {
    let mut r = rng(21);
    let mut out = Vec::new();
    for (cells, kinds) in [
        (2, [(true, false)].as_slice()),
        (2, &[(false, true)]),
        (3, &[(true, true)]),
        (2, &[(true, false), (false, true), (true, true)]),
    ] {
        let lattice = Lattice::cubic(LatticeKind::SimpleCubic, cells, 1.0).unwrap();
        let rotors: Vec<_> = lattice
            .sites
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let (d, q) = kinds[k % kinds.len()];
                random_rotor(&mut r, *s, d, q)
            })
            .collect();
        out.push(Cell {
            name: match kinds.len() {
                3 => "sc, mixed dipoles and quadrupoles",
                _ if kinds[0] == (true, false) => "sc, dipoles",
                _ if kinds[0] == (false, true) => "sc, quadrupoles",
                _ => "sc, dipoles and quadrupoles",
            },
            orientations: rotors.iter().map(|_| random_orientation(&mut r)).collect(),
            rotors,
            box_lengths: lattice.box_lengths,
        });
    }
    // A general set: five scattered sites in an orthorhombic box, each rotor
    // with its own asymmetric multipoles.
    let box_lengths = Vector3::new(1.7, 2.1, 1.3);
    let rotors: Vec<_> = [
        (true, true),
        (true, false),
        (false, true),
        (true, true),
        (true, true),
    ]
    .iter()
    .enumerate()
    .map(|(k, &(d, q))| {
        let site = Vector3::new(
            (0.31 + 0.6180339887 * k as f64).fract() * box_lengths.x,
            (0.17 + 0.4142135623 * k as f64).fract() * box_lengths.y,
            (0.53 + 0.7320508075 * k as f64).fract() * box_lengths.z,
        );
        random_rotor(&mut r, site, d, q)
    })
    .collect();
    out.push(Cell {
        name: "orthorhombic, scattered general multipoles",
        orientations: rotors.iter().map(|_| random_orientation(&mut r)).collect(),
        rotors,
        box_lengths,
    });
    out
}

/// The cell replicated `k` times along each axis, orientations copied: copy
/// `c` of rotor `i` is at index `c * n + i`.
fn supercell(cell: &Cell, k: [usize; 3]) -> (Vec<Rotor>, Vec<Quat>, Vector3<f64>) {
    let mut rotors = Vec::new();
    let mut orientations = Vec::new();
    for x in 0..k[0] {
        for y in 0..k[1] {
            for z in 0..k[2] {
                let shift =
                    Vector3::new(x as f64, y as f64, z as f64).component_mul(&cell.box_lengths);
                for (rotor, q) in cell.rotors.iter().zip(&cell.orientations) {
                    rotors.push(Rotor {
                        site: rotor.site + shift,
                        ..rotor.clone()
                    });
                    orientations.push(*q);
                }
            }
        }
    }
    let lengths =
        cell.box_lengths
            .component_mul(&Vector3::new(k[0] as f64, k[1] as f64, k[2] as f64));
    (rotors, orientations, lengths)
}

/// A cell with `cutoff > L/2` against the same system replicated into a
/// supercell with every edge above 2 cutoff (each pair then has a single
/// image in the cutoff, as in a minimum-image sum): equal energy per rotor,
/// and every copy's torque and eq 14 gradient equal to the original rotor's
/// in the cell. (The supercell energy is `k^3` times the cell's as a function
/// of one shared orientation per rotor, and by symmetry each of the `k^3`
/// copies carries an equal share of its derivative: one cell's worth.)
#[test]
fn small_cell_matches_minimum_image_supercell() {
    for cell in cells() {
        assert!(CUTOFF > 0.5 * cell.box_lengths.min(), "{}", cell.name);
        let small = evaluate(
            &cell.rotors,
            periodic(cell.box_lengths, CUTOFF),
            &cell.orientations,
        );
        let k = [0, 1, 2].map(|a| (2.0 * CUTOFF / cell.box_lengths[a]).floor() as usize + 1);
        let (rotors, orientations, lengths) = supercell(&cell, k);
        assert!(lengths.min() > 2.0 * CUTOFF);
        let big = evaluate(&rotors, periodic(lengths, CUTOFF), &orientations);
        let n = cell.rotors.len();
        let copies = (rotors.len() / n) as f64;
        // Order-1 multipoles at distances ~1: a pair term is of order 1.
        let energy_scale = small.energy.abs().max(n as f64);
        assert!(
            (big.energy / copies - small.energy).abs() < SUM_ORDER_TOLERANCE * energy_scale,
            "{}: {} vs {}",
            cell.name,
            big.energy / copies,
            small.energy
        );
        let torque_scale = small.torques.iter().map(|t| t.norm()).fold(1.0, f64::max);
        let gradient_scale = small.gradient.iter().map(|g| g.norm()).fold(1.0, f64::max);
        for (index, (t, g)) in big.torques.iter().zip(&big.gradient).enumerate() {
            let i = index % n;
            assert!(
                (t - small.torques[i]).norm() < SUM_ORDER_TOLERANCE * torque_scale,
                "{}: torque of copy {index} of rotor {i}",
                cell.name
            );
            assert!(
                (*g - small.gradient[i]).norm() < SUM_ORDER_TOLERANCE * gradient_scale,
                "{}: gradient of copy {index} of rotor {i}",
                cell.name
            );
        }
    }
}

/// A lone rotor in a periodic box interacts only with its own images:
/// `V = 1/2 sum_{n != 0, |n L| <= cutoff} v(n L)`, summed here over explicit
/// lattice vectors with the open two-rotor potential for `v`. Its eq 14
/// gradient and its torque match central differences of that direct sum.
#[test]
fn lone_rotor_matches_direct_image_sum() {
    let mut r = rng(5);
    let box_lengths = Vector3::new(1.0, 1.2, 0.9);
    let rotor = random_rotor(&mut r, Vector3::new(0.3, 0.2, 0.1), true, true);
    let q = random_orientation(&mut r);
    let lattice_vectors: Vec<Vector3<f64>> = {
        let m = [0, 1, 2].map(|a| (CUTOFF / box_lengths[a]).ceil() as i64);
        let mut v = Vec::new();
        for x in -m[0]..=m[0] {
            for y in -m[1]..=m[1] {
                for z in -m[2]..=m[2] {
                    let shift =
                        Vector3::new(x as f64, y as f64, z as f64).component_mul(&box_lengths);
                    if (x, y, z) != (0, 0, 0) && shift.norm() <= CUTOFF {
                        v.push(shift);
                    }
                }
            }
        }
        v
    };
    assert!(lattice_vectors.len() > 100);
    let image_pairs: Vec<MultipolePotential> = lattice_vectors
        .iter()
        .map(|shift| {
            let image = Rotor {
                site: rotor.site + shift,
                ..rotor.clone()
            };
            MultipolePotential::new(
                &[rotor.clone(), image],
                Boundary::Open,
                ExternalFields::NONE,
            )
            .unwrap()
        })
        .collect();
    let direct = |q: Quat| 0.5 * image_pairs.iter().map(|p| p.energy(&[q, q])).sum::<f64>();
    let lone = evaluate(
        std::slice::from_ref(&rotor),
        periodic(box_lengths, CUTOFF),
        &[q],
    );
    let scale = image_pairs
        .iter()
        .map(|p| p.energy(&[q, q]).abs())
        .sum::<f64>();
    assert!(
        (lone.energy - direct(q)).abs() < SUM_ORDER_TOLERANCE * scale,
        "{} vs {}",
        lone.energy,
        direct(q)
    );
    let gradient_scale = lone.gradient[0].norm().max(1.0);
    for k in 0..4 {
        let mut step = Quat::ZERO;
        step.0[k] = FD_STEP;
        let fd = (direct(q + step) - direct(q - step)) / (2.0 * FD_STEP);
        assert!(
            (fd - lone.gradient[0].0[k]).abs() < FD_TOLERANCE * gradient_scale,
            "dV/dq_{k}: {fd} vs {}",
            lone.gradient[0].0[k]
        );
    }
    let torque_scale = lone.torques[0].norm().max(1.0);
    for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
        let turned = |eps: f64| direct(Quat::exp(&(axis * eps)) * q);
        let fd = (turned(FD_STEP) - turned(-FD_STEP)) / (2.0 * FD_STEP);
        assert!(
            (fd + lone.torques[0].dot(&axis)).abs() < FD_TOLERANCE * torque_scale,
            "torque along {axis:?}: -dV {fd} vs {}",
            lone.torques[0].dot(&axis)
        );
    }
}

/// The nonzero vectors of a cubic Bravais lattice (constant `a`) within
/// `cutoff`, counted over `a/2` times integer triples: sc takes even
/// triples, bcc all-even or all-odd ones, fcc those with an even sum.
fn lattice_vectors_in_sphere(kind: LatticeKind, a: f64, cutoff: f64) -> usize {
    let m = (2.0 * cutoff / a).ceil() as i64;
    let mut count = 0;
    for x in -m..=m {
        for y in -m..=m {
            for z in -m..=m {
                let member = match kind {
                    LatticeKind::SimpleCubic => x % 2 == 0 && y % 2 == 0 && z % 2 == 0,
                    LatticeKind::Bcc => (x - y) % 2 == 0 && (y - z) % 2 == 0,
                    LatticeKind::Fcc => (x + y + z) % 2 == 0,
                };
                let r = 0.5 * a * ((x * x + y * y + z * z) as f64).sqrt();
                if member && (x, y, z) != (0, 0, 0) && r <= cutoff {
                    count += 1;
                }
            }
        }
    }
    count
}

/// On a Bravais lattice every site sees the same neighbours, so a periodic
/// box of `N` sites holds `N c / 2` pairs, `c` the lattice vectors in the
/// cutoff sphere (each pair seen from both ends; a self pair `±n` from both
/// signs), whether the box is larger or smaller than the cutoff.
#[test]
fn pair_count_is_half_the_lattice_vectors_per_site() {
    for (kind, cells, cutoff) in [
        (LatticeKind::SimpleCubic, 1, CUTOFF),
        (LatticeKind::SimpleCubic, 2, CUTOFF),
        (LatticeKind::SimpleCubic, 3, CUTOFF),
        (LatticeKind::SimpleCubic, 10, CUTOFF),
        (LatticeKind::Bcc, 2, 2.5),
        (LatticeKind::Fcc, 1, 2.2),
        (LatticeKind::Fcc, 3, 1.6),
    ] {
        let lattice = Lattice::cubic(kind, cells, 1.0).unwrap();
        let mut r = rng(3);
        let rotors: Vec<_> = lattice
            .sites
            .iter()
            .map(|s| random_rotor(&mut r, *s, true, false))
            .collect();
        let p = MultipolePotential::new(
            &rotors,
            periodic(lattice.box_lengths, cutoff),
            ExternalFields::NONE,
        )
        .unwrap();
        let c = lattice_vectors_in_sphere(kind, 1.0, cutoff);
        assert_eq!(
            2 * p.pair_count(),
            rotors.len() * c,
            "{kind:?}, {cells} cells, cutoff {cutoff}"
        );
    }
}

/// A scene whose cutoff exceeds half its lattice box is accepted, and its
/// potential sums the whole cutoff sphere: the built-in
/// `dipole_lattice_sc_cutoff` (cutoff 3.1) at 2^3 cells has as many pairs
/// per rotor as a large lattice.
#[test]
fn scene_accepts_a_cutoff_beyond_half_the_box() {
    let text = quatrot::scene::builtin("dipole_lattice_sc_cutoff")
        .expect("built-in")
        .toml
        .replace("cells = 10", "cells = 2");
    let (_, scene) = quatrot::scene::load_text(&text, &Default::default()).unwrap();
    let p = quatrot::run::potential(&scene).unwrap().unwrap();
    let c = lattice_vectors_in_sphere(LatticeKind::SimpleCubic, 1.0, CUTOFF);
    assert_eq!(2 * p.pair_count(), 8 * c);
}
