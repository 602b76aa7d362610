//! [`MeshSum`]: the smooth PME sum ([`super::mesh_ewald`]) behind a
//! [`super::MultipolePotential`], giving the fields of the rotors'
//! space-frame multipoles at their fixed sites.

use super::kernels::{Lanes, MultipoleKind, SiteFields, SpaceMultipoles};
use super::mesh_ewald::{
    for_multipoles_forced, Carried, ForcedMesh, MeshEstimate, MeshEwald, MeshParameters,
    SiteResponse, Sources,
};
use super::{Accuracy, PotentialError, Surface};
use crate::checks::num;
use nalgebra::{Matrix3, Vector3};
use std::sync::{Mutex, PoisonError};

/// The mesh sum and the buffers of one evaluation, behind a lock: an
/// evaluation writes them, and the potential evaluates through `&self`.
#[derive(Clone, Debug)]
struct Buffers {
    sum: MeshEwald,
    response: SiteResponse,
    dipoles: Vec<Vector3<f64>>,
    quadrupoles: Vec<Matrix3<f64>>,
}

/// The smooth PME sum of fixed sites, its parameters chosen for an accuracy
/// ([`for_multipoles_forced`]).
#[derive(Debug)]
pub(crate) struct MeshSum {
    positions: Vec<Vector3<f64>>,
    estimate: MeshEstimate,
    buffers: Mutex<Buffers>,
}

impl Clone for MeshSum {
    fn clone(&self) -> Self {
        MeshSum {
            positions: self.positions.clone(),
            estimate: self.estimate,
            buffers: Mutex::new(self.lock().clone()),
        }
    }
}

impl MeshSum {
    /// The parameters of the sum of `sites` sites in `box_lengths` carrying
    /// `(dipoles, quadrupoles)` at `accuracy`, those `forced` as given
    /// ([`for_multipoles_forced`]); errors name the option (`accuracy`,
    /// `box_lengths`, the forced ones).
    pub fn choose(
        sites: usize,
        box_lengths: &Vector3<f64>,
        (accuracy, forced): (Accuracy, &ForcedMesh),
        (dipoles, quadrupoles): (bool, bool),
    ) -> Result<(MeshParameters, MeshEstimate), PotentialError> {
        let carried = Carried {
            charges: false,
            dipoles,
            quadrupoles,
        };
        for_multipoles_forced(accuracy.get(), carried, sites, box_lengths, forced)
    }

    /// The sum of `sites` in `box_lengths` with `parameters` chosen for
    /// `accuracy` ([`Self::choose`]), carrying `(dipoles, quadrupoles)`;
    /// a refusal of its size names `accuracy`.
    pub fn new(
        sites: &[Vector3<f64>],
        box_lengths: Vector3<f64>,
        (accuracy, surface): (Accuracy, Surface),
        (parameters, estimate): (MeshParameters, MeshEstimate),
        (dipoles, quadrupoles): (bool, bool),
    ) -> Result<MeshSum, PotentialError> {
        let n = sites.len();
        // The mesh was chosen for the accuracy: its size is the accuracy's.
        let sum = MeshEwald::new(n, box_lengths, parameters, surface).map_err(|e| {
            PotentialError::new(
                "accuracy",
                format!("{}: {}", num(accuracy.get()), e.message),
            )
        })?;
        Ok(MeshSum {
            positions: sites.to_vec(),
            estimate,
            buffers: Mutex::new(Buffers {
                sum,
                response: SiteResponse::zeros(n),
                dipoles: vec![Vector3::zeros(); if dipoles { n } else { 0 }],
                quadrupoles: vec![Matrix3::zeros(); if quadrupoles { n } else { 0 }],
            }),
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Buffers> {
        // A panic elsewhere leaves the buffers valid: each evaluation rewrites them.
        self.buffers.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The parameters chosen and the errors estimated for them.
    pub fn parameters(&self) -> (MeshParameters, MeshEstimate) {
        (self.lock().sum.parameters(), self.estimate)
    }

    /// The fields `E` and `W` of the space-frame `multipoles` at the sites.
    pub fn fields<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles) -> SiteFields {
        let mut guard = self.lock();
        let Buffers {
            sum,
            response,
            dipoles,
            quadrupoles,
        } = &mut *guard;
        if K::DIPOLES {
            for (mu, lanes) in dipoles.iter_mut().zip(&multipoles.dipoles) {
                *mu = Vector3::new(lanes[0], lanes[1], lanes[2]);
            }
        }
        if K::QUADRUPOLES {
            quadrupoles.copy_from_slice(&multipoles.quadrupoles);
        }
        let sources = Sources {
            positions: &self.positions,
            charges: None,
            dipoles: K::DIPOLES.then_some(dipoles.as_slice()),
            quadrupoles: K::QUADRUPOLES.then_some(quadrupoles.as_slice()),
        };
        sum.evaluate(&sources, response)
            .expect("the sites were checked finite and the buffers sized at construction");
        let mut fields = SiteFields::zeros::<K>(self.positions.len());
        if K::DIPOLES {
            for (lanes, e) in fields.field.iter_mut().zip(&response.field) {
                *lanes = Lanes([e.x, e.y, e.z, 0.0]);
            }
        }
        if K::QUADRUPOLES {
            fields
                .quadrupole_conjugate
                .copy_from_slice(&response.quadrupole_conjugate);
        }
        fields
    }
}
