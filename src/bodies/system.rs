//! A system of rigid bodies: their types, their state, the space and the
//! interactions between sites of different bodies.

use super::body_type::BodyType;
use super::electrostatics::{CutoffSum, Electrostatics, SiteMultipoles, SiteResponse};
use super::electrostatics_ewald::{BodyEwald, EwaldOptions};
use super::electrostatics_shifted::ElectrostaticTruncation;
use super::lennard_jones::{LennardJonesOptions, LennardJonesTerm};
use super::neighbours::NeighbourList;
use super::pair_pass::PairPass;
use super::site::LennardJones;
use super::space::Space;
use crate::checks::{each, finite, non_negative, orientation, InputError};
use crate::potential::multipole::mesh_ewald::{Carried, MeshEstimate, MeshParameters};
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// The state of one body.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Index of its type.
    pub kind: usize,
    /// The centre, space frame (wrapped into a periodic box at each
    /// neighbour-list build).
    pub position: Vector3<f64>,
    /// Box lengths crossed by the centre's wrapping (unwrapped position
    /// `position + image * L`).
    pub image: [i64; 3],
    /// The centre's velocity.
    pub velocity: Vector3<f64>,
    /// Unit orientation, body (principal) frame to space.
    pub orientation: Quat,
    /// Angular momentum, body frame (zero about a linear body's axis).
    pub angular_momentum_body: Vector3<f64>,
}

/// The interactions' options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InteractionOptions {
    /// Lennard-Jones (required when a site has Lennard-Jones parameters).
    pub lennard_jones: Option<LennardJonesOptions>,
    /// How charges, dipoles and quadrupoles are summed (required when a
    /// site has one).
    pub electrostatics: Option<ElectrostaticsOptions>,
    /// The neighbour lists' skin (length, >= 0; 0.3 is LAMMPS's default in
    /// LJ units).
    pub skin: f64,
}

/// The electrostatics of bodies: the one choice of method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ElectrostaticsOptions {
    /// The pair terms within a cutoff (> 0), plain or shifted-force,
    /// [`CutoffSum`].
    Cutoff(f64, ElectrostaticTruncation),
    /// The Ewald sum (periodic boxes only), [`BodyEwald`].
    Ewald(EwaldOptions),
}

/// Bodies, their types, the space and the interactions.
#[derive(Debug)]
pub struct BodySystem {
    /// The body types.
    pub types: Vec<BodyType>,
    /// The bodies.
    pub bodies: Vec<Body>,
    /// The space.
    pub space: Space,
    /// Whether the dynamics keeps the total momentum (true unless a
    /// thermostat acts on each centre on its own): `T_trans` then counts
    /// `3N - 3` degrees of freedom, else `3N`.
    pub keeps_momentum: bool,
    pub(super) lennard_jones: Option<LennardJonesTerm>,
    pub(super) electrostatics: Option<Box<dyn Electrostatics>>,
    pub(super) neighbours: NeighbourList,
    /// Per site (bodies in order, each body's sites in order): its body
    /// and its Lennard-Jones parameters' index.
    pub(super) site_body: Vec<u32>,
    pub(super) lj_kind: Vec<Option<u32>>,
    /// Sites of each Lennard-Jones parameter set (the tail corrections).
    pub(super) lj_counts: Vec<usize>,
    pub(super) scratch: Scratch,
}

/// Buffers reused by every evaluation.
#[derive(Debug, Default)]
pub(super) struct Scratch {
    pub multipoles: SiteMultipoles,
    pub response: SiteResponse,
    pub pairs: PairPass,
    /// Site offsets from their centres, space frame.
    pub offsets: Vec<Vector3<f64>>,
}

impl BodySystem {
    /// The system; errors name the field (`bodies[3].orientation`,
    /// `electrostatics.cutoff`, `electrostatics.truncation`,
    /// `electrostatics.accuracy`,
    /// `box_lengths[0]`).
    pub fn new(
        types: Vec<BodyType>,
        bodies: Vec<Body>,
        space: Space,
        options: &InteractionOptions,
    ) -> Result<BodySystem, InputError> {
        let mut bodies = bodies;
        for (i, body) in bodies.iter_mut().enumerate() {
            check_body(body, &types).map_err(|e| e.at(&format!("bodies[{i}]")))?;
        }
        let (mut kinds, mut lj_kind, mut site_body) = (vec![], vec![], vec![]);
        let (mut lj_counts, mut carried) = (Vec::new(), Carried::default());
        for kind in &types {
            for site in &kind.sites {
                if let Some(lj) = site.lennard_jones {
                    if !kinds.contains(&lj) {
                        kinds.push(lj);
                    }
                }
                carried.charges |= site.charge != 0.0;
                carried.dipoles |= site.dipole.is_some();
                carried.quadrupoles |= site.quadrupole.is_some();
            }
        }
        for (b, body) in bodies.iter().enumerate() {
            for site in &types[body.kind].sites {
                let index = site.lennard_jones.map(|lj| lj_index(&kinds, &lj));
                if let Some(a) = index {
                    lj_counts.resize(kinds.len(), 0);
                    lj_counts[a as usize] += 1;
                }
                lj_kind.push(index);
                site_body.push(b as u32);
            }
        }
        let lennard_jones = match (options.lennard_jones, kinds.is_empty()) {
            (Some(o), false) => {
                Some(LennardJonesTerm::new(o, kinds).map_err(|e| e.at("lennard_jones"))?)
            }
            (None, false) => return Err(required("lennard_jones", "Lennard-Jones parameters")),
            (_, true) => None,
        };
        let skin = non_negative(options.skin).map_err(|e| e.at("skin"))?;
        let electrostatics = electrostatics(options, carried, &site_body, (&space, skin))?;
        let neighbours = neighbour_list(
            lennard_jones.as_ref(),
            electrostatics.as_deref(),
            &lj_kind,
            skin,
        )?;
        space.check(neighbours.reach())?;
        Ok(BodySystem {
            types,
            bodies,
            space,
            keeps_momentum: true,
            lennard_jones,
            electrostatics,
            neighbours,
            site_body,
            lj_kind,
            lj_counts,
            scratch: Scratch {
                multipoles: SiteMultipoles {
                    carried,
                    ..SiteMultipoles::default()
                },
                ..Scratch::default()
            },
        })
    }

    /// The number of sites.
    pub fn sites(&self) -> usize {
        self.site_body.len()
    }

    /// The parameters and estimated errors of the Ewald sum (`None` for a
    /// cutoff sum or no electrostatics).
    pub fn mesh_parameters(&self) -> Option<(MeshParameters, MeshEstimate)> {
        self.electrostatics.as_ref()?.mesh_parameters()
    }

    /// The electrostatic method (`None` without electrostatics): its
    /// parameters and, for `method = "auto"`, its choice.
    pub fn electrostatic_sum(&self) -> Option<&dyn Electrostatics> {
        self.electrostatics.as_deref()
    }

    /// How many times the neighbour list was built.
    pub fn neighbour_builds(&self) -> u64 {
        self.neighbours.builds()
    }

    /// The translational kinetic energy `sum m v^2 / 2`.
    pub fn translational_kinetic_energy(&self) -> f64 {
        let each = |b: &Body| 0.5 * self.types[b.kind].mass * b.velocity.norm_squared();
        self.bodies.iter().map(each).sum()
    }

    /// The rotational kinetic energy `sum_k L_k^2 / (2 I_k)` (axes with a
    /// zero moment carry none).
    pub fn rotational_kinetic_energy(&self) -> f64 {
        let each = |b: &Body| {
            let moments = &self.types[b.kind].moments;
            (0..3)
                .filter(|&k| moments[k] > 0.0)
                .map(|k| 0.5 * b.angular_momentum_body[k].powi(2) / moments[k])
                .sum::<f64>()
        };
        self.bodies.iter().map(each).sum()
    }

    /// The total linear momentum `sum m v`.
    pub fn linear_momentum(&self) -> Vector3<f64> {
        self.bodies
            .iter()
            .map(|b| b.velocity * self.types[b.kind].mass)
            .sum()
    }

    /// The total angular momentum about the origin, `sum (R x m v + L_s)`
    /// (unwrapped centres).
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.bodies
            .iter()
            .map(|b| {
                let centre = self.unwrapped(b);
                centre.cross(&(b.velocity * self.types[b.kind].mass))
                    + b.orientation.body_to_space(&b.angular_momentum_body)
            })
            .sum()
    }

    /// A body's centre with its image counts undone.
    pub fn unwrapped(&self, body: &Body) -> Vector3<f64> {
        match self.space {
            Space::Open => body.position,
            Space::Periodic(l) => {
                body.position + Vector3::from_fn(|k, _| body.image[k] as f64 * l[k])
            }
        }
    }
}

/// The index of `lj` in `kinds` (it is there: collected above).
fn lj_index(kinds: &[LennardJones], lj: &LennardJones) -> u32 {
    kinds.iter().position(|k| k == lj).unwrap_or(0) as u32
}

fn required(field: &str, what: &str) -> InputError {
    InputError::new(field, format!("required when sites carry {what}"))
}

/// One body's values: a known type, finite vectors, no angular momentum
/// about a linear body's axis, a non-zero orientation (normalised here).
fn check_body(body: &mut Body, types: &[BodyType]) -> Result<(), InputError> {
    let Some(kind) = types.get(body.kind) else {
        return Err(InputError::new(
            "kind",
            format!(
                "must be below the number of body types ({}), got {}",
                types.len(),
                body.kind
            ),
        ));
    };
    each(body.position.as_slice(), finite).map_err(|e| e.at("position"))?;
    each(body.velocity.as_slice(), finite).map_err(|e| e.at("velocity"))?;
    each(body.angular_momentum_body.as_slice(), finite)
        .map_err(|e| e.at("angular_momentum_body"))?;
    if let Some(k) =
        (0..3).find(|&k| kind.moments[k] == 0.0 && body.angular_momentum_body[k] != 0.0)
    {
        return Err(InputError::new(
            format!("angular_momentum_body[{k}]"),
            format!(
                "must be 0 about a linear body's axis, got {}",
                body.angular_momentum_body[k]
            ),
        ));
    }
    body.orientation = orientation(&body.orientation).map_err(|e| e.at("orientation"))?;
    Ok(())
}

/// The electrostatic method `options` choose for sites carrying `carried`
/// (none when no site carries a multipole), errors naming the field.
fn electrostatics(
    options: &InteractionOptions,
    carried: Carried,
    site_body: &[u32],
    (space, skin): (&Space, f64),
) -> Result<Option<Box<dyn Electrostatics>>, InputError> {
    let electrostatic = carried.charges || carried.dipoles || carried.quadrupoles;
    Ok(match (options.electrostatics, electrostatic) {
        (Some(ElectrostaticsOptions::Cutoff(c, truncation)), true) => Some(Box::new(
            CutoffSum::new(c, truncation, carried).map_err(|e| e.at("electrostatics"))?,
        )),
        (Some(ElectrostaticsOptions::Ewald(o)), true) => {
            let Space::Periodic(box_lengths) = *space else {
                return Err(InputError::new(
                    "electrostatics.kind",
                    "the Ewald sum needs a periodic box",
                ));
            };
            Some(Box::new(
                BodyEwald::new(&o, carried, site_body, (box_lengths, skin)).map_err(|e| {
                    // A box the cutoff does not fit is the box's error.
                    if e.path == "box_lengths" {
                        e
                    } else {
                        e.at("electrostatics")
                    }
                })?,
            ))
        }
        (None, true) => {
            return Err(required(
                "electrostatics",
                "charges, dipoles or quadrupoles",
            ))
        }
        (_, false) => None,
    })
}

/// The neighbour list of the sites: its reach the longest cutoff that reads
/// it plus `skin`; the full view only for an electrostatic sum outside the
/// pair pass that reads the list; only the Lennard-Jones sites (`lj_kind`)
/// when no electrostatic sum reads it.
fn neighbour_list(
    lennard_jones: Option<&LennardJonesTerm>,
    electrostatics: Option<&dyn Electrostatics>,
    lj_kind: &[Option<u32>],
    skin: f64,
) -> Result<NeighbourList, InputError> {
    let cutoff = [
        lennard_jones.map(|t| t.cutoff()),
        electrostatics.and_then(|e| e.pair_cutoff()),
    ]
    .into_iter()
    .flatten()
    .fold(0.0, f64::max);
    // Bodies without interacting sites still get a (never used) list.
    let neighbours = NeighbourList::new(if cutoff > 0.0 { cutoff } else { 1.0 }, skin)?;
    // Only an electrostatic sum outside the pair pass that reads the list reads the full view.
    let neighbours = match electrostatics {
        Some(e) if e.cutoff_pairs().is_none() && e.pair_cutoff().is_some() => neighbours,
        _ => neighbours.half_only(),
    };
    // Only the Lennard-Jones sites when no electrostatic sum reads the list
    // (none, or a mesh sum that finds its pairs itself: rigid water's hydrogens).
    let reads =
        electrostatics.is_some_and(|e| e.cutoff_pairs().is_some() || e.pair_cutoff().is_some());
    let neighbours = match (reads, lj_kind.iter().any(Option::is_none)) {
        (false, true) => neighbours.listing(lj_kind.iter().map(Option::is_some).collect()),
        _ => neighbours,
    };
    Ok(neighbours)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The neighbour list keeps its full view only for an electrostatic sum
    /// that reads it outside the pair pass: a cutoff sum of quadrupoles
    /// (summed over the full view) has it, a cutoff sum of dipoles (summed
    /// in the pair pass, over the half list) has none; both list the one
    /// pair of two sites 1 apart once in the half list, although only the
    /// first has Lennard-Jones (a list of the Lennard-Jones sites alone is
    /// for sums that do not read it).
    #[test]
    fn the_list_holds_what_the_electrostatic_sum_reads() {
        let sites = [Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)];
        for (quadrupoles, full_view) in [(true, 1), (false, 0)] {
            let carried = Carried {
                charges: false,
                dipoles: true,
                quadrupoles,
            };
            let sum = CutoffSum::new(2.0, ElectrostaticTruncation::Plain, carried).unwrap();
            let mut list = neighbour_list(None, Some(&sum), &[Some(0), None], 0.5).unwrap();
            list.build(&sites, &[0, 1], &Space::Open);
            assert_eq!(
                list.separations(0, &sites).count(),
                full_view,
                "quadrupoles {quadrupoles}"
            );
            assert_eq!(list.half_pairs(0, &sites).count(), 1);
        }
    }
}
