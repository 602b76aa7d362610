//! Regression: the pair-geometry cache keyed offsets by `round(x / 1e-9)`
//! as an integer, which saturates beyond about 9.2e9 length units and merges
//! offsets closer than 1e-9, so distinct pairs shared one geometry and the
//! energy was wrong (issue 19). A cache must never change a result: these
//! energies are compared with the closed-form dipole-dipole sum
//! `V = sum_{i<j} [mu_i.mu_j - 3 (mu_i.n)(mu_j.n)] / r^3` evaluated pair by
//! pair in this file.

use nalgebra::Vector3;
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;

/// Summation order differs between the engine and the reference loop (a
/// few terms, a few ulps each).
const ROUND_OFF: f64 = 1e-14;

fn dipole_at(x: f64, y: f64, z: f64, mu: Vector3<f64>) -> Rotor {
    Rotor {
        site: Vector3::new(x, y, z),
        inertia: Inertia::Spherical(1.0),
        dipole_body: Some(mu),
        quadrupole_body: None,
    }
}

/// The closed-form pair sum over all pairs (identity orientations, so the
/// space dipoles are the body dipoles).
fn closed_form(rotors: &[Rotor]) -> f64 {
    let mut v = 0.0;
    for (i, a) in rotors.iter().enumerate() {
        for b in &rotors[i + 1..] {
            let r = b.site - a.site;
            let n = r / r.norm();
            let (mu_a, mu_b) = (a.dipole_body.unwrap(), b.dipole_body.unwrap());
            v += (mu_a.dot(&mu_b) - 3.0 * mu_a.dot(&n) * mu_b.dot(&n)) / r.norm().powi(3);
        }
    }
    v
}

fn engine(rotors: &[Rotor]) -> f64 {
    let p = MultipolePotential::new(rotors, Boundary::Open, ExternalFields::NONE).unwrap();
    p.energy(&vec![Quat::IDENTITY; rotors.len()])
}

/// Three dipoles along z on the x axis at 0, 1e10 and 3e10: three distinct
/// offsets far beyond the range of the old integer key (which gave 3.0e-30
/// instead of 1.162e-30).
#[test]
fn far_offsets_keep_their_own_geometry() {
    let z = Vector3::z();
    let rotors = [
        dipole_at(0.0, 0.0, 0.0, z),
        dipole_at(1e10, 0.0, 0.0, z),
        dipole_at(3e10, 0.0, 0.0, z),
    ];
    let expected = 1e-30 + 1.0 / 8e30 + 1.0 / 27e30;
    assert!((closed_form(&rotors) - expected).abs() <= ROUND_OFF * expected);
    let e = engine(&rotors);
    assert!((e - expected).abs() <= ROUND_OFF * expected, "{e:e}");
}

/// Two pairs whose offsets differ by less than the old key's resolution
/// (1.2e-9 and 1.4e-9 along z; 1 and 1 + 4e-10 along x): each pair keeps its
/// own geometry.
#[test]
fn near_coincident_offsets_keep_their_own_geometry() {
    let mu = Vector3::new(0.3, -0.4, 0.8);
    for (a, b) in [(1.2e-9, 1.4e-9), (1.0, 1.0 + 4e-10)] {
        let rotors = [
            dipole_at(0.0, 0.0, 0.0, mu),
            dipole_at(0.0, 0.0, a, mu),
            dipole_at(50.0, 0.0, 0.0, mu),
            dipole_at(50.0, 0.0, b, mu),
        ];
        let expected = closed_form(&rotors);
        let e = engine(&rotors);
        assert!(
            (e - expected).abs() <= ROUND_OFF * expected.abs(),
            "offsets {a:e}, {b:e}: {e:e} against {expected:e}"
        );
    }
}
