//! Every integrator's step gives bit-for-bit the same state on a 1-thread and
//! on a 2-thread rayon pool: its per-rotor passes run over fixed chunks of
//! rotors, each rotor reading and writing only its own entries. Checked on
//! the 1000-rotor dipole lattice (four chunks of rotors), with spherical tops
//! and with asymmetric tops (the two monomorphised paths of the Gear
//! schemes), for scheme A with and without renormalisation, scheme B with
//! each correction switch on its own, all of them and none, and the
//! kick-based baselines. Taking the steps in one call of
//! `Integrator::steps` (the Gear schemes then predict each step in the
//! previous step's last pass) gives the same bits as one call of `step`
//! each, also when it is stopped early.
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

/// How a run's steps are taken: one call of `Integrator::step` each, or
/// one call of `Integrator::steps` for all of them.
#[derive(Clone, Copy, Debug)]
enum Calls {
    OneByOne,
    Batched,
}

/// The complete state (the checkpoint, orientations included) after `steps`
/// steps of a copy of the set-up `integrator` on a pool of `threads`.
fn state_after<I: Integrator + Clone + Send>(
    integrator: &I,
    potential: &OnOneThread<MultipolePotential>,
    (threads, calls, steps): (usize, Calls, usize),
) -> Vec<u64> {
    let mut integrator = integrator.clone();
    pool(threads).install(|| match calls {
        Calls::OneByOne => {
            for _ in 0..steps {
                integrator.step(potential);
            }
        }
        Calls::Batched => {
            let taken = integrator.steps(potential, steps as u64, &mut |_| true);
            assert_eq!(taken, steps as u64);
        }
    });
    let orientations = integrator
        .orientations()
        .iter()
        .flat_map(|q| q.0.iter().map(|x| x.to_bits()));
    let state = integrator.checkpoint().into_iter().map(f64::to_bits);
    orientations.chain(state).collect()
}

/// Sets `integrator` up on both lattices and asserts that 1 and 2 threads,
/// one step per call or all in one call, give identical bits.
fn assert_thread_count_independent<I: Integrator + Clone + Send>(label: &str, integrator: I) {
    for asymmetric in [false, true] {
        let (scene, potential) = lattice(asymmetric);
        let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
        let mut integrator = integrator.clone();
        integrator
            .setup(&inertia, &potential, &scene.initial, scene.dt)
            .expect("valid setup");
        let one = state_after(&integrator, &potential, (1, Calls::OneByOne, STEPS));
        for run in [(2, Calls::OneByOne, STEPS), (2, Calls::Batched, STEPS)] {
            let other = state_after(&integrator, &potential, run);
            assert_eq!(one.len(), other.len());
            let differing = one.iter().zip(&other).filter(|(a, b)| a != b).count();
            assert_eq!(
                differing, 0,
                "{label}, asymmetric tops {asymmetric}, {run:?}: {differing} values differ"
            );
        }
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

/// A batch of steps that `go_on` stops after step 7 of 20 takes 7 steps and
/// leaves the state of 7 single steps (the Gear schemes must not have
/// predicted an eighth), for both Gear schemes.
#[test]
fn a_stopped_batch_of_gear_steps_ends_corrected() {
    let (scene, potential) = lattice(false);
    let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
    let gear_a = || -> Box<dyn Integrator> { Box::new(GearA::default()) };
    let gear_b = || -> Box<dyn Integrator> { Box::new(GearB::default()) };
    for make in [&gear_a as &dyn Fn() -> Box<dyn Integrator>, &gear_b] {
        let state = |batched: bool| {
            let mut integrator = make();
            integrator
                .setup(&inertia, &potential, &scene.initial, scene.dt)
                .expect("valid setup");
            if batched {
                let taken = integrator.steps(&potential, 20, &mut |taken| taken < 7);
                assert_eq!(taken, 7, "{}", integrator.name());
            } else {
                for _ in 0..7 {
                    integrator.step(&potential);
                }
            }
            integrator.checkpoint()
        };
        assert_eq!(state(true), state(false));
    }
}
