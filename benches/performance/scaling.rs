//! Time per step against the number of rotors: periodic simple-cubic dipole
//! lattices (spacing 1, cutoff 3.1, |mu| = 1, I = 0.1, T = 1, as the built-in
//! 1000-rotor scene) from 2^3 = 8 to 47^3 = 103,823 rotors, on 1 and 2
//! threads. Below 7^3 the cutoff exceeds half the box and the sum runs over
//! several images per pair and each rotor's own images, so every size has the
//! same 61 pairs per rotor. A kernel measurement, so it uses the bare library
//! API: the potential is built (the pair-list build timed, median of
//! repeats), then NO_SQUISH (one torque evaluation per step, no start-up) is
//! stepped in a timed loop.

use crate::measure::{median, pool};
use crate::Effort;
use quatrot::integrators::{Integrator, NoSquish};
use quatrot::rotor::Inertia;
use quatrot::scene::raw::RawRotors;
use quatrot::scene::{load_raw, validate};
use serde_json::{json, Value};
use std::error::Error;
use std::time::Instant;

type Res<T> = Result<T, Box<dyn Error + Send + Sync>>;

/// Rotor-steps per timed repeat (the step count is this divided by N).
const ROTOR_STEPS: f64 = 1e6;
/// At most this many steps per repeat: the smallest lattices' steps cost
/// mostly per-step overhead, which 2e4 steps already resolve.
const MAX_STEPS: f64 = 2e4;
const REPEATS: usize = 3;

/// Every size on every thread count.
pub fn run(effort: Effort) -> Res<Value> {
    let cells: &[i64] = effort.pick(&[2, 3, 5, 7, 10, 14, 20, 30, 47][..], &[2, 3][..]);
    let mut out = Vec::new();
    for &n in cells {
        let mut raw = load_raw("dipole_lattice_sc_cutoff")?;
        if let Some(RawRotors::Lattice(l)) = &mut raw.rotors {
            l.cells = n;
        }
        let scene = validate(&raw)?;
        let mut builds = Vec::new();
        let mut built = None;
        for _ in 0..REPEATS {
            let started = Instant::now();
            built = quatrot::run::potential(&scene)?;
            builds.push(started.elapsed().as_secs_f64());
        }
        let potential = built.ok_or("the lattice scene has interactions")?;
        let pair_list_seconds = median(&builds);
        let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
        let rotors = inertia.len();
        let steps = effort.pick(
            (ROTOR_STEPS / rotors as f64).ceil().clamp(5.0, MAX_STEPS) as usize,
            2,
        );
        for threads in [1usize, 2] {
            let walls = pool(threads)?.install(|| -> Res<Vec<f64>> {
                let mut walls = Vec::new();
                for _ in 0..REPEATS {
                    let mut integrator = NoSquish::default();
                    integrator.setup(&inertia, &potential, &scene.initial, scene.dt)?;
                    let started = Instant::now();
                    for _ in 0..steps {
                        integrator.step(&potential);
                    }
                    walls.push(started.elapsed().as_secs_f64());
                }
                Ok(walls)
            })?;
            out.push(json!({
                "cells": n,
                "rotors": rotors,
                "pairs": potential.pair_count(),
                "threads": threads,
                "steps": steps,
                "wall_seconds": walls,
                "seconds_per_step": median(&walls) / steps as f64,
                "pair_list_seconds": pair_list_seconds,
            }));
        }
        eprintln!("  N = {rotors} (pair list {pair_list_seconds:.2} s)");
    }
    Ok(Value::from(out))
}
