//! Moving bodies with the particle-mesh Ewald sum: forces and torques as
//! exact gradients (point quadrupoles at sites included), and energy
//! conserved in NVE.

mod bodies_common;

use bodies_common::{assert_minus_gradients, bent_molecule, bodies, options, stockmayer};
use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    BodyNoSquish, BodySystem, BodyType, BodyTypeSpec, ElectrostaticsOptions, Evaluation,
    EwaldOptions, InteractionOptions, LennardJones, Site, Space, Truncation,
};
use quatrot::integrators::NoSquishOptions;
use quatrot::potential::multipole::{SumMethod, Surface};

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

/// 64 bodies, bent molecules and `sphere`s, in a box of 6.4, PME at
/// `accuracy`.
fn system(sphere: BodyType, accuracy: f64) -> BodySystem {
    let interactions = InteractionOptions {
        electrostatics: Some(ElectrostaticsOptions::Ewald(EwaldOptions {
            accuracy,
            method: SumMethod::Pme,
            surface: Surface::Conducting,
        })),
        ..options(Truncation::ForceShifted, 2.5, 2.5)
    };
    BodySystem::new(
        vec![bent_molecule(), sphere],
        bodies(64, 1.6, 5, 2),
        Space::Periodic(Vector3::repeat(6.4)),
        &interactions,
    )
    .expect("a valid system")
}

/// Every body's force and torque are minus the central differences of the
/// energy under a translation and a rotation of that body about each space
/// axis (PME at 1e-7: pairs crossing the real-space cutoff change the
/// energy by ~1e-7 of its scale, none within the step 1e-4 here; truncation
/// ~1e-8).
#[test]
fn pme_forces_and_torques_are_minus_the_energy_gradients() {
    const TOLERANCE: f64 = 1e-5;
    assert_minus_gradients(
        &mut system(quadrupolar_sphere(), 1e-7),
        &[0, 17],
        1e-4,
        &|scale| TOLERANCE * (1.0 + scale),
    );
}

/// The largest `|E(t) - E(0)|` over `steps` NO_SQUISH steps of `dt`, for
/// bent molecules and Stockmayer spheres (charges and dipoles) with PME at
/// 1e-5 (the accuracy the wander was reported at).
fn nve_error(dt: f64, steps: usize) -> f64 {
    let mut system = system(stockmayer(), 1e-5);
    let mut integrator =
        BodyNoSquish::new(&mut system, dt, NoSquishOptions::default()).expect("a valid integrator");
    let energy = |system: &mut BodySystem| {
        let mut e = Evaluation::default();
        system.evaluate(&mut e);
        e.potential_energy()
            + system.translational_kinetic_energy()
            + system.rotational_kinetic_energy()
    };
    let start = energy(&mut system);
    let mut largest: f64 = 0.0;
    for _ in 0..steps {
        integrator.step(&mut system);
        largest = largest.max((energy(&mut system) - start).abs());
    }
    largest
}

/// NVE with PME for bodies conserves energy as a second-order splitting
/// with smooth forces does: over t = 1 (500 steps of 0.002, 1,000 of 0.001)
/// the largest error falls by 4 (order 2 within 0.3), so no part of it
/// stays as dt falls. A drift from pairs crossing the real-space cutoff, or
/// forces that are not the energy's gradient, would not fall with dt.
#[test]
fn pme_nve_energy_error_falls_as_dt_squared_without_drift() {
    let (coarse, fine) = (nve_error(0.002, 500), nve_error(0.001, 1000));
    let order = (coarse / fine).log2();
    assert!(
        (order - 2.0).abs() < 0.3,
        "errors {coarse:e} and {fine:e} over t = 1: order {order}"
    );
}
