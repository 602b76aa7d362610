use nalgebra::Vector3;
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::*;
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;

#[test]
fn scratch() {
    for kind in [LatticeKind::SimpleCubic, LatticeKind::Bcc, LatticeKind::Fcc] {
        let lattice = Lattice::cubic(kind, 3, 1.3).unwrap();
        let mu = Vector3::new(0.3, -0.5, 0.8);
        let rotors: Vec<Rotor> = lattice
            .sites
            .iter()
            .map(|s| Rotor {
                site: *s,
                inertia: Inertia::Spherical(1.0),
                dipole_body: Some(mu),
                quadrupole_body: None,
            })
            .collect();
        let n = rotors.len() as f64 / lattice.box_lengths.product();
        let expect = -(2.0 * std::f64::consts::PI / 3.0) * n * mu.norm_squared();
        for method in [SumMethod::Auto, SumMethod::Direct] {
            let p = MultipolePotential::with_method(
                &rotors,
                Boundary::periodic_ewald(lattice.box_lengths),
                ExternalFields::NONE,
                method,
            )
            .unwrap();
            let q = vec![Quat::IDENTITY; rotors.len()];
            let e = p.energy(&q) / rotors.len() as f64;
            println!(
                "{kind:?} {:?} {:?} {e} {expect} {:e}",
                method,
                p.sum_path(),
                (e - expect) / expect
            );
        }
    }
}
