//! The parameters chosen for an accuracy, checked against the converged sum.

use super::references::textbook_charges;
use super::{flat3, flat33, relative_rms, Configuration};
use crate::potential::multipole::mesh_ewald::{
    for_charges, for_multipoles, for_multipoles_forced, Carried, ForcedMesh, MeshParameters,
    SiteResponse, ACCURACY_RANGE,
};
use crate::potential::multipole::Surface;
use nalgebra::Vector3;

/// The estimates hold: at each requested accuracy, the RMS force error of
/// neutral random charges against the converged textbook sum, relative to
/// `F_0 = (Q^2 / N) n^(2/3)`, is within the request, and the estimate is
/// not wasteful by more than a factor 100 (a cheaper mesh would do).
#[test]
fn chosen_parameters_reach_the_requested_force_accuracy() {
    let box_lengths = Vector3::new(5.0, 5.5, 6.0);
    let c = Configuration::random(11, 100, box_lengths, (true, false, false));
    let (_, force) = textbook_charges(&c);
    let q = c.charges.as_ref().unwrap();
    let n = q.len() as f64;
    let f0 = q.iter().map(|q| q * q).sum::<f64>() / n * (n / box_lengths.product()).powf(2.0 / 3.0);
    for accuracy in [1e-3, 1e-4, 1e-5, 1e-6] {
        let (parameters, estimate) = for_charges(accuracy, q, &box_lengths, 2.0, None).unwrap();
        let out = c.mesh(parameters, Surface::Conducting);
        let rms = relative_rms(&flat3(&out.force), &flat3(&force))
            * (force.iter().map(|f| f.norm_squared()).sum::<f64>() / n).sqrt()
            / f0;
        let estimated = estimate.real.hypot(estimate.mesh);
        assert!(
            rms <= accuracy && rms >= accuracy / 100.0,
            "accuracy {accuracy}: measured {rms:.2e}, estimated {estimated:.2e}, {parameters:?}"
        );
    }
}

/// The multipole estimate holds for charges (what charged bodies' sums
/// use): at each requested accuracy the RMS field error of neutral random
/// charges against the textbook sum, relative to `q_rms n^(2/3)`, is within
/// the request and not below a hundredth of it. Before
/// `CHARGE_MESH_SAFETY` the mesh estimate of charges fell short by up to
/// 2.8x and the field error reached 1.4 times the request.
#[test]
fn charge_parameters_of_the_multipole_estimate_reach_the_requested_field_accuracy() {
    let box_lengths = Vector3::new(6.0, 6.5, 7.0);
    let c = Configuration::random(31, 150, box_lengths, (true, false, false));
    let (_, force) = textbook_charges(&c);
    let q = c.charges.as_ref().unwrap();
    let n = q.len() as f64;
    let field: Vec<Vector3<f64>> = force.iter().zip(q).map(|(f, q)| f / *q).collect();
    let scale = (q.iter().map(|q| q * q).sum::<f64>() / n).sqrt()
        * (n / box_lengths.product()).powf(2.0 / 3.0);
    let carried = Carried {
        charges: true,
        ..Carried::default()
    };
    for accuracy in [1e-3, 1e-4, 1e-5, 1e-6] {
        let (parameters, estimate) =
            for_multipoles(accuracy, carried, q.len(), &box_lengths, None, None).unwrap();
        let out = c.mesh(parameters, Surface::Conducting);
        let measured = rms_difference(&flat3(&out.field), &flat3(&field), q.len()) / scale;
        assert!(
            measured <= accuracy && measured >= accuracy / 100.0,
            "accuracy {accuracy}: measured {measured:.2e}, estimated {estimate:?}, {parameters:?}"
        );
    }
}

/// Requests the estimates cannot serve are refused, naming the field.
#[test]
fn unreachable_requests_are_refused_naming_the_field() {
    let box_lengths = Vector3::repeat(4.0);
    let q = [1.0, -1.0];
    let (low, high) = ACCURACY_RANGE;
    for (accuracy, cutoff, order, path) in [
        (low / 2.0, 1.5, None, "accuracy"),
        (high * 2.0, 1.5, None, "accuracy"),
        (1e-5, 2.5, None, "real_cutoff"),
        (1e-5, 1.5, Some(8), "order"),
        (1e-5, 1.5, Some(6), "order"),
    ] {
        let e = for_charges(accuracy, &q, &box_lengths, cutoff, order).unwrap_err();
        assert_eq!(e.path, path, "{e}");
    }
    let e = for_charges(1e-5, &[0.0, 0.0], &box_lengths, 1.5, None).unwrap_err();
    assert_eq!(e.path, "charges", "{e}");
}

/// The RMS over `sites` sites of the difference of per-site values `a`
/// and `b` (flattened).
fn rms_difference(a: &[f64], b: &[f64], sites: usize) -> f64 {
    let squares: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    (squares / sites as f64).sqrt()
}

/// The RMS errors of the fields the torques need, `(E, W)`, against the
/// converged direct sum, relative to the field scales
/// `sigma_s n^((s + g + 1) / 3)` of the largest source order `s` carried
/// (the `estimate` module doc).
fn multipole_field_errors(c: &Configuration, parameters: MeshParameters) -> (f64, f64) {
    let (_, field, conjugate) = c.direct(Surface::Conducting);
    let out = c.mesh(parameters, Surface::Conducting);
    let n = c.positions.len() as f64;
    let density = n / c.box_lengths.product();
    let rms = |x: f64| (x / n).sqrt();
    let (sigma, s) = match (&c.quadrupoles, &c.dipoles) {
        (Some(t), _) => (rms(t.iter().map(|t| t.norm_squared()).sum()), 2.0),
        (None, Some(m)) => (rms(m.iter().map(|m| m.norm_squared()).sum()), 1.0),
        (None, None) => unreachable!("multipoles"),
    };
    let error_e = rms_difference(&flat3(&out.field), &flat3(&field), field.len());
    let error_w = rms_difference(
        &flat33(&out.quadrupole_conjugate),
        &flat33(&conjugate),
        conjugate.len(),
    );
    (
        error_e / (sigma * density.powf((s + 2.0) / 3.0)),
        error_w / (sigma * density.powf((s + 3.0) / 3.0)),
    )
}

/// The estimate holds for dipoles, quadrupoles and both, on random sites:
/// at each requested accuracy the measured RMS field errors against the
/// converged direct sum are within the request and not below a hundredth of
/// it (a cheaper mesh would do). Measured over requested (2026-11-28):
/// dipoles 0.31-0.42, quadrupoles and mixtures 0.03-0.14 (the mesh
/// estimate is pessimistic for the rank-4 tensor).
#[test]
fn multipole_parameters_reach_the_requested_field_accuracy() {
    let box_lengths = Vector3::new(6.0, 6.5, 7.0);
    for (kinds, seed) in [
        ((false, true, false), 21),
        ((false, false, true), 22),
        ((false, true, true), 23),
    ] {
        let c = Configuration::random(seed, 150, box_lengths, kinds);
        let carried = Carried {
            charges: false,
            dipoles: kinds.1,
            quadrupoles: kinds.2,
        };
        for accuracy in [1e-3, 1e-5, 1e-7] {
            let (parameters, estimate) =
                for_multipoles(accuracy, carried, 150, &box_lengths, None, None).unwrap();
            let (e, w) = multipole_field_errors(&c, parameters);
            let measured = if kinds.2 { e.max(w) } else { e };
            assert!(
                measured <= accuracy && measured >= accuracy / 100.0,
                "{kinds:?} accuracy {accuracy}: measured {e:.2e} {w:.2e}, estimated {estimate:?}, {parameters:?}"
            );
        }
    }
}

/// At a fixed accuracy, parameters chosen at splittings `alpha d` from 2 to
/// 4.5 (so different cutoffs and meshes) give the same energy and fields
/// within twice the request (the trap of helpme #57: PME energies of
/// dipoles that depended on the splitting), on random dipoles and
/// quadrupoles.
#[test]
fn multipole_results_at_fixed_accuracy_do_not_depend_on_the_splitting() {
    let box_lengths = Vector3::new(6.0, 6.5, 7.0);
    let c = Configuration::random(24, 150, box_lengths, (false, true, true));
    let carried = Carried {
        charges: false,
        dipoles: true,
        quadrupoles: true,
    };
    let n = 150.0;
    let density = n / box_lengths.product();
    let rms = |x: f64| (x / n).sqrt();
    let sigma = rms(c
        .quadrupoles
        .iter()
        .flatten()
        .map(|t| t.norm_squared())
        .sum());
    let accuracy = 1e-5;
    let d = density.cbrt().recip();
    let runs: Vec<(MeshParameters, SiteResponse)> = [2.0, 3.0, 4.5]
        .iter()
        .map(|&alpha_d| {
            let (p, _) = for_multipoles(
                accuracy,
                carried,
                150,
                &box_lengths,
                None,
                Some(alpha_d / d),
            )
            .unwrap();
            (p, c.mesh(p, Surface::Conducting))
        })
        .collect();
    // Energy scale sum_i Theta_i^2 n^(5/3), as the fields' (module doc of `estimate`).
    let energy_scale = n * sigma * sigma * density.powf(5.0 / 3.0);
    for (a, b) in runs.iter().zip(runs.iter().skip(1)) {
        let energy = (a.1.energy - b.1.energy).abs() / energy_scale;
        let field = rms_difference(&flat3(&a.1.field), &flat3(&b.1.field), 150)
            / (sigma * density.powf(4.0 / 3.0));
        assert!(
            energy <= 2.0 * accuracy && field <= 2.0 * accuracy,
            "{:?} vs {:?}: energy {energy:.2e}, field {field:.2e}",
            a.0,
            b.0
        );
    }
}

/// Forced parameters are kept, the rest chosen for the accuracy, and the
/// estimate holds for them: on random dipoles, each forced set the
/// estimates accept at 1e-5 gives a measured field error within 1e-5
/// against the converged direct sum; each set they refuse says the
/// accuracy it reaches, and asked for that (10 % over the two digits
/// printed), the same set is accepted and its measured error is within it.
/// The sets keep `alpha d` (`d = n^(-1/3)`) at most 3: beyond, the mesh
/// estimate of dipoles falls short (2026-11-28, this configuration, a forced
/// `real_cutoff = 1.3` taking `alpha d = 4.3`: measured up to 4.2x the
/// request, at order 5; `alpha d = 3.7` at order 8: 1.3x), an open defect
/// of the estimate that the automatic choice meets only where such
/// splittings are cheapest (none of its accuracy tests).
#[test]
fn forced_parameters_are_kept_and_reach_what_their_estimate_says() {
    let box_lengths = Vector3::new(6.0, 6.5, 7.0);
    let c = Configuration::random(25, 150, box_lengths, (false, true, false));
    let carried = Carried {
        dipoles: true,
        ..Carried::default()
    };
    let accuracy = 1e-5;
    let forced = |order: Option<i64>, grid: Option<&[i64]>, rc: Option<f64>, alpha: Option<f64>| {
        ForcedMesh::new(order, grid, rc, alpha).unwrap()
    };
    let sets = [
        forced(Some(4), None, None, None),
        forced(None, Some(&[30]), None, None),
        forced(Some(8), Some(&[24, 25, 27]), None, None),
        forced(None, None, Some(2.9), None),
        forced(None, None, None, Some(1.4)),
        forced(Some(6), Some(&[40]), Some(2.6), Some(1.3)),
        forced(Some(4), Some(&[12]), None, None),
        forced(None, None, Some(2.0), None),
        forced(None, None, Some(2.0), Some(1.0)),
    ];
    let (mut accepted, mut refused) = (0, 0);
    for set in sets {
        let request = match for_multipoles_forced(accuracy, carried, 150, &box_lengths, &set) {
            Ok(_) => {
                accepted += 1;
                accuracy
            }
            Err(e) => {
                refused += 1;
                assert!(["grid", "real_cutoff"].contains(&e.path.as_str()), "{e}");
                let reach: f64 = e
                    .message
                    .split(" reaches ")
                    .nth(1)
                    .and_then(|rest| rest.split(' ').next())
                    .and_then(|x| x.parse().ok())
                    .unwrap_or_else(|| panic!("no accuracy reached in {e}"));
                assert!(reach > accuracy, "{e}");
                1.1 * reach
            }
        };
        if request > ACCURACY_RANGE.1 {
            continue;
        }
        let (p, estimate) = for_multipoles_forced(request, carried, 150, &box_lengths, &set)
            .unwrap_or_else(|e| panic!("{set:?} at its reach {request:.2e}: {e}"));
        let kept = [
            set.order.is_none_or(|o| o == p.order),
            set.grid.is_none_or(|g| g == p.grid),
            set.real_cutoff.is_none_or(|r| r == p.real_cutoff),
            set.alpha.is_none_or(|a| a == p.alpha),
        ];
        assert_eq!(kept, [true; 4], "{set:?} gave {p:?}");
        let (measured, _) = multipole_field_errors(&c, p);
        assert!(
            measured <= request,
            "{set:?} at {request:.2e}: measured {measured:.2e}, estimated {estimate:?}, {p:?}"
        );
    }
    assert!(
        accepted >= 4 && refused >= 2,
        "{accepted} accepted, {refused} refused"
    );
}
