//! Generated starts: random non-overlapping centres in a periodic cube at a
//! number density (random sequential insertion) or the sites of a simple
//! cubic or face-centred cubic lattice filling it, uniformly random
//! orientations (or one given orientation on a lattice), and
//! Maxwell-Boltzmann centre velocities (zero total momentum) and angular
//! momenta (`L_k ~ N(0, I_k T)` about each axis with a positive moment) at a
//! temperature.

use super::body_type::BodyType;
use super::space::Space;
use super::system::Body;
use crate::checks::{named_choices, non_negative, num, orientation, positive, InputError};
use crate::quaternion::Quat;
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use std::f64::consts::PI;

/// The largest packing fraction `pi/6 rho closest^3` asked of random
/// sequential insertion (its jamming limit is about 0.38: beyond 0.3 it
/// slows down without bound).
pub const MAX_PACKING: f64 = 0.3;
/// Random trials per body before the insertion gives up.
pub const TRIALS_PER_BODY: usize = 10_000;

/// What a random start is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomStart {
    /// Number density of centres (> 0).
    pub density: f64,
    /// The smallest distance between centres (> 0).
    pub closest: f64,
    /// The temperature of the velocities and angular momenta (>= 0).
    pub temperature: f64,
    /// The seed of the random numbers.
    pub seed: u64,
}

/// The periodic cube and the bodies of types `kinds` (one per body) of a
/// random start; errors name the field (`density`, `closest`,
/// `temperature`).
pub fn random_start(
    types: &[BodyType],
    kinds: &[usize],
    start: &RandomStart,
) -> Result<(Space, Vec<Body>), InputError> {
    let density = positive(start.density).map_err(|e| e.at("density"))?;
    let closest = positive(start.closest).map_err(|e| e.at("closest"))?;
    let temperature = non_negative(start.temperature).map_err(|e| e.at("temperature"))?;
    let packing = PI / 6.0 * density * closest.powi(3);
    if packing > MAX_PACKING {
        return Err(InputError::new(
            "density",
            format!(
                "cannot be packed at random with centres {} apart: packing fraction {} > {MAX_PACKING}",
                num(closest),
                num(packing)
            ),
        ));
    }
    let side = (kinds.len() as f64 / density).cbrt();
    let mut rng = ChaCha8Rng::seed_from_u64(start.seed);
    let centres = insert(kinds.len(), side, closest, &mut rng)?;
    let bodies = thermal(types, kinds, centres, None, temperature, &mut rng);
    Ok((Space::Periodic(Vector3::repeat(side)), bodies))
}

/// A cubic lattice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lattice {
    /// Simple cubic: one body per cubic cell.
    SimpleCubic,
    /// Face-centred cubic: four bodies per cubic cell (default).
    #[default]
    FaceCentredCubic,
}

named_choices!(Lattice {
    "simple_cubic" => Lattice::SimpleCubic,
    "fcc" => Lattice::FaceCentredCubic,
});

impl Lattice {
    /// The sites of one cubic cell of unit edge.
    fn basis(self) -> &'static [[f64; 3]] {
        match self {
            Lattice::SimpleCubic => &[[0.0; 3]],
            Lattice::FaceCentredCubic => &[
                [0.0, 0.0, 0.0],
                [0.5, 0.5, 0.0],
                [0.5, 0.0, 0.5],
                [0.0, 0.5, 0.5],
            ],
        }
    }
}

/// What a lattice start is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatticeStart {
    /// The lattice.
    pub lattice: Lattice,
    /// Number density of centres (> 0).
    pub density: f64,
    /// Every body's orientation (`None`: uniformly random).
    pub orientation: Option<Quat>,
    /// The temperature of the velocities and angular momenta (>= 0).
    pub temperature: f64,
    /// The seed of the random numbers.
    pub seed: u64,
}

/// The periodic cube and the bodies of types `kinds` (one per body, in
/// lattice order) of a lattice start: `kinds.len()` must fill `n^3` cells
/// (`n^3` bodies simple cubic, `4 n^3` fcc). Errors name the field
/// (`density`, `orientation`, `temperature`, `counts`).
pub fn lattice_start(
    types: &[BodyType],
    kinds: &[usize],
    start: &LatticeStart,
) -> Result<(Space, Vec<Body>), InputError> {
    let density = positive(start.density).map_err(|e| e.at("density"))?;
    let temperature = non_negative(start.temperature).map_err(|e| e.at("temperature"))?;
    let given = start
        .orientation
        .map(|q| orientation(&q).map_err(|e| e.at("orientation")))
        .transpose()?;
    let basis = start.lattice.basis();
    let cells = ((kinds.len() / basis.len()) as f64).cbrt().round() as usize;
    if cells == 0 || cells.pow(3) * basis.len() != kinds.len() {
        return Err(InputError::new(
            "counts",
            format!(
                "{} bodies do not fill a cube of n^3 lattice cells ({} bodies per cell)",
                kinds.len(),
                basis.len()
            ),
        ));
    }
    let side = (kinds.len() as f64 / density).cbrt();
    let edge = side / cells as f64;
    let mut centres = Vec::with_capacity(kinds.len());
    for cell in 0..cells.pow(3) {
        let corner = Vector3::new(
            (cell / (cells * cells)) as f64,
            ((cell / cells) % cells) as f64,
            (cell % cells) as f64,
        );
        for b in basis {
            centres.push((corner + Vector3::from(*b)) * edge);
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(start.seed);
    let bodies = thermal(types, kinds, centres, given, temperature, &mut rng);
    Ok((Space::Periodic(Vector3::repeat(side)), bodies))
}

/// Bodies of types `kinds` at `centres`, each with `orientation` (`None`:
/// uniformly random) and thermal velocities and angular momenta at
/// `temperature`, the total momentum removed.
fn thermal(
    types: &[BodyType],
    kinds: &[usize],
    centres: Vec<Vector3<f64>>,
    orientation: Option<Quat>,
    temperature: f64,
    rng: &mut ChaCha8Rng,
) -> Vec<Body> {
    let mut bodies: Vec<Body> = centres
        .into_iter()
        .zip(kinds)
        .map(|(position, &kind)| {
            let mass = types[kind].mass;
            let moments = types[kind].moments;
            let mut normal = || -> f64 { rng.sample(StandardNormal) };
            let drawn = match orientation {
                Some(q) => q,
                None => Quat(std::array::from_fn(|_| normal()))
                    .try_normalize()
                    .unwrap_or(Quat::IDENTITY),
            };
            let velocity = Vector3::from_fn(|_, _| normal() * (temperature / mass).sqrt());
            let angular_momentum_body =
                Vector3::from_fn(|k, _| normal() * (moments[k] * temperature).sqrt());
            Body {
                kind,
                position,
                image: [0; 3],
                velocity,
                orientation: drawn,
                angular_momentum_body,
            }
        })
        .collect();
    let total_mass: f64 = bodies.iter().map(|b| types[b.kind].mass).sum();
    let drift = bodies
        .iter()
        .map(|b| b.velocity * types[b.kind].mass)
        .sum::<Vector3<f64>>()
        / total_mass;
    for body in &mut bodies {
        body.velocity -= drift;
    }
    bodies
}

/// `n` centres in the cube of edge `side`, no two closer than `closest`
/// (minimum image), checked against the centres of the neighbouring cells
/// of a grid of cells at least `closest` wide.
fn insert(
    n: usize,
    side: f64,
    closest: f64,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Vector3<f64>>, InputError> {
    let cells = ((side / closest).floor() as usize).max(1);
    let cell = |x: f64| ((x / side * cells as f64) as usize).min(cells - 1);
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); cells * cells * cells];
    let mut centres: Vec<Vector3<f64>> = Vec::with_capacity(n);
    let space = Space::Periodic(Vector3::repeat(side));
    let near = |d: isize, c: usize| (c as isize + d).rem_euclid(cells as isize) as usize;
    for body in 0..n {
        let found = (0..TRIALS_PER_BODY).find_map(|_| {
            let x = Vector3::from_fn(|_, _| rng.random::<f64>() * side);
            let c = [cell(x.x), cell(x.y), cell(x.z)];
            let mut neighbours = Vec::with_capacity(27);
            for d in 0..27isize {
                let (dx, dy, dz) = (d / 9 - 1, (d / 3) % 3 - 1, d % 3 - 1);
                let index = (near(dx, c[0]) * cells + near(dy, c[1])) * cells + near(dz, c[2]);
                neighbours.push(index);
            }
            neighbours.sort_unstable();
            neighbours.dedup();
            let clear = neighbours
                .iter()
                .flat_map(|&k| &grid[k])
                .all(|&j| space.minimum_image(x - centres[j]).norm() >= closest);
            clear.then_some((x, (c[0] * cells + c[1]) * cells + c[2]))
        });
        let Some((x, index)) = found else {
            return Err(InputError::new(
                "density",
                format!("no place found for body {body} in {TRIALS_PER_BODY} random trials"),
            ));
        };
        grid[index].push(body);
        centres.push(x);
    }
    Ok(centres)
}
