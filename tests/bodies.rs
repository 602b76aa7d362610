//! Moving rigid bodies (issue 39): forces, torques and the virial against
//! finite differences of the energy, the neighbour list's rebuilds, bad
//! systems and random starts (the integrators: `bodies_integrators.rs`).

mod bodies_common;

use bodies_common::{
    assert_minus_gradients, bent_molecule, bodies, energy, mixed_system, options, stockmayer,
};

use nalgebra::Vector3;
use quatrot::bodies::{
    random_start, Body, BodyNoSquish, BodySystem, Evaluation, InteractionOptions, RandomStart,
    Space, Truncation,
};
use quatrot::integrators::NoSquishOptions;

/// Every body's force and torque are minus the central differences of the
/// energy under a translation and a rotation of that body about each space
/// axis (an open cluster whose site pairs all lie within the cutoffs, so
/// the energy is smooth; step 1e-6: truncation ~1e-12, round-off ~1e-9
/// of an energy ~10).
#[test]
fn forces_and_torques_are_minus_the_energy_gradients() {
    const TOLERANCE: f64 = 2e-6;
    let mut system = mixed_system(Space::Open, Truncation::ForceShifted, 50.0, 12);
    let all: Vec<usize> = (0..system.bodies.len()).collect();
    assert_minus_gradients(&mut system, &all, 1e-6, &|_| TOLERANCE);
}

/// The trace of the molecular virial is minus the derivative of the energy
/// under a uniform scaling of the centres and the box (orientations fixed):
/// `dU/d lambda = -tr W` at `lambda = 1` (periodic box, shifted truncations
/// so the energy has no jumps; step 1e-6).
#[test]
fn the_molecular_virial_is_the_scaling_derivative() {
    let lengths = Vector3::repeat(6.4);
    let mut system = mixed_system(Space::Periodic(lengths), Truncation::ForceShifted, 2.5, 64);
    let mut e = Evaluation::default();
    system.evaluate(&mut e);
    // The electrostatic cutoff sum jumps where a pair crosses 2.5: check no
    // pair sits within the step of it by comparing both one-sided differences.
    let centres: Vec<Vector3<f64>> = system.bodies.iter().map(|b| b.position).collect();
    let mut scaled = |s: f64| {
        for (b, c) in system.bodies.iter_mut().zip(&centres) {
            b.position = c * s;
        }
        system.space = Space::Periodic(lengths * s);
        energy(&mut system)
    };
    let h = 1e-6;
    let (up, mid, down) = (scaled(1.0 + h), scaled(1.0), scaled(1.0 - h));
    let fd = (up - down) / (2.0 * h);
    assert!(
        ((up - mid) / h - (mid - down) / h).abs() < 1e-3 * (1.0 + fd.abs()),
        "a jump"
    );
    let trace = e.virial.trace();
    assert!(
        (fd + trace).abs() < 1e-6 * (1.0 + trace.abs()),
        "{fd} {trace}"
    );
}

/// A run with the list rebuilt only when a site moved half the skin gives
/// the same energies (to round-off of the summation order) as one rebuilt
/// at every step (skin 0), and it did rebuild along the way.
#[test]
fn rebuilding_by_the_skin_misses_no_pair() {
    let lengths = Vector3::repeat(6.4);
    let run = |skin: f64| {
        let types = vec![bent_molecule(), stockmayer()];
        let options = InteractionOptions {
            skin,
            ..options(Truncation::Plain, 2.5, 2.5)
        };
        let mut system = BodySystem::new(
            types,
            bodies(64, 1.6, 3, 2),
            Space::Periodic(lengths),
            &options,
        )
        .unwrap();
        let mut integrator =
            BodyNoSquish::new(&mut system, 0.002, NoSquishOptions::default()).unwrap();
        let mut energies = vec![];
        for _ in 0..200 {
            integrator.step(&mut system);
            energies.push(integrator.evaluation().potential_energy());
        }
        (energies, system.neighbour_builds())
    };
    let (with_skin, builds) = run(0.3);
    let (every_step, every) = run(0.0);
    assert!(builds > 1 && builds < 200, "{builds} builds");
    assert_eq!(every, 201);
    for (a, b) in with_skin.iter().zip(&every_step) {
        assert!((a - b).abs() < 1e-10 * (1.0 + b.abs()), "{a} {b}");
    }
}

/// Bad systems are refused naming the field.
#[test]
fn bad_systems_are_refused_naming_the_field() {
    let types = || vec![stockmayer()];
    let message = |bodies: Vec<Body>, space: Space, options: InteractionOptions| {
        BodySystem::new(types(), bodies, space, &options)
            .unwrap_err()
            .to_string()
    };
    let ok = options(Truncation::Plain, 2.5, 2.5);
    let mut bad = bodies(2, 1.6, 1, 1);
    bad[1].velocity.y = f64::INFINITY;
    assert_eq!(
        message(bad, Space::Open, ok),
        "bodies[1].velocity[1]: must be finite, got inf"
    );
    assert_eq!(
        message(
            bodies(2, 1.6, 1, 1),
            Space::Periodic(Vector3::new(6.0, 5.5, 6.0)),
            ok
        ),
        "box_lengths[1]: must be at least twice the cutoff plus the skin (5.6), got 5.5"
    );
    let no_coulomb = InteractionOptions {
        electrostatics: None,
        ..ok
    };
    assert_eq!(
        message(bodies(2, 1.6, 1, 1), Space::Open, no_coulomb),
        "electrostatics: required when sites carry charges, dipoles or quadrupoles"
    );
    let mut unknown = bodies(2, 1.6, 1, 1);
    unknown[0].kind = 1;
    assert_eq!(
        message(unknown, Space::Open, ok),
        "bodies[0].kind: must be below the number of body types (1), got 1"
    );
}

/// A random start of 1000 bent molecules and 1000 dipolar spheres: no two
/// centres closer than asked (a direct check of every pair), zero total
/// momentum to round-off, degrees of freedom 3N - 3 and 3 per molecule + 2
/// per sphere (its spin about the dipole left out), and temperatures within
/// five standard deviations `T sqrt(2 / N_f)` of the one asked.
#[test]
fn a_random_start_is_apart_at_rest_and_at_its_temperature() {
    let types = vec![bent_molecule(), stockmayer()];
    let kinds: Vec<usize> = (0..2000).map(|i| i % 2).collect();
    let start = RandomStart {
        density: 0.3,
        closest: 1.0,
        temperature: 1.5,
        seed: 11,
    };
    let (space, bodies) = random_start(&types, &kinds, &start).unwrap();
    let Space::Periodic(lengths) = space else {
        panic!("a periodic cube")
    };
    assert!((lengths.x.powi(3) * 0.3 - 2000.0).abs() < 1e-9);
    for i in 0..bodies.len() {
        for j in 0..i {
            let d = space.minimum_image(bodies[i].position - bodies[j].position);
            assert!(d.norm() >= 1.0, "bodies {i} and {j} are {} apart", d.norm());
        }
    }
    let system =
        BodySystem::new(types, bodies, space, &options(Truncation::Plain, 2.5, 2.5)).unwrap();
    assert!(system.linear_momentum().norm() < 1e-11);
    assert_eq!(system.translational_degrees(), 5997);
    assert_eq!(system.rotational_degrees(), 5000);
    for (t, dof) in [
        (system.translational_temperature().unwrap(), 5997.0),
        (system.rotational_temperature().unwrap(), 5000.0),
    ] {
        let sigma = 1.5 * (2.0f64 / dof).sqrt();
        assert!((t - 1.5).abs() < 5.0 * sigma, "{t}");
    }
}

/// A density that random insertion cannot pack is refused naming it.
#[test]
fn an_impossible_density_is_refused() {
    let start = RandomStart {
        density: 0.8,
        closest: 1.0,
        temperature: 1.0,
        seed: 1,
    };
    let e = random_start(&[stockmayer()], &[0; 10], &start).unwrap_err();
    assert_eq!(
        e.to_string(),
        "density: cannot be packed at random with centres 1 apart: packing fraction 0.41887902047863906 > 0.3"
    );
}

/// The pair pass counts the Lennard-Jones pairs that may overlap, those
/// closer than `OVERLAP_FRACTION` of their sigma (0.5; a part in 1e9 of
/// margin), and the run looks for the closest pair only when it counted
/// some: Stockmayer spheres (sigma 1) spread 1.6 apart, three pairs moved
/// to 0.45, 0.51 and 0.49 of each other count 2, and the closest pair is
/// the first; a forces-only evaluation counts nothing (`None`). The pairs
/// lie at the first, middle and last sites, so that with 3 threads the two
/// counted fall in different threads' blocks, whose counts add.
#[test]
fn the_pass_counts_the_pairs_inside_the_core() {
    use quatrot::bodies::{Scope, OVERLAP_FRACTION};
    assert_eq!(OVERLAP_FRACTION, 0.5);
    let mut moved = bodies(27, 1.6, 4, 1);
    for (k, gap) in [(0, 0.45), (12, 0.51), (24, 0.49)] {
        moved[k + 1].position = moved[k].position + Vector3::new(0.0, gap, 0.0);
    }
    let interactions = options(Truncation::Plain, 2.5, 2.5);
    let cases = [(bodies(27, 1.6, 4, 1), 0), (moved, 2)];
    for ((start, expected), threads) in cases.iter().flat_map(|c| [(c, 1), (c, 3)]) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut system = BodySystem::new(
            vec![stockmayer()],
            start.clone(),
            Space::Open,
            &interactions,
        )
        .unwrap();
        let mut e = Evaluation::default();
        pool.install(|| system.evaluate(&mut e));
        assert_eq!(e.overlaps, Some(*expected), "{threads} threads");
        let closest = system.closest_pair().expect("pairs of sites");
        if *expected > 0 {
            assert_eq!(closest.bodies, (0, 1));
            assert!((closest.distance - 0.45).abs() < 1e-12, "{closest:?}");
        } else {
            assert!(closest.distance > 1.0, "{closest:?}");
        }
        system.evaluate_in(&mut e, Scope::Forces);
        assert_eq!(e.overlaps, None);
    }
}

/// A list of some sites (`NeighbourList::listing`: the Lennard-Jones sites
/// when no electrostatic sum reads the list, as in rigid water under PME)
/// holds exactly the full list's pairs of those sites, with the same
/// separations, gives the others no partners, and does not go stale when
/// only an unlisted site moves.
#[test]
fn a_list_of_some_sites_holds_their_pairs_of_the_full_list() {
    use quatrot::bodies::NeighbourList;
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let space = Space::Periodic(Vector3::new(7.0, 6.5, 8.0));
    let mut sites: Vec<Vector3<f64>> = (0..300)
        .map(|_| Vector3::from_fn(|a, _| rng.random::<f64>() * [7.0, 6.5, 8.0][a]))
        .collect();
    // Bodies of three sites; the second and third of each unlisted.
    let body: Vec<u32> = (0..300).map(|s| s / 3).collect();
    let listed: Vec<bool> = (0..300).map(|s| s % 3 == 0).collect();
    let mut full = NeighbourList::new(2.5, 0.3).unwrap();
    let mut some = NeighbourList::new(2.5, 0.3)
        .unwrap()
        .listing(listed.clone());
    full.build(&sites, &body, &space);
    some.build(&sites, &body, &space);
    let mut kept = 0;
    for i in 0..sites.len() {
        let bits = |v: Vector3<f64>| v.map(f64::to_bits);
        let expected: Vec<_> = match listed[i] {
            true => full
                .half_pairs(i, &sites)
                .filter(|&(j, _)| listed[j])
                .map(|(j, r)| (j, bits(r)))
                .collect(),
            false => Vec::new(),
        };
        let found: Vec<_> = some
            .half_pairs(i, &sites)
            .map(|(j, r)| (j, bits(r)))
            .collect();
        assert_eq!(found, expected, "site {i}");
        kept += found.len();
    }
    assert!(
        kept > 100 && kept < full.pairs() / 4,
        "{kept} of {} pairs",
        full.pairs()
    );
    sites[1] += Vector3::new(0.2, 0.0, 0.0);
    assert!(full.is_stale(&sites, &space) && !some.is_stale(&sites, &space));
    sites[0] += Vector3::new(0.2, 0.0, 0.0);
    assert!(some.is_stale(&sites, &space));
}
