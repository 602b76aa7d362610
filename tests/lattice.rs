//! The cubic lattices: site counts, nearest-neighbour shells and box lengths
//! against the textbook values (sc: 6 at a; bcc: 8 at a sqrt(3)/2; fcc: 12 at a/sqrt(2)).

use quatrot::lattice::{Lattice, LatticeKind};

/// Distances are sums of a few multiples of the spacing: exact up to round-off.
const DISTANCE_TOLERANCE: f64 = 1e-12;

/// Every site has the textbook number of nearest neighbours at the textbook
/// distance, under minimum-image periodic boundaries.
#[test]
fn nearest_neighbour_shells_are_textbook() {
    let a = 1.7;
    for (kind, per_cell, shell, distance) in [
        (LatticeKind::SimpleCubic, 1, 6, a),
        (LatticeKind::Bcc, 2, 8, a * 3f64.sqrt() / 2.0),
        (LatticeKind::Fcc, 4, 12, a / 2f64.sqrt()),
    ] {
        let lattice = Lattice::cubic(kind, 3, a).unwrap();
        assert_eq!(lattice.sites.len(), 27 * per_cell, "{kind:?}");
        assert!(
            (lattice.box_lengths - nalgebra::Vector3::repeat(3.0 * a)).amax() < DISTANCE_TOLERANCE
        );
        for si in &lattice.sites {
            let distances: Vec<f64> = lattice
                .sites
                .iter()
                .filter(|sj| *sj != si)
                .map(|sj| {
                    (sj - si)
                        .zip_map(&lattice.box_lengths, |d, l| d - l * (d / l).round())
                        .norm()
                })
                .collect();
            let nearest = distances.iter().cloned().fold(f64::INFINITY, f64::min);
            let count = distances
                .iter()
                .filter(|d| (*d - nearest).abs() < DISTANCE_TOLERANCE)
                .count();
            assert!(
                (nearest - distance).abs() < DISTANCE_TOLERANCE,
                "{kind:?}: {nearest} vs {distance}"
            );
            assert_eq!(count, shell, "{kind:?}");
        }
    }
}

/// Zero cells or a non-positive spacing are refused with the value in the message.
#[test]
fn bad_lattice_parameters_are_refused() {
    let err = Lattice::cubic(LatticeKind::Fcc, 0, 1.0).unwrap_err();
    assert_eq!(err.to_string(), "cells: must be >= 1, got 0");
    let err = Lattice::cubic(LatticeKind::Bcc, 2, -1.0).unwrap_err();
    assert_eq!(err.to_string(), "spacing: must be > 0, got -1");
}
