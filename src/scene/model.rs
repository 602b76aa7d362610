//! The validated scene: physics objects the runner uses directly. Every value
//! here has passed the checks of [`super::validate()`].

use super::bodies::BodyScene;
use super::record::Record;
use crate::integrators::{IntegratorSpec, RotorState};
use crate::parallel::ThreadCount;
use crate::potential::multipole::mesh_ewald::ForcedMesh;
use crate::potential::{Boundary, ExternalFields, SumMethod};
use crate::rotor::{Inertia, Rotor};
use crate::thermostats::ThermostatSpec;
use crate::units::{Dimension, Units};
use nalgebra::Vector3;

/// The pair interactions of a scene: their boundary and the way a periodic
/// sum is taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interactions {
    /// Open, or a periodic box and its sum.
    pub boundary: Boundary,
    /// The way of summing (the scene's `method`, default automatic).
    pub method: SumMethod,
    /// The mesh Ewald sum's parameters the scene forces (`order`, `grid`,
    /// `real_cutoff`, `alpha`; only with `method = "pme"`).
    pub forced: ForcedMesh,
}

/// A complete, validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name (defaults to "scene").
    pub name: String,
    /// One-line description (may be empty).
    pub description: String,
    /// The rotors, one per site, in the order of the sites (none in a
    /// scene of bodies).
    pub rotors: Vec<Rotor>,
    /// The moving bodies of a scene of bodies (`None` for rotors).
    pub bodies: Option<BodyScene>,
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
    /// The unit system of the scene's numbers (the engine's inside are
    /// converted at load, [`crate::units`]).
    pub units: Units,
    /// Time step in the scene's units (> 0; fs in real units): the engine
    /// steps by [`Scene::engine_dt`].
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

    /// The time step in the engine's units.
    pub fn engine_dt(&self) -> f64 {
        self.units.to_internal(self.dt, Dimension::Time)
    }

    /// The moments of inertia, one per rotor.
    pub fn inertia(&self) -> Vec<Inertia> {
        self.rotors.iter().map(|r| r.inertia).collect()
    }
}
