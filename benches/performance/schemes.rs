//! The schemes compared: Allen's A, B with its correction variants, and the
//! baselines, as the scene choices a user would write.

use quatrot::integrators::{
    DlmOptions, FirstCorrector, GearAOptions, GearBOptions, IntegratorSpec, NoSquishOptions,
    RichardsonOptions,
};

/// A labelled integrator choice.
#[derive(Clone, Copy, Debug)]
pub struct Scheme {
    pub label: &'static str,
    pub choice: IntegratorSpec,
}

fn gear_b(
    c0: FirstCorrector,
    projections: bool,
    correct_higher_derivatives: bool,
) -> IntegratorSpec {
    IntegratorSpec::GearB(GearBOptions {
        c0,
        project_torque: projections,
        project_velocity: projections,
        renormalise: projections,
        correct_higher_derivatives,
        ..GearBOptions::default()
    })
}

/// Every scheme of the benchmark, in plotting order.
pub fn all() -> Vec<Scheme> {
    use FirstCorrector::{PositionOnly, VelocityDependent};
    vec![
        Scheme {
            label: "A",
            choice: IntegratorSpec::GearA(GearAOptions::default()),
        },
        Scheme {
            label: "B",
            choice: gear_b(VelocityDependent, true, false),
        },
        Scheme {
            label: "B c0=3/20",
            choice: gear_b(PositionOnly, true, false),
        },
        Scheme {
            label: "B +higher",
            choice: gear_b(VelocityDependent, true, true),
        },
        Scheme {
            label: "B bare",
            choice: gear_b(VelocityDependent, false, false),
        },
        Scheme {
            label: "NO_SQUISH",
            choice: IntegratorSpec::NoSquish(NoSquishOptions::default()),
        },
        Scheme {
            label: "NO_SQUISH x10",
            choice: IntegratorSpec::NoSquish(NoSquishOptions {
                substeps: NoSquishOptions::SUBSTEPS_DL_POLY,
                ..NoSquishOptions::default()
            }),
        },
        Scheme {
            label: "DLM",
            choice: IntegratorSpec::Dlm(DlmOptions::default()),
        },
        Scheme {
            label: "Richardson",
            choice: IntegratorSpec::Richardson(RichardsonOptions {}),
        },
    ]
}
