//! The cost models the parameter search and the automatic choices weigh:
//! each term of `mesh_cost` against its closed form, the kind whose costs a
//! mixture takes, and the direct sum's choice of splitting against its
//! costs.

use crate::potential::multipole::mesh_ewald::{
    for_multipoles_with_skin, for_waves, mesh_cost, Carried, ForcedMesh, MeshCosts, MeshParameters,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

const CHARGES: Carried = Carried {
    charges: true,
    dipoles: false,
    quadrupoles: false,
};
const DIPOLES: Carried = Carried {
    charges: false,
    dipoles: true,
    quadrupoles: false,
};
const QUADRUPOLES: Carried = Carried {
    charges: false,
    dipoles: false,
    quadrupoles: true,
};

/// A mixture is priced as its dearest kind (quadrupoles, then dipoles),
/// and the kernels' work orders the kinds' pairs and spline points.
#[test]
fn a_mixture_takes_the_costs_of_its_dearest_kind() {
    let every = Carried {
        charges: true,
        dipoles: true,
        quadrupoles: true,
    };
    let charges_and_dipoles = Carried {
        quadrupoles: false,
        ..every
    };
    assert_eq!(every.costs(), QUADRUPOLES.costs());
    assert_eq!(charges_and_dipoles.costs(), DIPOLES.costs());
    let (c, d, q) = (CHARGES.costs(), DIPOLES.costs(), QUADRUPOLES.costs());
    assert!(c.pair < d.pair && d.pair < q.pair, "{c:?} {d:?} {q:?}");
    assert!(c.spline_point < d.spline_point && d.spline_point < q.spline_point);
}

/// Each term of the model is its count times its cost: `N n (2 pi / 3)
/// r_c^3` pairs, `N p^3` spline points, `N` sites, and a mesh term that
/// does not depend on the sites' costs and grows as `M log2 M`.
#[test]
fn each_term_is_its_count_times_its_cost() {
    let box_lengths = Vector3::new(10.0, 12.0, 9.0);
    let (n, rc, order) = (700, 2.5, 6);
    let parameters = MeshParameters {
        alpha: 1.2,
        real_cutoff: rc,
        grid: [32, 36, 30],
        order,
    };
    let priced = |pair, spline_point, site| {
        let costs = MeshCosts {
            pair,
            spline_point,
            site,
        };
        mesh_cost(&parameters, n, &box_lengths, costs)
    };
    let mesh = priced(0.0, 0.0, 0.0);
    let nf = n as f64;
    let pairs = nf * (nf / box_lengths.product()) * (2.0 * PI / 3.0) * rc.powi(3);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(priced(1.0, 0.0, 0.0) - mesh, pairs));
    assert!(close(
        priced(0.0, 1.0, 0.0) - mesh,
        nf * (order as f64).powi(3)
    ));
    assert!(close(priced(0.0, 0.0, 1.0) - mesh, nf));
    let points = |grid: [usize; 3]| -> f64 { grid.iter().map(|&k| k as f64).product() };
    let finer = MeshParameters {
        grid: [64, 72, 60],
        ..parameters
    };
    let free = MeshCosts {
        pair: 0.0,
        spline_point: 0.0,
        site: 0.0,
    };
    let m0 = points(parameters.grid);
    let m1 = points(finer.grid);
    let ratio = mesh_cost(&finer, n, &box_lengths, free) / mesh;
    assert!(mesh > 0.0);
    assert!(close(ratio, m1 * m1.log2() / (m0 * m0.log2())), "{ratio}");
}

/// The direct sum's estimate is linear in its two costs, and dearer wave
/// vectors move the splitting to fewer of them: a smaller `alpha`, a
/// longer real-space cutoff, a shorter reciprocal one.
#[test]
fn dearer_wave_vectors_take_fewer_of_them() {
    let box_lengths = Vector3::repeat(9.0);
    let longest = (4.5, "half the box");
    let sites = (DIPOLES, 729);
    let (base, seconds) =
        for_waves(1e-5, sites, &box_lengths, longest, (300e-9, 20e-9)).expect("a direct sum");
    let (same, doubled) =
        for_waves(1e-5, sites, &box_lengths, longest, (600e-9, 40e-9)).expect("a direct sum");
    assert_eq!(base, same);
    assert!(
        (doubled - 2.0 * seconds).abs() <= 1e-12 * seconds,
        "{doubled} {seconds}"
    );
    let (dear, _) =
        for_waves(1e-5, sites, &box_lengths, longest, (300e-9, 200e-9)).expect("a direct sum");
    assert!(dear.alpha < base.alpha, "{dear:?} {base:?}");
    assert!(dear.real_cutoff > base.real_cutoff);
    assert!(dear.reciprocal_cutoff < base.reciprocal_cutoff);
}

/// The direct sum's estimate is its counts at the splitting it chose times
/// their costs: `N n (2 pi / 3) r_c^3` real-space pairs and `N V k_c^3 /
/// (12 pi^2)` site-wave terms (half the wave vectors within `k_c`).
#[test]
fn the_direct_sum_counts_its_pairs_and_waves() {
    let box_lengths = Vector3::new(9.0, 10.0, 11.0);
    let n = 800;
    let longest = (4.5, "half the shortest side");
    let (nf, volume) = (n as f64, box_lengths.product());
    for (pair, wave) in [(1.0, 0.0), (0.0, 1.0), (300e-9, 20e-9)] {
        let (p, seconds) = for_waves(1e-5, (DIPOLES, n), &box_lengths, longest, (pair, wave))
            .expect("a direct sum");
        let pairs = nf * (nf / volume) * (2.0 * PI / 3.0) * p.real_cutoff.powi(3);
        let waves = nf * volume * p.reciprocal_cutoff.powi(3) / (12.0 * PI * PI);
        let expected = pair * pairs + wave * waves;
        assert!(
            (seconds - expected).abs() <= 1e-12 * expected,
            "{pair} {wave}: {seconds} against {expected}"
        );
    }
}

/// The mesh's search with a neighbour list's skin prices the real-space
/// pairs at the caller's cost: dearer pairs take a shorter cutoff (and a
/// finer mesh) than the kind's own pair cost.
#[test]
fn the_callers_pair_cost_moves_the_mesh_choice() {
    let box_lengths = Vector3::repeat(20.0);
    let (n, skin) = (8000, 0.3);
    let own = DIPOLES.costs().pair;
    let choose = |pair: f64| {
        for_multipoles_with_skin(
            1e-5,
            DIPOLES,
            n,
            &box_lengths,
            (skin, pair),
            &ForcedMesh::default(),
        )
        .expect("a mesh")
        .0
    };
    let (cheap, dear) = (choose(own), choose(10.0 * own));
    assert!(dear.real_cutoff < cheap.real_cutoff, "{dear:?} {cheap:?}");
    let points = |p: MeshParameters| p.grid.iter().product::<usize>();
    assert!(points(dear) > points(cheap), "{dear:?} {cheap:?}");
}
