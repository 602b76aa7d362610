//! What the mesh Ewald sum guarantees beyond its values: sums reproducible
//! for a given thread count, no buffers allocated per evaluation, refusals.

use super::{fine, Configuration};
use crate::allocation_meter::peak_above_start;
use crate::potential::multipole::mesh_ewald::{MeshEwald, MeshParameters, SiteResponse, Sources};
use crate::potential::multipole::Surface;
use nalgebra::Vector3;

/// Each thread count gives the same bits at every evaluation (the mesh
/// sums run in a fixed order per plane and per site, the real-space pairs
/// in one block per thread added in a fixed order), and 2 and 3 threads
/// agree with one to round-off (the blocks only regroup the pair sums).
#[test]
fn results_are_reproducible_for_a_thread_count() {
    let box_lengths = Vector3::new(5.0, 4.6, 5.2);
    let c = Configuration::random(9, 300, box_lengths, (true, true, true));
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| c.mesh(fine(&box_lengths, 4.0), Surface::Vacuum))
    };
    let one = run(1);
    let scale = one.force.iter().map(|f| f.norm()).fold(0.0, f64::max);
    for threads in [1, 2, 3] {
        let (first, again) = (run(threads), run(threads));
        assert_eq!(first.energy.to_bits(), again.energy.to_bits(), "{threads}");
        assert_eq!(first.force, again.force, "{threads}");
        assert_eq!(first.quadrupole_conjugate, again.quadrupole_conjugate);
        assert!((first.energy - one.energy).abs() <= 1e-12 * one.energy.abs());
        for (f, g) in first.force.iter().zip(&one.force) {
            assert!((f - g).norm() <= 1e-12 * scale, "{threads} threads");
        }
    }
}

/// Parameters the sum cannot use are refused naming the field.
#[test]
fn unusable_parameters_are_refused_naming_the_field() {
    let box_lengths = Vector3::repeat(3.0);
    let good = fine(&box_lengths, 4.0);
    let cases = [
        (MeshParameters { order: 9, ..good }, "order"),
        (
            MeshParameters {
                grid: [16, 5, 16],
                order: 6,
                ..good
            },
            "grid[1]",
        ),
        (
            MeshParameters {
                real_cutoff: 1.6,
                ..good
            },
            "real_cutoff",
        ),
        (MeshParameters { alpha: 0.0, ..good }, "alpha"),
    ];
    for (parameters, path) in cases {
        let e = MeshEwald::new(4, box_lengths, parameters, Surface::Conducting).unwrap_err();
        assert_eq!(e.path, path, "{e}");
    }
    let mut sum = MeshEwald::new(2, box_lengths, good, Surface::Conducting).unwrap();
    let positions = [Vector3::zeros(), Vector3::new(f64::NAN, 0.0, 0.0)];
    let sources = Sources {
        positions: &positions,
        charges: Some(&[1.0, -1.0]),
        dipoles: None,
        quadrupoles: None,
    };
    let e = sum
        .evaluate(&sources, &mut SiteResponse::zeros(2))
        .unwrap_err();
    assert_eq!(e.path, "positions[1]", "{e}");
    let e = sum
        .evaluate(&sources, &mut SiteResponse::zeros(3))
        .unwrap_err();
    assert_eq!(e.path, "positions", "{e}");
}

/// An evaluation holds nothing afterwards and allocates no buffer sized by
/// the sites or the mesh: every one is built once, the FFT convolution's
/// included, and what is left is the transforms' scratch of a few lines
/// (at most 4 complex values per point of the longest axis for each line
/// kept, 64 bytes per point), the same for 60 and 600 sites (one thread,
/// so that the calling thread does all the work).
#[test]
fn evaluations_allocate_no_site_or_mesh_buffers() {
    let box_lengths = Vector3::repeat(4.0);
    let parameters = fine(&box_lengths, 3.0);
    let peak = |n: usize| {
        let c = Configuration::random(10, n, box_lengths, (true, true, true));
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| {
                let mut sum = MeshEwald::new(n, box_lengths, parameters, Surface::Vacuum).unwrap();
                let mut out = SiteResponse::zeros(n);
                sum.evaluate(&c.sources(), &mut out).unwrap();
                let (result, peak, held) =
                    peak_above_start(|| sum.evaluate(&c.sources(), &mut out));
                result.unwrap();
                assert_eq!(held, 0);
                peak
            })
    };
    let few = peak(60);
    let longest = *parameters.grid.iter().max().unwrap();
    assert!(
        few <= 64 * longest,
        "{few} bytes for a longest axis of {longest} points"
    );
    assert_eq!(peak(600), few);
}

/// Without the field gradient, a sum of charges gives the same energy,
/// potentials, fields and forces to round-off (the real-space kernel and
/// the gathering only skip the second derivatives) and a zero
/// `quadrupole_conjugate`; a sum with dipoles keeps its gradient.
#[test]
fn charges_without_the_field_gradient_keep_their_forces() {
    let box_lengths = Vector3::new(5.0, 4.6, 5.2);
    let parameters = fine(&box_lengths, 3.5);
    for dipoles in [false, true] {
        let c = Configuration::random(11, 200, box_lengths, (true, dipoles, false));
        let full = c.mesh(parameters, Surface::Conducting);
        let mut sum = MeshEwald::new(200, box_lengths, parameters, Surface::Conducting)
            .unwrap()
            .without_field_gradient();
        let mut out = SiteResponse::zeros(200);
        sum.evaluate(&c.sources(), &mut out).unwrap();
        let scale = full.force.iter().map(|f| f.norm()).fold(0.0, f64::max);
        assert!((out.energy - full.energy).abs() <= 1e-12 * full.energy.abs());
        for i in 0..200 {
            assert!((out.force[i] - full.force[i]).norm() <= 1e-12 * scale);
            assert!((out.field[i] - full.field[i]).norm() <= 1e-12 * scale);
            assert!((out.potential[i] - full.potential[i]).abs() <= 1e-12 * scale);
        }
        let gradient = out.quadrupole_conjugate.iter().any(|w| w.norm() > 0.0);
        assert_eq!(gradient, dipoles, "dipoles {dipoles}");
    }
}
