//! The schemes compared: Allen's A, B with its correction variants, and the
//! baselines, as the scene choices a user would write.

use quatrot::scene::{GearBC0, GearStartup, IntegratorChoice, SphericalTopRotation};

/// A labelled integrator choice.
#[derive(Clone, Copy, Debug)]
pub struct Scheme {
    pub label: &'static str,
    pub choice: IntegratorChoice,
}

fn gear_b(c0: GearBC0, projections: bool, correct_higher_derivatives: bool) -> IntegratorChoice {
    IntegratorChoice::GearB {
        c0,
        project_torque: projections,
        project_velocity: projections,
        renormalise: projections,
        correct_higher_derivatives,
        startup: GearStartup::Consistent,
    }
}

/// Every scheme of the benchmark, in plotting order.
pub fn all() -> Vec<Scheme> {
    use GearBC0::{ThreeSixteenths, ThreeTwentieths};
    let exact = SphericalTopRotation::Exact;
    vec![
        Scheme {
            label: "A",
            choice: IntegratorChoice::GearA {
                renormalise: true,
                startup: GearStartup::Consistent,
            },
        },
        Scheme {
            label: "B",
            choice: gear_b(ThreeSixteenths, true, false),
        },
        Scheme {
            label: "B c0=3/20",
            choice: gear_b(ThreeTwentieths, true, false),
        },
        Scheme {
            label: "B +higher",
            choice: gear_b(ThreeSixteenths, true, true),
        },
        Scheme {
            label: "B bare",
            choice: gear_b(ThreeSixteenths, false, false),
        },
        Scheme {
            label: "NO_SQUISH",
            choice: IntegratorChoice::NoSquish {
                substeps: 1,
                spherical_tops: exact,
            },
        },
        Scheme {
            label: "NO_SQUISH x10",
            choice: IntegratorChoice::NoSquish {
                substeps: 10,
                spherical_tops: exact,
            },
        },
        Scheme {
            label: "DLM",
            choice: IntegratorChoice::Dlm {
                spherical_tops: exact,
            },
        },
        Scheme {
            label: "Richardson",
            choice: IntegratorChoice::Richardson,
        },
    ]
}
