//! The virial as the strain derivative of the energy: each diagonal
//! component against central differences of the energy of the box and the
//! sites stretched along one axis (the multipoles fixed), for charges
//! (with and without a net charge), dipoles, quadrupoles and a mixture, in
//! both surroundings. The mesh energy is a smooth function of the strain at
//! a fixed mesh (the sites keep their mesh coordinates), so the coarse mesh
//! below does not limit the agreement; the real-space cutoff at `alpha r_c
//! = 6` keeps the pairs crossing it below round-off.

use super::Configuration;
use crate::potential::multipole::mesh_ewald::{MeshEwald, MeshParameters, SiteResponse};
use crate::potential::multipole::Surface;
use nalgebra::{Matrix3, Vector3};

/// Central differences' step in the strain.
const STRAIN_STEP: f64 = 1e-5;

/// Truncation `~ h^2` and round-off `~ 1e-16 / h` of the differences,
/// relative to the largest virial component: both near 1e-10.
const VIRIAL_TOLERANCE: f64 = 1e-8;

/// The parameters of the unstrained box (3.6 its shortest side).
fn parameters() -> MeshParameters {
    let real_cutoff = 0.49 * 3.6;
    MeshParameters {
        alpha: 6.0 / real_cutoff,
        real_cutoff,
        grid: [20, 18, 24],
        order: 6,
    }
}

fn evaluate(c: &Configuration, surface: Surface) -> SiteResponse {
    let mut sum = MeshEwald::new(c.positions.len(), c.box_lengths, parameters(), surface)
        .unwrap()
        .with_virial();
    let mut out = SiteResponse::zeros(c.positions.len());
    sum.evaluate(&c.sources(), &mut out).unwrap();
    out
}

/// `c` with the box and the positions stretched by `1 + strain` along `axis`.
fn stretched(c: &Configuration, axis: usize, strain: f64) -> Configuration {
    let mut s = c.clone();
    s.box_lengths[axis] *= 1.0 + strain;
    for r in &mut s.positions {
        r[axis] *= 1.0 + strain;
    }
    s
}

#[test]
fn the_virial_is_the_strain_derivative_of_the_energy() {
    let box_lengths = Vector3::new(4.0, 3.6, 4.4);
    let mut charged = Configuration::random(21, 30, box_lengths, (true, false, false));
    if let Some(q) = charged.charges.as_mut() {
        q[0] += 0.7;
    }
    let cases = [
        (
            "charges",
            Configuration::random(22, 30, box_lengths, (true, false, false)),
        ),
        ("net charge", charged),
        (
            "dipoles",
            Configuration::random(23, 30, box_lengths, (false, true, false)),
        ),
        (
            "quadrupoles",
            Configuration::random(24, 30, box_lengths, (false, false, true)),
        ),
        (
            "mixture",
            Configuration::random(25, 30, box_lengths, (true, true, true)),
        ),
    ];
    for (name, c) in &cases {
        for surface in [Surface::Conducting, Surface::Vacuum] {
            let virial: Matrix3<f64> = evaluate(c, surface).virial;
            let scale = virial.abs().max();
            for axis in 0..3 {
                let energy = |strain| evaluate(&stretched(c, axis, strain), surface).energy;
                let derivative = (energy(STRAIN_STEP) - energy(-STRAIN_STEP)) / (2.0 * STRAIN_STEP);
                assert!(
                    (virial[(axis, axis)] + derivative).abs() < VIRIAL_TOLERANCE * scale,
                    "{name} {surface:?} W[{axis}{axis}] {} vs -dV/de {}",
                    virial[(axis, axis)],
                    -derivative
                );
            }
        }
    }
}
