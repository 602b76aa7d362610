//! Cost per step of the runner against the bare integrator loop, on the
//! 1000-rotor simple-cubic dipole lattice (scheme B) and on 1000 free
//! asymmetric tops (DLM, where the runner's own overhead is most visible):
//! every observable every step, energies every 100 steps, nothing recorded,
//! and the bare `integrator.step(potential)` loop. Each iteration runs
//! `STEPS` steps from the same set-up integrator (setup excluded).
//!
//! On a shared machine the criterion groups, measured one after the other,
//! drift with the load; after them an interleaved comparison runs the four
//! cases in turn `REPETITIONS` times (`INTERLEAVED_STEPS` steps each) and
//! prints the best time of each and the
//! runner's overhead over the bare loop (best against best).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use quatrot::integrators::{Dlm, GearB, Integrator};
use quatrot::internals::on_worker;
use quatrot::potential::{Boundary, ExternalFields, Free, MultipolePotential, Potential};
use quatrot::rotor::Inertia;
use quatrot::run::{CsvTarget, RunError, SeriesObserver};
use quatrot::scene::{load, validate, Overrides, Scene, Series};
use quatrot::simulation::{
    run, BlowUpChecks, EnergyReference, MultipoleInputs, Observer, Quantity, RunOptions, Scheduled,
};
use std::hint::black_box;
use std::time::Instant;

/// Steps per measured iteration.
const STEPS: u64 = 200;
/// Rounds of the interleaved comparison, and steps per round: many short
/// rounds make the best time robust to load from other processes.
const REPETITIONS: usize = 100;
const INTERLEAVED_STEPS: u64 = 20;

/// Options for steps `start..end`; with a `reference` given, the runner
/// evaluates no energy at the start for the energy error.
fn options(scene: &Scene, start: u64, end: u64, reference: Option<EnergyReference>) -> RunOptions {
    RunOptions {
        start_step: start,
        end_step: end,
        checks: Some(BlowUpChecks {
            every: scene.record.check_every,
            energy_error_threshold: None,
        }),
        reference,
        control: None,
    }
}

fn every_quantity(every: u64, quantities: Vec<Quantity>) -> Series {
    Series {
        name: "bench".to_string(),
        every,
        quantities,
    }
}

/// The observables of the "everything every step" case: every quantity the
/// integrator and the rotors can give (`q_dot_n` needs scheme B, the
/// multipole quantities rotors that carry the multipole).
fn all_quantities(integrator_name: &str, scene: &Scene) -> Vec<Quantity> {
    Quantity::ALL
        .into_iter()
        .filter(|&q| q != Quantity::NormForce || integrator_name == "gear_b")
        .filter(|&q| MultipoleInputs::new(&scene.rotors, &[q]).is_ok())
        .collect()
}

/// The runner cases: a name and the series recorded (none for the first);
/// energies are recorded every `energies_every` steps.
fn cases(
    integrator_name: &str,
    scene: &Scene,
    energies_every: u64,
) -> [(String, Option<Series>); 3] {
    let energies = vec![
        Quantity::KineticEnergy,
        Quantity::PotentialEnergy,
        Quantity::TotalEnergy,
    ];
    [
        ("nothing_recorded".to_string(), None),
        (
            format!("energies_every_{energies_every}"),
            Some(every_quantity(energies_every, energies)),
        ),
        (
            "everything_every_step".to_string(),
            Some(every_quantity(1, all_quantities(integrator_name, scene))),
        ),
    ]
}

/// `steps` bare steps, on a rayon worker as `run::execute` runs them.
fn bare<I: Integrator + Send, P: Potential>(mut integrator: I, potential: &P, steps: u64) {
    on_worker(|| {
        for _ in 0..steps {
            integrator.step(potential);
        }
        black_box(integrator.orientations()[0]);
    });
}

/// The observer of `series` of `scene`, writing CSV to `csv` (created
/// outside the timed region: opening a file is a per-run cost, not a
/// per-step one).
fn observer(
    series: Option<&Series>,
    scene: &Scene,
    csv: &std::path::Path,
) -> Option<SeriesObserver> {
    series.map(|s| {
        SeriesObserver::new(s, &scene.rotors, Some(CsvTarget::Create(csv)), false).expect("csv")
    })
}

/// The runner from `options.start_step` to `options.end_step`, feeding
/// `observer` every `every` steps, on a rayon worker as `run::execute` runs it.
fn through_runner<I: Integrator + Send, P: Potential>(
    mut integrator: I,
    mut observer: Option<SeriesObserver>,
    every: u64,
    potential: &P,
    options: &RunOptions,
    inertia: &[Inertia],
) {
    on_worker(|| {
        let mut scheduled: Vec<Scheduled<'_, RunError>> = observer
            .iter_mut()
            .map(|o| Scheduled {
                every,
                at_end: false,
                observer: o as &mut dyn Observer<Error = RunError>,
            })
            .collect();
        black_box(
            run(
                &mut integrator,
                potential,
                inertia,
                &mut scheduled,
                None,
                options,
            )
            .expect("runs"),
        );
    });
}

fn bench_system<I: Integrator + Clone + Send, P: Potential>(
    c: &mut Criterion,
    group_name: &str,
    scene: &Scene,
    mut integrator: I,
    potential: &P,
) {
    let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
    integrator
        .setup(&inertia, potential, &scene.initial, scene.dt)
        .expect("setup");
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("bench.csv");
    let mut group = c.benchmark_group(group_name);
    group.sample_size(10);
    group.bench_function("bare_loop", |b| {
        b.iter_batched(
            || integrator.clone(),
            |i| bare(i, potential, STEPS),
            BatchSize::LargeInput,
        )
    });
    for (name, series) in cases(integrator.name(), scene, 100) {
        group.bench_function(name, |b| {
            let every = series.as_ref().map_or(1, |s| s.every);
            b.iter_batched(
                || (integrator.clone(), observer(series.as_ref(), scene, &csv)),
                |(i, o)| {
                    let opts = options(scene, 0, STEPS, None);
                    through_runner(i, o, every, potential, &opts, &inertia)
                },
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
    interleaved(group_name, scene, &integrator, potential, &inertia, &csv);
}

/// Runs the bare loop and the three runner cases in turn and prints the best
/// time per step of each and the overhead over the bare loop.
fn interleaved<I: Integrator + Clone + Send, P: Potential>(
    group_name: &str,
    scene: &Scene,
    integrator: &I,
    potential: &P,
    inertia: &[Inertia],
    csv: &std::path::Path,
) {
    // Rounds run steps 1..=INTERLEAVED_STEPS with the energy reference given,
    // so "energies every INTERLEAVED_STEPS" evaluates the energy exactly once
    // per round, as a long run would.
    let cases = cases(integrator.name(), scene, INTERLEAVED_STEPS);
    let reference = Some(EnergyReference::initial(1.0, 1.0));
    let opts = options(scene, 1, 1 + INTERLEAVED_STEPS, reference);
    let mut best = [f64::INFINITY; 4];
    for _ in 0..REPETITIONS {
        let i = integrator.clone();
        let start = Instant::now();
        bare(i, potential, INTERLEAVED_STEPS);
        best[0] = best[0].min(start.elapsed().as_secs_f64());
        for (k, (_, series)) in cases.iter().enumerate() {
            let i = integrator.clone();
            let every = series.as_ref().map_or(1, |s| s.every);
            let o = observer(series.as_ref(), scene, csv);
            let start = Instant::now();
            through_runner(i, o, every, potential, &opts, inertia);
            best[k + 1] = best[k + 1].min(start.elapsed().as_secs_f64());
        }
    }
    let per_step = |t: f64| t / INTERLEAVED_STEPS as f64 * 1e6;
    println!("{group_name} interleaved, best of {REPETITIONS} x {INTERLEAVED_STEPS} steps:");
    println!("  bare_loop: {:.1} us/step", per_step(best[0]));
    for (k, (name, _)) in cases.iter().enumerate() {
        println!(
            "  {name}: {:.1} us/step, {:+.1} % over the bare loop",
            per_step(best[k + 1]),
            100.0 * (best[k + 1] / best[0] - 1.0)
        );
    }
}

fn runner(c: &mut Criterion) {
    let (_, lattice) = load("dipole_lattice_sc", &Overrides::default()).expect("built-in");
    let periodic = Boundary::periodic_cutoff(lattice.box_lengths().expect("periodic"), 3.1);
    let potential = MultipolePotential::new(&lattice.rotors, periodic, ExternalFields::NONE)
        .expect("potential");
    bench_system(
        c,
        "runner_dipole_lattice_gear_b",
        &lattice,
        GearB::default(),
        &potential,
    );

    let (mut raw, _) = load("multipole_tops_bcc", &Overrides::default()).expect("built-in");
    raw.interactions = None;
    if let Some(quatrot::scene::raw::RawRotors::Lattice(l)) = &mut raw.rotors {
        l.cells = 8; // 1024 rotors
        l.default.dipole = None;
        l.default.quadrupole = None;
    }
    let free_tops = validate(&raw).expect("valid");
    bench_system(c, "runner_free_tops_dlm", &free_tops, Dlm::default(), &Free);
}

criterion_group!(benches, runner);
criterion_main!(benches);
