//! Moving bodies with the particle-mesh Ewald sum: forces and torques as
//! exact gradients (point quadrupoles at sites included), and energy
//! conservation of a short NVE run.

mod bodies_common;

use bodies_common::{bent_molecule, bodies, options};
use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    Body, BodyNoSquish, BodySystem, BodyType, BodyTypeSpec, ElectrostaticsOptions, Evaluation,
    EwaldOptions, InteractionOptions, LennardJones, Site, Space, Truncation,
};
use quatrot::integrators::NoSquishOptions;
use quatrot::potential::multipole::{SumMethod, Surface};
use quatrot::Quat;

/// A Lennard-Jones sphere with a dipole and a point quadrupole.
fn quadrupolar_sphere() -> BodyType {
    BodyType::new(&BodyTypeSpec {
        sites: vec![Site {
            lennard_jones: Some(LennardJones {
                epsilon: 1.0,
                sigma: 1.0,
            }),
            dipole: Some(Vector3::new(0.0, 0.4, 0.9)),
            quadrupole: Some(Matrix3::new(0.5, 0.2, 0.0, 0.2, -0.2, 0.1, 0.0, 0.1, -0.3)),
            ..Site::default()
        }],
        mass: Some(1.0),
        inertia: Some(Matrix3::new(0.1, 0.0, 0.0, 0.0, 0.12, 0.0, 0.0, 0.0, 0.08)),
    })
    .expect("a valid sphere")
}

/// 64 bodies, bent molecules and quadrupolar spheres, in a box of 6.4, PME
/// at `accuracy`.
fn system(accuracy: f64) -> BodySystem {
    let interactions = InteractionOptions {
        electrostatics: Some(ElectrostaticsOptions::Ewald(EwaldOptions {
            accuracy,
            method: SumMethod::Pme,
            surface: Surface::Conducting,
        })),
        ..options(Truncation::ForceShifted, 2.5, 2.5)
    };
    BodySystem::new(
        vec![bent_molecule(), quadrupolar_sphere()],
        bodies(64, 1.6, 5, 2),
        Space::Periodic(Vector3::repeat(6.4)),
        &interactions,
    )
    .expect("a valid system")
}

fn energy(system: &mut BodySystem) -> f64 {
    let mut e = Evaluation::default();
    system.evaluate(&mut e);
    e.potential_energy()
}

/// Every body's force and torque are minus the central differences of the
/// energy under a translation and a rotation of that body about each space
/// axis (PME at 1e-9: pairs crossing the real-space cutoff change the
/// energy by ~1e-9 of its scale, small against the step 1e-4; truncation
/// ~1e-8).
#[test]
fn pme_forces_and_torques_are_minus_the_energy_gradients() {
    const TOLERANCE: f64 = 1e-5;
    let mut system = system(1e-9);
    let mut e = Evaluation::default();
    system.evaluate(&mut e);
    let h = 1e-4;
    for i in [0, 1, 17, 42] {
        for a in 0..3 {
            let axis = Vector3::from_fn(|k, _| if k == a { 1.0 } else { 0.0 });
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
            let fd = slope(&mut system, &|b, s| b.position += axis * s);
            let scale = 1.0 + e.force[i].norm();
            assert!(
                (e.force[i][a] - fd).abs() < TOLERANCE * scale,
                "force {i} {a}: {} {fd}",
                e.force[i][a]
            );
            let fd = slope(&mut system, &|b, s| {
                b.orientation = Quat::exp(&(axis * s)) * b.orientation
            });
            let scale = 1.0 + e.torque[i].norm();
            assert!(
                (e.torque[i][a] - fd).abs() < TOLERANCE * scale,
                "torque {i} {a}: {} {fd}",
                e.torque[i][a]
            );
        }
    }
}

/// A short NVE run (NO_SQUISH, 200 steps of 0.001) with PME at 1e-8
/// conserves the total energy to 1e-5 of the kinetic energy (the
/// integrator's own drift at this step; the PME forces are exact
/// gradients, so the sum adds none beyond the cutoff crossings).
#[test]
fn an_nve_run_with_pme_conserves_energy() {
    let mut system = system(1e-8);
    let mut integrator = BodyNoSquish::new(&mut system, 0.001, NoSquishOptions::default()).unwrap();
    let total = |system: &BodySystem, integrator: &BodyNoSquish| {
        integrator.evaluation().potential_energy()
            + system.translational_kinetic_energy()
            + system.rotational_kinetic_energy()
    };
    let start = total(&system, &integrator);
    let kinetic = system.translational_kinetic_energy() + system.rotational_kinetic_energy();
    let mut worst: f64 = 0.0;
    for _ in 0..200 {
        integrator.step(&mut system);
        worst = worst.max((total(&system, &integrator) - start).abs());
    }
    assert!(worst < 1e-5 * kinetic, "drift {worst} of kinetic {kinetic}");
}
