//! Checkpoint files: the integrator's complete state at a step (a body
//! run's: `BodyIntegrator::checkpoint`), stored as the
//! bit patterns of its floats (JSON; serde_json's default float parsing is
//! not correctly rounded, so no float is stored as a decimal), with the
//! identity of the run it belongs to and a checksum.
//!
//! * The identity ([`Identity`]) is what a restart must share with the run
//!   that wrote the checkpoint: fingerprints of the rotors (sites, inertia,
//!   multipoles), of the interactions (boundary, box, sum) and of the
//!   external fields, the integrator and the thermostat with all their
//!   options (the thermostat's seed too), `dt` bit for bit (the one
//!   comparison of `dt` on a restart),
//!   the number of rotors and the format version; for a scene of bodies
//!   also the number of bodies and fingerprints of the body types (with
//!   each body's type) and of the box and interactions. The initial state, the
//!   run length and what is recorded may differ (a restart may run longer).
//!   A restart with anything else is refused, saying what differs.
//! * The checksum (64-bit FNV-1a of the file's JSON with an empty checksum
//!   field) catches damage and edits; non-finite state values and a
//!   non-finite energy reference are refused as well.

use super::error::RunError;
use super::folder::write_atomically;
use crate::potential::{Boundary, ExternalFields, PeriodicSum, Surface};
use crate::rotor::{Inertia, Rotor};
use crate::scene::Scene;
use crate::simulation::{CheckpointSink, EnergyReference};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag written in every checkpoint.
const FORMAT: &str = "quatrot-checkpoint-2";

/// 64-bit FNV-1a, over the bytes given in order (a fingerprint, not a
/// cryptographic hash: it detects damage and mismatches, not forgery).
#[derive(Clone, Copy, Debug)]
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, bytes: &[u8]) -> &mut Self {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        self
    }
    fn u64(&mut self, x: u64) -> &mut Self {
        self.bytes(&x.to_le_bytes())
    }
    /// `x` bit for bit (`-0.0` and `0.0` are one value).
    fn f64(&mut self, x: f64) -> &mut Self {
        self.u64((x + 0.0).to_bits())
    }
    fn f64s(&mut self, xs: &[f64]) -> &mut Self {
        xs.iter().for_each(|&x| {
            let _ = self.f64(x);
        });
        self
    }
    /// A tag, then the values if present.
    fn optional(&mut self, xs: Option<&[f64]>) -> &mut Self {
        match xs {
            None => self.u64(0),
            Some(xs) => self.u64(1).f64s(xs),
        }
    }
    fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

/// What a checkpoint belongs to (see the module doc).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Identity {
    /// Fingerprint of the rotors' sites, inertia and body multipoles.
    pub rotors: String,
    /// Fingerprint of the interactions (none, open, or the periodic box and sum).
    pub interactions: String,
    /// Fingerprint of the external fields.
    pub fields: String,
    /// The integrator and all its options, as the scene's JSON.
    pub integrator: String,
    /// The thermostat and all its options (seed included: the checkpoint
    /// holds the position in its noise stream) as the scene's JSON; `None`
    /// without one.
    pub thermostat: Option<String>,
    /// `dt.to_bits()`.
    pub dt_bits: u64,
    /// The number of rotors.
    pub rotor_count: usize,
    /// A scene of bodies: the number of bodies (`None`, and not written,
    /// for rotors).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_count: Option<usize>,
    /// A scene of bodies: fingerprint of the body types (mass, inertia,
    /// sites with all their parameters) and of each body's type.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_types: Option<String>,
    /// A scene of bodies: fingerprint of the space (open, or the box) and
    /// the interactions (Lennard-Jones, electrostatics, skin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_interactions: Option<String>,
}

impl Identity {
    /// The identity of a run of `scene`.
    pub fn of(scene: &Scene) -> Identity {
        Identity {
            rotors: rotors_fingerprint(&scene.rotors),
            interactions: interactions_fingerprint(
                scene.interactions.as_ref().map(|i| &i.boundary),
            ),
            fields: fields_fingerprint(&scene.fields),
            integrator: serde_json::to_string(&scene.integrator).unwrap_or_default(),
            thermostat: scene
                .thermostat
                .as_ref()
                .map(|t| serde_json::to_string(t).unwrap_or_default()),
            dt_bits: scene.dt.to_bits(),
            rotor_count: scene.rotors.len(),
            body_count: scene.bodies.as_ref().map(|b| b.bodies.len()),
            body_types: scene.bodies.as_ref().map(|b| {
                let kinds: Vec<usize> = b.bodies.iter().map(|b| b.kind).collect();
                debug_fingerprint(&(&b.types, kinds))
            }),
            body_interactions: scene
                .bodies
                .as_ref()
                .map(|b| debug_fingerprint(&(b.space, b.interactions))),
        }
    }

    /// What differs between the identity of the scene (`self`) and the
    /// checkpoint's, in words; `None` when they are equal.
    fn difference(&self, saved: &Identity) -> Option<String> {
        let kind = |i: &Identity| match i.body_count {
            Some(_) => "bodies",
            None => "rotors",
        };
        if kind(self) != kind(saved) {
            return Some(format!(
                "the scene is of {} but the checkpoint of {}",
                kind(self),
                kind(saved)
            ));
        }
        if self.body_count != saved.body_count {
            return Some(format!(
                "the number of bodies is {} in the scene but {} in the checkpoint",
                self.body_count.unwrap_or_default(),
                saved.body_count.unwrap_or_default()
            ));
        }
        if self.rotor_count != saved.rotor_count {
            return Some(format!(
                "the number of rotors is {} in the scene but {} in the checkpoint",
                self.rotor_count, saved.rotor_count
            ));
        }
        if self.integrator != saved.integrator {
            return Some(format!(
                "the integrator is {} in the scene but {} in the checkpoint",
                self.integrator, saved.integrator
            ));
        }
        if self.thermostat != saved.thermostat {
            return Some(thermostat_difference(
                self.thermostat.as_deref(),
                saved.thermostat.as_deref(),
            ));
        }
        if self.dt_bits != saved.dt_bits {
            return Some(format!(
                "dt is {:e} in the scene but {:e} in the checkpoint",
                f64::from_bits(self.dt_bits),
                f64::from_bits(saved.dt_bits)
            ));
        }
        [
            (
                self.rotors != saved.rotors,
                "the rotors (sites, inertia, multipoles)",
            ),
            (
                self.interactions != saved.interactions,
                "the interactions (boundary, box, sum)",
            ),
            (self.fields != saved.fields, "the external fields"),
            (
                self.body_types != saved.body_types,
                "the body types (body_types: mass, inertia, sites) or the bodies' types",
            ),
            (
                self.body_interactions != saved.body_interactions,
                "the box and the interactions of the bodies (bodies.box, body_interactions)",
            ),
        ]
        .into_iter()
        .find(|(differs, _)| *differs)
        .map(|(_, what)| format!("{what} differ from those of the checkpoint's run"))
    }
}

/// The thermostats of the scene and of the checkpoint, which differ: their
/// kinds (`none` without one) when those differ, else their options.
fn thermostat_difference(scene: Option<&str>, saved: Option<&str>) -> String {
    let kind = |t: Option<&str>| {
        t.and_then(|t| serde_json::from_str::<serde_json::Value>(t).ok())
            .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(str::to_string))
            .unwrap_or_else(|| "none".to_string())
    };
    let (here, there) = (kind(scene), kind(saved));
    if here == there {
        format!(
            "the thermostat is {} in the scene but {} in the checkpoint",
            scene.unwrap_or_default(),
            saved.unwrap_or_default()
        )
    } else {
        format!("the thermostat is {here} in the scene but {there} in the checkpoint")
    }
}

/// Fingerprint of a value's `Debug` form, which writes every float as the
/// shortest decimal that reads back to its bits: values differing in any
/// bit differ here (a change of the types' fields changes it too, so a
/// checkpoint is refused by a build whose body types differ in form).
fn debug_fingerprint(value: &impl std::fmt::Debug) -> String {
    Fnv::new().bytes(format!("{value:?}").as_bytes()).hex()
}

fn rotors_fingerprint(rotors: &[Rotor]) -> String {
    let mut h = Fnv::new();
    for r in rotors {
        let _ = h.f64s(r.site.as_slice());
        let _ = match r.inertia {
            Inertia::Spherical(i) => h.u64(0).f64(i),
            Inertia::Principal(m) => h.u64(1).f64s(m.as_slice()),
        };
        let _ = h
            .optional(r.dipole_body.as_ref().map(|d| d.as_slice()))
            .optional(r.quadrupole_body.as_ref().map(|q| q.as_slice()));
    }
    h.hex()
}

fn interactions_fingerprint(boundary: Option<&Boundary>) -> String {
    let mut h = Fnv::new();
    let _ = match boundary {
        None => h.u64(0),
        Some(Boundary::Open) => h.u64(1),
        Some(Boundary::Periodic { box_lengths, sum }) => {
            let _ = h.u64(2).f64s(box_lengths.as_slice());
            match sum {
                PeriodicSum::Cutoff { cutoff } => h.u64(0).f64(*cutoff),
                PeriodicSum::Ewald { accuracy, surface } => {
                    h.u64(1).f64(accuracy.get()).u64(match surface {
                        Surface::Conducting => 0,
                        Surface::Vacuum => 1,
                    })
                }
            }
        }
    };
    h.hex()
}

fn fields_fingerprint(fields: &ExternalFields) -> String {
    let mut h = Fnv::new();
    let _ = h
        .optional(fields.field.as_ref().map(|f| f.as_slice()))
        .optional(fields.field_gradient.as_ref().map(|g| g.as_slice()));
    h.hex()
}

/// The contents of a checkpoint file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Checkpoint {
    /// The format tag, `quatrot-checkpoint-2`.
    pub format: String,
    /// The scene's name (informative: not part of the identity).
    pub scene: String,
    /// What the checkpoint belongs to.
    pub identity: Identity,
    /// The step of the state.
    pub step: u64,
    /// Bits of the reference energy `(total, scale)`, if one was computed.
    pub reference_bits: Option<[u64; 2]>,
    /// `f64::to_bits` of [`crate::integrators::Integrator::checkpoint`].
    pub state_bits: Vec<u64>,
    /// FNV-1a of the file's JSON with this field empty, as 16 hex digits.
    pub checksum: String,
}

impl Checkpoint {
    /// The checksum of the checkpoint's contents.
    fn compute_checksum(&self) -> String {
        let unsummed = Checkpoint {
            checksum: String::new(),
            ..self.clone()
        };
        let text = serde_json::to_string(&unsummed).unwrap_or_default();
        Fnv::new().bytes(text.as_bytes()).hex()
    }

    /// Sets the checksum to that of the contents.
    pub fn seal(&mut self) {
        self.checksum = self.compute_checksum();
    }

    /// Reads a checkpoint file, refusing one that is damaged or edited (its
    /// checksum), of another format, or with non-finite values.
    pub fn read(path: &Path) -> Result<Checkpoint, RunError> {
        let fail = |message: String| RunError::Checkpoint {
            path: path.display().to_string(),
            message,
        };
        let text = std::fs::read_to_string(path).map_err(|e| RunError::io(path, e))?;
        let value: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| fail(format!("not a checkpoint file ({e})")))?;
        let format = value.get("format").and_then(|f| f.as_str()).unwrap_or("");
        if format != FORMAT {
            return Err(fail(format!(
                "format `{}`, expected `{FORMAT}` (checkpoints of other formats cannot be restored)",
                crate::checks::printable(format, 40)
            )));
        }
        let checkpoint: Checkpoint =
            serde_json::from_value(value).map_err(|e| fail(format!("damaged ({e})")))?;
        if checkpoint.checksum != checkpoint.compute_checksum() {
            return Err(fail(
                "damaged or edited: its checksum does not match its contents".to_string(),
            ));
        }
        if checkpoint
            .state_bits
            .iter()
            .any(|&b| !f64::from_bits(b).is_finite())
        {
            return Err(fail("the state holds non-finite values".to_string()));
        }
        if let Some(r) = checkpoint.reference() {
            if !(r.total.is_finite() && r.scale.is_finite() && r.scale > 0.0) {
                return Err(fail(format!(
                    "the energy reference is not finite and positive (total {}, scale {})",
                    r.total, r.scale
                )));
            }
        }
        Ok(checkpoint)
    }

    /// Checks that the checkpoint belongs to a run of `scene`, naming what
    /// differs.
    pub fn check(&self, path: &Path, scene: &Scene) -> Result<(), RunError> {
        match Identity::of(scene).difference(&self.identity) {
            None => Ok(()),
            Some(message) => Err(RunError::Checkpoint {
                path: path.display().to_string(),
                message,
            }),
        }
    }

    /// The reference energy of the run.
    pub fn reference(&self) -> Option<EnergyReference> {
        self.reference_bits.map(|[total, scale]| EnergyReference {
            total: f64::from_bits(total),
            scale: f64::from_bits(scale),
        })
    }

    /// The integrator state.
    pub fn state(&self) -> Vec<f64> {
        self.state_bits.iter().map(|&b| f64::from_bits(b)).collect()
    }
}

/// Writes checkpoints of one run to one file, replacing it atomically (the
/// data on disk before the rename).
#[derive(Clone, Debug)]
pub struct CheckpointWriter {
    /// The checkpoint file.
    pub path: PathBuf,
    /// The scene's name.
    pub scene: String,
    /// What the checkpoints belong to.
    pub identity: Identity,
}

impl CheckpointSink for CheckpointWriter {
    type Error = RunError;

    /// Writes the state at `step` (to a temporary file, then renamed).
    fn write(
        &mut self,
        step: u64,
        state: &[f64],
        reference: Option<EnergyReference>,
    ) -> Result<(), RunError> {
        let mut checkpoint = Checkpoint {
            format: FORMAT.to_string(),
            scene: self.scene.clone(),
            identity: self.identity.clone(),
            step,
            reference_bits: reference.map(|r| [r.total.to_bits(), r.scale.to_bits()]),
            state_bits: state.iter().map(|x| x.to_bits()).collect(),
            checksum: String::new(),
        };
        checkpoint.seal();
        let text = serde_json::to_string(&checkpoint).map_err(|e| RunError::io(&self.path, e))?;
        write_atomically(&self.path, text.as_bytes(), true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FNV-1a of the empty input and of "a" (the published test vectors).
    #[test]
    fn fnv_matches_its_test_vectors() {
        assert_eq!(Fnv::new().hex(), "cbf29ce484222325");
        assert_eq!(Fnv::new().bytes(b"a").hex(), "af63dc4c8601ec8c");
    }
}
