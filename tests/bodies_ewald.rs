//! Moving bodies with the Ewald sum, by particle-mesh Ewald and directly
//! over the wave vectors: forces and torques as exact gradients (point
//! quadrupoles at sites included), energy conserved in NVE with PME, the two
//! paths against each other, and `method = "auto"`'s choice between them.

mod bodies_common;

use bodies_common::{assert_minus_gradients, bent_molecule, bodies, options, stockmayer};
use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    direct_costs, BodyNoSquish, BodySystem, BodyType, BodyTypeSpec, ElectrostaticsOptions,
    Evaluation, EwaldOptions, InteractionOptions, LennardJones, Scope, Site, Space, Truncation,
};
use quatrot::integrators::NoSquishOptions;
use quatrot::potential::multipole::mesh_ewald::{Carried, ForcedMesh};
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

/// `n` bodies (64 in a box of 6.4), bent molecules and `sphere`s at
/// spacing 1.6, the Ewald sum by `method` at `accuracy`.
fn system_of(n: usize, sphere: BodyType, accuracy: f64, method: SumMethod) -> BodySystem {
    let interactions = InteractionOptions {
        electrostatics: Some(ElectrostaticsOptions::Ewald(EwaldOptions {
            accuracy,
            method,
            surface: Surface::Conducting,
            forced: ForcedMesh::default(),
        })),
        ..options(Truncation::ForceShifted, 2.5, 2.5)
    };
    let edge = 1.6 * (n as f64).cbrt().ceil();
    BodySystem::new(
        vec![bent_molecule(), sphere],
        bodies(n, 1.6, 5, 2),
        Space::Periodic(Vector3::repeat(edge)),
        &interactions,
    )
    .expect("a valid system")
}

/// The 64 bodies, bent molecules and `sphere`s, with PME at `accuracy`.
fn system(sphere: BodyType, accuracy: f64) -> BodySystem {
    system_of(64, sphere, accuracy, SumMethod::Pme)
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

/// The same with the direct sum over the wave vectors (at 1e-7 as well).
#[test]
fn direct_forces_and_torques_are_minus_the_energy_gradients() {
    const TOLERANCE: f64 = 1e-5;
    let mut direct = system_of(64, quadrupolar_sphere(), 1e-7, SumMethod::Direct);
    assert!(direct
        .electrostatic_sum()
        .and_then(|s| s.ewald_parameters())
        .is_some());
    assert_minus_gradients(&mut direct, &[0, 17], 1e-4, &|scale| {
        TOLERANCE * (1.0 + scale)
    });
}

/// The direct sum at 1e-10 and PME at 1e-10 (each converged to ~1e-10 of
/// the field scale by its estimate) give the same electrostatic energy,
/// site forces and body torques, within `AGREE` of their scales.
#[test]
fn direct_and_pme_agree_at_a_tight_accuracy() {
    /// Two sums each within ~1e-10 of the field scale, which is ~1e-1 of
    /// the forces' RMS here: 1e-8 leaves a margin of 10 over the estimates.
    const AGREE: f64 = 1e-8;
    let evaluate = |method| {
        let mut system = system_of(64, quadrupolar_sphere(), 1e-10, method);
        let mut e = Evaluation::default();
        system.evaluate(&mut e);
        e
    };
    let (direct, pme) = (evaluate(SumMethod::Direct), evaluate(SumMethod::Pme));
    let de = (direct.electrostatic - pme.electrostatic).abs() / pme.electrostatic.abs();
    let rms = |v: &[Vector3<f64>]| {
        (v.iter().map(|x| x.norm_squared()).sum::<f64>() / v.len() as f64).sqrt()
    };
    let differences = |a: &[Vector3<f64>], b: &[Vector3<f64>]| {
        let d: Vec<Vector3<f64>> = a.iter().zip(b).map(|(x, y)| x - y).collect();
        rms(&d) / rms(b)
    };
    let df = differences(&direct.site_force, &pme.site_force);
    let dt = differences(&direct.torque, &pme.torque);
    println!("energy {de:.2e}, site forces {df:.2e}, torques {dt:.2e}");
    assert!(
        de < AGREE && df < AGREE && dt < AGREE,
        "energy {de:e}, forces {df:e}, torques {dt:e}"
    );
}

/// `method = "auto"` takes the direct sum for 64 bodies and PME for 8,000
/// (their cost models, docs/scenes.md), recording both estimates; an
/// accuracy beyond PME's range takes the direct sum.
#[test]
fn auto_takes_the_direct_sum_for_small_systems_and_pme_for_large() {
    for (n, accuracy, direct) in [(64, 1e-5, true), (8000, 1e-5, false), (64, 1e-12, true)] {
        let system = system_of(n, quadrupolar_sphere(), accuracy, SumMethod::Auto);
        let sum = system.electrostatic_sum().expect("electrostatics");
        let choice = sum.auto_choice().expect("a choice");
        println!("{n} bodies at {accuracy:e}: {choice:?}");
        assert_eq!(sum.ewald_parameters().is_some(), direct, "{n}: {choice:?}");
        assert_eq!(sum.mesh_parameters().is_none(), direct, "{n}: {choice:?}");
        assert_eq!(choice.takes_pme(), !direct);
        assert_eq!(choice.pme_seconds.is_none(), accuracy < 1e-10);
    }
}

/// The bodies' direct sum prices a mixture as its dearest kind
/// (quadrupoles, then dipoles), whose pairs and wave vectors cost more.
#[test]
fn the_direct_sum_prices_a_mixture_as_its_dearest_kind() {
    let carried = |charges, dipoles, quadrupoles| Carried {
        charges,
        dipoles,
        quadrupoles,
    };
    let (c, d, q) = (
        direct_costs(carried(true, false, false)),
        direct_costs(carried(false, true, false)),
        direct_costs(carried(false, false, true)),
    );
    assert_eq!(direct_costs(carried(true, true, false)), d);
    assert_eq!(direct_costs(carried(true, true, true)), q);
    assert!(c.0 < d.0 && d.0 < q.0, "{c:?} {d:?} {q:?}");
    assert!(c.1 < d.1 && d.1 < q.1, "{c:?} {d:?} {q:?}");
}

/// A bent molecule of charges alone (no dipole): its mesh sum takes its
/// real-space pairs itself, and a forces-only evaluation leaves out its
/// virial.
fn charged_molecule() -> BodyType {
    let site = |p: [f64; 3], charge: f64, lj: bool| Site {
        position: Vector3::from(p),
        mass: 1.0,
        lennard_jones: lj.then_some(LennardJones {
            epsilon: 1.0,
            sigma: 1.0,
        }),
        charge,
        ..Site::default()
    };
    BodyType::new(&BodyTypeSpec {
        sites: vec![
            site([0.0, 0.0, 0.0], -0.8, true),
            site([0.33, 0.2, 0.0], 0.4, false),
            site([-0.33, 0.2, 0.0], 0.4, false),
        ],
        mass: None,
        inertia: None,
    })
    .expect("a valid molecule")
}

/// A forces-only evaluation (`Scope::Forces`, the steps a run does not
/// record) gives the site forces, body forces and torques of the full one
/// bit for bit, and NaN for the energies and the virial it leaves out: for
/// the cutoff sum in the pair pass (charges and dipoles), the cutoff sum
/// of quadrupoles (its own path), PME of charges alone (the mesh without
/// its virial) and PME of dipoles (the mesh without its virial, the
/// real-space pairs by the bodies' own sum).
#[test]
fn forces_only_evaluations_are_the_full_forces_bit_for_bit() {
    let cutoff = |sphere: BodyType| {
        BodySystem::new(
            vec![bent_molecule(), sphere],
            bodies(64, 1.6, 5, 2),
            Space::Periodic(Vector3::repeat(6.4)),
            &options(Truncation::Plain, 2.5, 2.5),
        )
        .expect("a valid system")
    };
    let interactions = InteractionOptions {
        electrostatics: Some(ElectrostaticsOptions::Ewald(EwaldOptions {
            accuracy: 1e-5,
            method: SumMethod::Pme,
            surface: Surface::Conducting,
            forced: ForcedMesh::default(),
        })),
        ..options(Truncation::ForceShifted, 2.5, 2.5)
    };
    let charges = BodySystem::new(
        vec![charged_molecule()],
        bodies(64, 1.6, 5, 1),
        Space::Periodic(Vector3::repeat(6.4)),
        &interactions,
    )
    .expect("a valid system");
    let cases = [
        ("cutoff, charges and dipoles", cutoff(stockmayer())),
        ("cutoff, quadrupoles", cutoff(quadrupolar_sphere())),
        ("PME, charges", charges),
        ("PME, dipoles", system(stockmayer(), 1e-5)),
    ];
    for (name, mut system) in cases {
        let (mut full, mut forces) = (Evaluation::default(), Evaluation::default());
        system.evaluate(&mut full);
        system.evaluate_in(&mut forces, Scope::Forces);
        let bits = |v: &[Vector3<f64>]| {
            v.iter()
                .flat_map(|x| x.iter().map(|c| c.to_bits()))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            bits(&full.site_force),
            bits(&forces.site_force),
            "{name}: site forces"
        );
        assert_eq!(bits(&full.force), bits(&forces.force), "{name}: forces");
        assert_eq!(bits(&full.torque), bits(&forces.torque), "{name}: torques");
        let parts = |e: &Evaluation| {
            [
                e.lennard_jones,
                e.lennard_jones_tail,
                e.electrostatic,
                e.pressure_tail,
            ]
        };
        assert!(
            full.virial
                .iter()
                .chain(&parts(&full))
                .all(|x| x.is_finite()),
            "{name}: {full:?}"
        );
        assert!(
            full.electrostatic != 0.0 && full.lennard_jones != 0.0,
            "{name}: both terms act"
        );
        assert!(
            forces
                .virial
                .iter()
                .chain(&parts(&forces))
                .all(|x| x.is_nan()),
            "{name}: {forces:?}"
        );
    }
}
