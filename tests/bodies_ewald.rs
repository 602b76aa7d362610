//! Moving bodies with the particle-mesh Ewald sum: forces and torques as
//! exact gradients (point quadrupoles at sites included).

mod bodies_common;

use bodies_common::{assert_minus_gradients, bent_molecule, bodies, options};
use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    BodySystem, BodyType, BodyTypeSpec, ElectrostaticsOptions, EwaldOptions, InteractionOptions,
    LennardJones, Site, Space, Truncation,
};
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

/// Every body's force and torque are minus the central differences of the
/// energy under a translation and a rotation of that body about each space
/// axis (PME at 1e-7: pairs crossing the real-space cutoff change the
/// energy by ~1e-7 of its scale, none within the step 1e-4 here; truncation
/// ~1e-8).
#[test]
fn pme_forces_and_torques_are_minus_the_energy_gradients() {
    const TOLERANCE: f64 = 1e-5;
    assert_minus_gradients(&mut system(1e-7), &[0, 17], 1e-4, &|scale| {
        TOLERANCE * (1.0 + scale)
    });
}
