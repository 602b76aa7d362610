//! A small pinned lattice of multipolar rotors for the Gear tests: the 8
//! sites of a simple-cubic 2 x 2 x 2 lattice (spacing 1.5) as an open cluster,
//! each rotor with a dipole and a Buckingham quadrupole, in a uniform field
//! ([`MultipolePotential`]: dipole terms are quadratic and quadrupole terms
//! quartic in each `Q`, so the unprojected eq 14 gradient has large
//! components along `Q`).

use nalgebra::{Matrix3, Vector3};
use quatrot::integrators::RotorState;
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;

/// The cluster: potential, inertias and initial states. `mixed` alternates
/// spherical and asymmetric tops; otherwise all are asymmetric.
pub fn cube(mixed: bool) -> (MultipolePotential, Vec<Inertia>, Vec<RotorState>) {
    let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 2, 1.5).expect("valid lattice");
    let quadrupole = Matrix3::from_diagonal(&Vector3::new(0.4, 0.2, -0.6));
    let rotors: Vec<Rotor> = lattice
        .sites
        .iter()
        .enumerate()
        .map(|(i, site)| Rotor {
            site: *site,
            inertia: if mixed && i % 2 == 0 {
                Inertia::Spherical(1.2)
            } else {
                Inertia::Principal(Vector3::new(1.0, 1.6, 2.3))
            },
            dipole_body: Some(Vector3::new(0.2, -0.1, 1.0)),
            quadrupole_body: Some(quadrupole),
        })
        .collect();
    let external = ExternalFields {
        field: Some(Vector3::new(0.1, 0.0, 0.3)),
        field_gradient: None,
    };
    let potential =
        MultipolePotential::new(&rotors, Boundary::Open, external).expect("valid cluster");
    let initial = (0..rotors.len())
        .map(|i| {
            let s = i as f64;
            RotorState {
                orientation: Quat::new(
                    1.0 + 0.1 * s,
                    (0.7 * s).sin(),
                    (1.3 * s).cos(),
                    0.2 * s - 0.5,
                )
                .try_normalize()
                .expect("non-zero"),
                omega_body: Vector3::new((0.9 * s).cos(), (0.4 * s).sin(), 0.3 - 0.1 * s) * 0.8,
            }
        })
        .collect();
    (
        potential,
        rotors.iter().map(|r| r.inertia).collect(),
        initial,
    )
}
