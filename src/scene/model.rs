//! The validated scene: typed objects the runner uses directly. Every value
//! here has passed the checks of [`super::validate`].

use crate::integrators::RotorState;
use crate::rotor::Rotor;
use nalgebra::{Matrix3, Vector3};

/// A complete, validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name (defaults to "scene").
    pub name: String,
    /// One-line description (may be empty).
    pub description: String,
    /// The rotors, one per site, in the order of the sites.
    pub rotors: Vec<Rotor>,
    /// Side lengths of the periodic box, when the boundary is periodic.
    pub box_lengths: Option<Vector3<f64>>,
    /// Pair interactions, if any.
    pub interactions: Option<Interactions>,
    /// External fields (both absent means none).
    pub fields: Fields,
    /// Initial orientations and body angular velocities, one per rotor.
    pub initial: Vec<RotorState>,
    /// The random seed that generated `initial`, if it was random.
    pub seed: Option<u64>,
    /// The integrator and its options.
    pub integrator: IntegratorChoice,
    /// Time step (reduced time units, > 0).
    pub dt: f64,
    /// Number of steps (>= 1).
    pub steps: u64,
    /// What to record.
    pub record: Record,
}

/// The pair terms between body multipoles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Terms {
    pub dipole_dipole: bool,
    pub dipole_quadrupole: bool,
    pub quadrupole_quadrupole: bool,
}

/// Pair interactions: which terms, and the boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interactions {
    pub terms: Terms,
    pub boundary: BoundaryChoice,
}

/// Open boundaries (all pairs) or periodic ones (every image inside a
/// spherical cutoff: see [`crate::potential::Boundary::Periodic`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoundaryChoice {
    Open,
    /// The box is [`Scene::box_lengths`]; `cutoff` (> 0) may exceed half the
    /// box (several images of a pair, and a rotor's own images, interact).
    Periodic {
        cutoff: f64,
    },
}

/// Uniform external fields, space frame.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Fields {
    /// Electric field `E`, acting on dipoles (`-mu . E`).
    pub uniform: Option<Vector3<f64>>,
    /// Field gradient `dE_i/dx_j` (symmetric), acting on quadrupoles.
    pub gradient: Option<Matrix3<f64>>,
}

/// The first corrector coefficient of scheme B.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GearBC0 {
    /// 3/16, for second-order equations whose right-hand side depends on `Q'` (default).
    ThreeSixteenths,
    /// 3/20, the value for position-only right-hand sides.
    ThreeTwentieths,
}

/// How the Gear schemes set the higher derivatives at t = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GearStartup {
    /// Consistent with the equations of motion (default).
    Consistent,
    /// Zeros (the naive start).
    Zeros,
}

/// How the splitting methods rotate spherical tops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SphericalTopRotation {
    /// The exact flow (default).
    Exact,
    /// The sweep about body axes used for every other top (as LAMMPS).
    Split,
}

/// The integrator named in the scene, with its options resolved to values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IntegratorChoice {
    /// Scheme A (coupled first-order Gear pair).
    GearA {
        renormalise: bool,
        startup: GearStartup,
    },
    /// Scheme B (second-order Gear on `Q`) and its switches.
    GearB {
        c0: GearBC0,
        project_torque: bool,
        project_velocity: bool,
        renormalise: bool,
        correct_higher_derivatives: bool,
        startup: GearStartup,
    },
    /// NO_SQUISH with `substeps` free-rotation sub-steps.
    NoSquish {
        substeps: u32,
        spherical_tops: SphericalTopRotation,
    },
    /// The Dullweber-Leimkuhler-McLachlan splitting.
    Dlm {
        spherical_tops: SphericalTopRotation,
    },
    /// The Richardson-iterated quaternion update of LAMMPS.
    Richardson,
}

impl IntegratorChoice {
    /// The name used in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            IntegratorChoice::GearA { .. } => "gear_a",
            IntegratorChoice::GearB { .. } => "gear_b",
            IntegratorChoice::NoSquish { .. } => "no_squish",
            IntegratorChoice::Dlm { .. } => "dlm",
            IntegratorChoice::Richardson => "richardson",
        }
    }
}

/// A scalar observable; per-rotor diagnostics are reduced to their largest
/// magnitude over the rotors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `K = 1/2 sum w_b . I w_b`.
    KineticEnergy,
    /// `V`.
    PotentialEnergy,
    /// `K + V`.
    TotalEnergy,
    /// `(E - E_0) / s` with the scale `s` of [`crate::run::energy_scale`].
    EnergyError,
    /// Rotational temperature `2 K / (3 n)`.
    Temperature,
    /// `max_i ||Q_i| - 1|`.
    NormError,
    /// `max_i |Q_i . Q_i'|` (zeroth component of eq 15a).
    QDotQ,
    /// `max_i |Q_i . N_i|` (zeroth component of eq 15b; scheme B only).
    QDotN,
}

impl Quantity {
    /// Every quantity, in the order of [`Quantity::name`]'s documentation.
    pub const ALL: [Quantity; 8] = [
        Quantity::KineticEnergy,
        Quantity::PotentialEnergy,
        Quantity::TotalEnergy,
        Quantity::EnergyError,
        Quantity::Temperature,
        Quantity::NormError,
        Quantity::QDotQ,
        Quantity::QDotN,
    ];

    /// The name used in scene files and as the CSV column header.
    pub fn name(&self) -> &'static str {
        match self {
            Quantity::KineticEnergy => "kinetic_energy",
            Quantity::PotentialEnergy => "potential_energy",
            Quantity::TotalEnergy => "total_energy",
            Quantity::EnergyError => "energy_error",
            Quantity::Temperature => "temperature",
            Quantity::NormError => "norm_error",
            Quantity::QDotQ => "q_dot_q",
            Quantity::QDotN => "q_dot_n",
        }
    }
}

/// A table of scalar observables sampled every `every` steps (CSV).
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// File stem and key of the table (`[A-Za-z0-9_-]+`, unique).
    pub name: String,
    /// Sampling interval in steps (>= 1); step 0 is always sampled.
    pub every: u64,
    /// The columns after `step` and `time`.
    pub quantities: Vec<Quantity>,
}

/// Trajectory frames: rotor centres and markers along the body axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrajectorySpec {
    /// Frame interval in steps (>= 1).
    pub every: u64,
    /// Distance of the body-axis markers from the centre (length units, > 0).
    pub marker_length: f64,
}

/// Everything the scene asks to record.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Record {
    pub series: Vec<Series>,
    pub trajectory: Option<TrajectorySpec>,
    /// Checkpoint interval in steps, if any.
    pub checkpoint_every: Option<u64>,
    /// Stop when `|energy_error|` exceeds this (needs energies at check steps).
    pub energy_error_threshold: Option<f64>,
    /// Interval of the blow-up checks in steps (default 100).
    pub check_every: u64,
}
