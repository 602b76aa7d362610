//! Every integrator's step gives bit-for-bit the same state on a 1-thread and
//! on a 2-thread rayon pool: its per-rotor passes run over fixed chunks of
//! rotors, each rotor reading and writing only its own entries. Checked on
//! the 1000-rotor dipole lattice (four chunks of rotors), with spherical tops
//! and with asymmetric tops (the two monomorphised paths of the Gear
//! schemes), for scheme A with and without renormalisation, scheme B with
//! each correction switch on its own, all of them and none, and the
//! kick-based baselines.
//!
//! The periodic pair loop sums its per-thread blocks in an order that depends
//! on the thread count, so the lattice potential is evaluated on a 1-thread
//! pool of its own ([`OnOneThread`]): what is compared is the integrators'
//! work alone.

use nalgebra::Vector3;
use quatrot::integrators::{
    Dlm, DlmOptions, FirstCorrector, GearA, GearAOptions, GearB, GearBOptions, Integrator,
    NoSquish, Richardson, SphericalTops, Startup,
};
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use quatrot::rotor::Inertia;
use quatrot::scene::{load, Overrides, Scene};
use quatrot::Quat;

/// Steps per run: enough for every pass to act on values set by the others.
const STEPS: usize = 20;

/// A potential evaluated on a 1-thread rayon pool of its own, whatever pool
/// the caller runs on.
struct OnOneThread<P> {
    potential: P,
    pool: rayon::ThreadPool,
}

impl<P: Potential> Potential for OnOneThread<P> {
    fn energy(&self, orientations: &[Quat]) -> f64 {
        self.pool.install(|| self.potential.energy(orientations))
    }

    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) {
        self.pool
            .install(|| self.potential.accumulate_gradient(orientations, gradient));
    }

    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]) {
        self.pool.install(|| {
            self.potential
                .accumulate_torques(orientations, torques_space)
        });
    }
}

/// A rayon pool of `threads` threads.
fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a rayon pool")
}

/// The built-in 1000-rotor dipole lattice, its rotors spherical tops as in
/// the scene or, with `asymmetric`, all of them asymmetric.
fn lattice(asymmetric: bool) -> (Scene, OnOneThread<MultipolePotential>) {
    let (_, mut scene) = load("dipole_lattice_sc", &Overrides::default()).expect("built-in");
    if asymmetric {
        for rotor in &mut scene.rotors {
            rotor.inertia = Inertia::Principal(Vector3::new(0.08, 0.1, 0.13));
        }
    }
    let periodic = Boundary::periodic_cutoff(scene.box_lengths().expect("periodic scene"), 3.1);
    let potential = MultipolePotential::new(&scene.rotors, periodic, ExternalFields::NONE)
        .expect("valid lattice");
    (
        scene,
        OnOneThread {
            potential,
            pool: pool(1),
        },
    )
}

/// The complete state (the checkpoint, orientations included) after `STEPS`
/// steps of a copy of the set-up `integrator` on a pool of `threads`.
fn state_after<I: Integrator + Clone + Send>(
    integrator: &I,
    potential: &OnOneThread<MultipolePotential>,
    threads: usize,
) -> Vec<u64> {
    let mut integrator = integrator.clone();
    pool(threads).install(|| {
        for _ in 0..STEPS {
            integrator.step(potential);
        }
    });
    let orientations = integrator
        .orientations()
        .iter()
        .flat_map(|q| q.0.iter().map(|x| x.to_bits()));
    let state = integrator.checkpoint().into_iter().map(f64::to_bits);
    orientations.chain(state).collect()
}

/// Sets `integrator` up on both lattices and asserts that 1 and 2 threads
/// give identical bits.
fn assert_thread_count_independent<I: Integrator + Clone + Send>(label: &str, integrator: I) {
    for asymmetric in [false, true] {
        let (scene, potential) = lattice(asymmetric);
        let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
        let mut integrator = integrator.clone();
        integrator
            .setup(&inertia, &potential, &scene.initial, scene.dt)
            .expect("valid setup");
        let one = state_after(&integrator, &potential, 1);
        let two = state_after(&integrator, &potential, 2);
        assert_eq!(one.len(), two.len());
        let differing = one.iter().zip(&two).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing, 0,
            "{label}, asymmetric tops {asymmetric}: {differing} values differ"
        );
    }
}

/// Scheme A, renormalised or not. The zero start-up keeps the set-up cheap
/// (the start-up is not what is compared).
#[test]
fn gear_a_is_bitwise_independent_of_the_thread_count() {
    for renormalise in [true, false] {
        let options = GearAOptions {
            renormalise,
            startup: Startup::Zeros,
        };
        assert_thread_count_independent(&format!("{options:?}"), GearA::new(options));
    }
}

/// Scheme B with no correction, each correction switch on its own, all of
/// them, and the default set with the other first corrector coefficient.
#[test]
fn gear_b_is_bitwise_independent_of_the_thread_count() {
    let none = GearBOptions {
        c0: FirstCorrector::VelocityDependent,
        project_torque: false,
        project_velocity: false,
        renormalise: false,
        correct_higher_derivatives: false,
        startup: Startup::Zeros,
    };
    let variants = [
        none,
        GearBOptions {
            project_torque: true,
            ..none
        },
        GearBOptions {
            project_velocity: true,
            ..none
        },
        GearBOptions {
            renormalise: true,
            ..none
        },
        GearBOptions {
            correct_higher_derivatives: true,
            ..none
        },
        GearBOptions {
            project_torque: true,
            project_velocity: true,
            renormalise: true,
            correct_higher_derivatives: true,
            ..none
        },
        GearBOptions {
            c0: FirstCorrector::PositionOnly,
            startup: Startup::Zeros,
            ..GearBOptions::default()
        },
    ];
    for options in variants {
        assert_thread_count_independent(&format!("{options:?}"), GearB::new(options));
    }
}

/// The kick-based baselines (their per-rotor passes share the chunking).
#[test]
fn baselines_are_bitwise_independent_of_the_thread_count() {
    assert_thread_count_independent("NO_SQUISH", NoSquish::default());
    assert_thread_count_independent(
        "DLM",
        Dlm::new(DlmOptions {
            spherical_tops: SphericalTops::Split,
        }),
    );
    assert_thread_count_independent("Richardson", Richardson::default());
}
