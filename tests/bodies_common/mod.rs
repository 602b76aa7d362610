//! Body systems shared by the body tests: a bent three-site molecule, a
//! Stockmayer sphere, jittered grids of them with random motion.
#![allow(dead_code)]

use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    Body, BodySystem, BodyType, BodyTypeSpec, ElectrostaticTruncation, ElectrostaticsOptions,
    InteractionOptions, LennardJones, LennardJonesOptions, Mixing, Site, Space, Truncation,
};
use quatrot::Quat;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A bent three-site molecule: LJ on every site, charges summing to zero,
/// a dipole off the centre.
pub fn bent_molecule() -> BodyType {
    let site = |p: [f64; 3], mass, sigma, charge, dipole: Option<[f64; 3]>| Site {
        position: Vector3::from(p),
        mass,
        lennard_jones: Some(LennardJones {
            epsilon: 1.0,
            sigma,
        }),
        charge,
        dipole: dipole.map(Vector3::from),
        quadrupole: None,
    };
    BodyType::new(&BodyTypeSpec {
        sites: vec![
            site([0.0, 0.0, 0.0], 2.0, 1.0, -0.8, Some([0.0, 0.3, 0.5])),
            site([0.5, 0.3, 0.0], 1.0, 0.8, 0.4, None),
            site([-0.4, 0.35, 0.1], 1.0, 0.8, 0.4, None),
        ],
        mass: None,
        inertia: None,
    })
    .expect("a valid molecule")
}

/// A dipolar LJ sphere (the Stockmayer particle).
pub fn stockmayer() -> BodyType {
    BodyType::new(&BodyTypeSpec {
        sites: vec![Site {
            lennard_jones: Some(LennardJones {
                epsilon: 1.0,
                sigma: 1.0,
            }),
            dipole: Some(Vector3::new(0.0, 0.0, 1.2)),
            ..Site::default()
        }],
        mass: Some(1.0),
        inertia: Some(Matrix3::identity() * 0.1),
    })
    .expect("a valid sphere")
}

/// `n` bodies of alternating types on a jittered cubic grid of spacing
/// `spacing`, random orientations, velocities and angular momenta.
pub fn bodies(n: usize, spacing: f64, seed: u64, types: usize) -> Vec<Body> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = (n as f64).cbrt().ceil() as usize;
    (0..n)
        .map(|i| {
            let grid = Vector3::new(i % side, (i / side) % side, i / (side * side));
            let jitter = Vector3::from_fn(|_, _| rng.random::<f64>() * 0.1);
            let q = Quat::new(
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5,
            );
            Body {
                kind: i % types,
                position: grid.map(|x| x as f64 + 0.5) * spacing + jitter,
                image: [0; 3],
                velocity: Vector3::from_fn(|_, _| rng.random::<f64>() - 0.5),
                orientation: q,
                angular_momentum_body: Vector3::from_fn(|_, _| 0.3 * (rng.random::<f64>() - 0.5)),
            }
        })
        .collect()
}

pub fn options(truncation: Truncation, lj_cutoff: f64, coulomb: f64) -> InteractionOptions {
    InteractionOptions {
        lennard_jones: Some(LennardJonesOptions {
            cutoff: lj_cutoff,
            truncation,
            mixing: Mixing::LorentzBerthelot,
        }),
        electrostatics: Some(ElectrostaticsOptions::Cutoff(
            coulomb,
            ElectrostaticTruncation::Plain,
        )),
        skin: 0.3,
    }
}

pub fn mixed_system(space: Space, truncation: Truncation, coulomb: f64, n: usize) -> BodySystem {
    let types = vec![bent_molecule(), stockmayer()];
    BodySystem::new(
        types,
        bodies(n, 1.6, 3, 2),
        space,
        &options(truncation, 2.5, coulomb),
    )
    .expect("a valid system")
}

/// 12 bodies (bent molecules and Stockmayer spheres) in open space with
/// every site pair within the cutoffs of 50, so the energy is analytic.
pub fn smooth_cluster() -> BodySystem {
    let types = vec![bent_molecule(), stockmayer()];
    let options = options(Truncation::ForceShifted, 50.0, 50.0);
    BodySystem::new(types, bodies(12, 1.6, 3, 2), Space::Open, &options).expect("a valid system")
}

/// The potential energy of the system's current state.
pub fn energy(system: &mut BodySystem) -> f64 {
    let mut e = quatrot::bodies::Evaluation::default();
    system.evaluate(&mut e);
    e.potential_energy()
}

/// Asserts that the force and torque of each body of `which` are minus the
/// central differences (step `h`) of the energy under a translation and a
/// rotation of that body about each space axis, within `tolerance(|F|)`
/// (`|tau|` for torques).
pub fn assert_minus_gradients(
    system: &mut BodySystem,
    which: &[usize],
    h: f64,
    tolerance: &dyn Fn(f64) -> f64,
) {
    let mut e = quatrot::bodies::Evaluation::default();
    system.evaluate(&mut e);
    for &i in which {
        for a in 0..3 {
            let axis = Vector3::from_fn(|k, _| if k == a { 1.0 } else { 0.0 });
            // Minus the central difference of the energy as body i is changed by `change`.
            let slope = |system: &mut BodySystem, change: &dyn Fn(&mut Body, f64)| {
                let saved = system.bodies[i].clone();
                let mut at = |s: f64| {
                    change(&mut system.bodies[i], s);
                    let u = energy(system);
                    system.bodies[i] = saved.clone();
                    u
                };
                -(at(h) - at(-h)) / (2.0 * h)
            };
            let fd = slope(system, &|b, s| b.position += axis * s);
            assert!(
                (e.force[i][a] - fd).abs() < tolerance(e.force[i].norm()),
                "force {i} {a}: {} {fd}",
                e.force[i][a]
            );
            let fd = slope(system, &|b, s| {
                b.orientation = Quat::exp(&(axis * s)) * b.orientation
            });
            assert!(
                (e.torque[i][a] - fd).abs() < tolerance(e.torque[i].norm()),
                "torque {i} {a}: {} {fd}",
                e.torque[i][a]
            );
        }
    }
}
