//! The validated scene: physics objects the runner uses directly. Every value
//! here has passed the checks of [`super::validate()`].

use super::record::Record;
use crate::integrators::{IntegratorSpec, RotorState};
use crate::parallel::ThreadCount;
use crate::potential::{Boundary, ExternalFields, SumMethod};
use crate::rotor::{Inertia, Rotor};
use crate::thermostats::ThermostatSpec;
use nalgebra::Vector3;

/// The pair interactions of a scene: their boundary and the way a periodic
/// sum is taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interactions {
    /// Open, or a periodic box and its sum.
    pub boundary: Boundary,
    /// The way of summing (the scene's `method`, default automatic).
    pub method: SumMethod,
}

/// A complete, validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name (defaults to "scene").
    pub name: String,
    /// One-line description (may be empty).
    pub description: String,
    /// The rotors, one per site, in the order of the sites.
    pub rotors: Vec<Rotor>,
    /// The pair interactions between the rotors' multipoles; `None` when
    /// they do not interact.
    pub interactions: Option<Interactions>,
    /// External fields (both absent means none).
    pub fields: ExternalFields,
    /// Initial orientations and body angular velocities, one per rotor.
    pub initial: Vec<RotorState>,
    /// The random seed that generated `initial`, if it was random.
    pub seed: Option<u64>,
    /// The integrator and its options.
    pub integrator: IntegratorSpec,
    /// The thermostat (`None`: constant energy), with its seed resolved.
    pub thermostat: Option<ThermostatSpec>,
    /// Time step (reduced time units, > 0).
    pub dt: f64,
    /// Number of steps (>= 1).
    pub steps: u64,
    /// The threads of the run (`run.threads`).
    pub threads: ThreadCount,
    /// What to record.
    pub record: Record,
}

impl Scene {
    /// Side lengths of the periodic box, when the boundary is periodic.
    pub fn box_lengths(&self) -> Option<Vector3<f64>> {
        match self.interactions.map(|i| i.boundary) {
            Some(Boundary::Periodic { box_lengths, .. }) => Some(box_lengths),
            _ => None,
        }
    }

    /// The moments of inertia, one per rotor.
    pub fn inertia(&self) -> Vec<Inertia> {
        self.rotors.iter().map(|r| r.inertia).collect()
    }
}
