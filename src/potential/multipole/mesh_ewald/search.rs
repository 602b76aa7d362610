//! The choice of the mesh Ewald sum's parameters from a requested
//! accuracy: every splitting `alpha` tried ([`SPLITTINGS`] values of
//! `alpha d` from 0.5 to 5, `d` the mean site spacing) and spline order
//! (4 to 8) gets the shortest real-space cutoff and the coarsest FFT-friendly
//! grid whose estimates ([`super::estimate`]) meet half the accuracy each;
//! the cheapest by the cost model wins. Forced values are kept as given,
//! and refused, saying what they reach, when no choice around them meets
//! the accuracy.

use super::accuracy::{check_accuracy, fft_size};
use super::estimate::{cost, mesh_estimate, Carried, MeshCosts, MeshEstimate};
use super::mesh::mesh_bytes;
use super::parameters::{ForcedMesh, MeshParameters};
use crate::checks::num;
use crate::potential::multipole::ewald_parameters::{real_estimate, solve};
use crate::potential::multipole::PotentialError;
use nalgebra::Vector3;

/// The splitting parameters tried, `alpha d` from 0.5 to 5.
const SPLITTINGS: usize = 16;

/// The parameters for `sites` sites carrying `carried` in `box_lengths` at
/// relative field accuracy `accuracy` (module doc), at spline order `order`
/// (or the cheapest of 4 to 8) and splitting `alpha` (or the cheapest of
/// those tried): [`for_multipoles_forced`] with those two forced.
pub fn for_multipoles(
    accuracy: f64,
    carried: Carried,
    sites: usize,
    box_lengths: &Vector3<f64>,
    order: Option<usize>,
    alpha: Option<f64>,
) -> Result<(MeshParameters, MeshEstimate), PotentialError> {
    let forced = ForcedMesh {
        order,
        alpha,
        ..ForcedMesh::default()
    };
    for_multipoles_forced(accuracy, carried, sites, box_lengths, &forced)
}

/// The parameters for `sites` sites carrying `carried` in `box_lengths` at
/// relative field accuracy `accuracy` (module doc), the values `forced`
/// taken as given and the rest chosen. Refuses (naming the field) an
/// accuracy outside [`super::ACCURACY_RANGE`], an order outside
/// [`super::ORDERS`], a forced real-space cutoff longer than half the
/// shortest box side (`real_cutoff`), forced values whose estimated error
/// exceeds the accuracy (`grid` or `real_cutoff`, saying the accuracy they
/// reach), a box the real-space cutoff does not fit (`box_lengths`) and
/// meshes over the memory limit (`accuracy`).
pub fn for_multipoles_forced(
    accuracy: f64,
    carried: Carried,
    sites: usize,
    box_lengths: &Vector3<f64>,
    forced: &ForcedMesh,
) -> Result<(MeshParameters, MeshEstimate), PotentialError> {
    let half_box = 0.5 * box_lengths.min();
    choose(
        accuracy,
        carried,
        sites,
        box_lengths,
        forced,
        (half_box, "half the shortest box side"),
        carried.costs(),
    )
}

/// [`for_multipoles_forced`] with a real-space cutoff of at most `skin`
/// less than half the shortest box side (the reach of a neighbour list with
/// that skin), and the real-space pairs summed by the caller at `pair`
/// seconds each (the model's pairs, [`super::mesh_cost`]).
pub fn for_multipoles_with_skin(
    accuracy: f64,
    carried: Carried,
    sites: usize,
    box_lengths: &Vector3<f64>,
    (skin, pair): (f64, f64),
    forced: &ForcedMesh,
) -> Result<(MeshParameters, MeshEstimate), PotentialError> {
    let longest = 0.5 * box_lengths.min() - skin;
    choose(
        accuracy,
        carried,
        sites,
        box_lengths,
        forced,
        (longest, "half the shortest box side less the skin"),
        MeshCosts {
            pair,
            ..carried.costs()
        },
    )
}

/// The forced values' closest approach to the accuracy over the choices
/// tried: the accuracy they reach (twice the larger of their parts'
/// estimates, each part getting half) and the choice.
struct Missed {
    reach: f64,
    mesh_part: bool,
    parameters: MeshParameters,
}

/// [`for_multipoles_forced`] with the real-space cutoff at most `longest`
/// (named `what`), the work costing `costs`.
fn choose(
    accuracy: f64,
    carried: Carried,
    sites: usize,
    box_lengths: &Vector3<f64>,
    forced: &ForcedMesh,
    (half_box, what): (f64, &str),
    costs: MeshCosts,
) -> Result<(MeshParameters, MeshEstimate), PotentialError> {
    check_accuracy(accuracy)?;
    let orders_tried = orders_to_try(forced.order)?;
    check_forced_cutoff(forced, (half_box, what))?;
    let pairs = carried.orders();
    let ranks: Vec<i32> = pairs.iter().map(|(s, g)| s + g).collect();
    let n_sites = sites.max(1) as f64;
    let density = n_sites / box_lengths.product();
    let d = density.cbrt().recip();
    let target = 0.5 * accuracy;
    let mut best: Option<(f64, MeshParameters, MeshEstimate)> = None;
    let mut missed: Option<Missed> = None;
    let splittings = splittings_to_try(forced, d);
    let largest = splittings.iter().copied().fold(0.0, f64::max);
    for alpha in splittings {
        let (rc, real) = match forced.real_cutoff {
            Some(rc) => (rc, real_estimate(&ranks, alpha * d, alpha * rc)),
            None => {
                let s_real = solve(|s| real_estimate(&ranks, alpha * d, s), target);
                (s_real / alpha, real_estimate(&ranks, alpha * d, s_real))
            }
        };
        if rc > half_box {
            continue;
        }
        for &p in &orders_tried {
            let Some(grid) =
                grid_to_try(forced, (&pairs, density, box_lengths), (alpha, p), target)
            else {
                continue;
            };
            let spacing: [f64; 3] = std::array::from_fn(|a| box_lengths[a] / grid[a] as f64);
            let parameters = MeshParameters {
                alpha,
                real_cutoff: rc,
                grid,
                order: p,
            };
            let estimate = MeshEstimate {
                real,
                mesh: mesh_estimate(&pairs, alpha, &spacing, p, density),
            };
            if let Some(miss) = forced_miss(forced, &estimate, target, parameters) {
                if missed.as_ref().is_none_or(|m| miss.reach < m.reach) {
                    missed = Some(miss);
                }
                continue;
            }
            let c = cost((n_sites, density), rc, grid, p, costs);
            if best.as_ref().is_none_or(|(b, _, _)| c < *b) {
                best = Some((c, parameters, estimate));
            }
        }
    }
    if let (None, Some(m)) = (&best, missed) {
        return Err(not_reached(accuracy, &m));
    }
    let Some((_, parameters, estimate)) = best else {
        let shortest = solve(|s| real_estimate(&ranks, largest * d, s), target) / largest;
        return Err(box_too_small(
            accuracy,
            (shortest, largest),
            (half_box, what),
        ));
    };
    check_mesh_memory(accuracy, parameters.grid)?;
    Ok((parameters, estimate))
}

/// No splitting fits the real-space cutoff in `half_box` (named `what`):
/// the shortest cutoff needed, at the largest splitting tried.
fn box_too_small(
    accuracy: f64,
    (shortest, largest): (f64, f64),
    (half_box, what): (f64, &str),
) -> PotentialError {
    PotentialError::new(
        "box_lengths",
        format!(
            "the mesh Ewald sum at accuracy {} needs a real-space cutoff of at least \
             {shortest:.4} (at the largest splitting tried, alpha = {largest:.4}), more than \
             {what} {half_box}: use a larger box or a looser accuracy",
            num(accuracy),
        ),
    )
}

/// A forced real-space cutoff beyond `half_box` (named `what`) is refused.
fn check_forced_cutoff(
    forced: &ForcedMesh,
    (half_box, what): (f64, &str),
) -> Result<(), PotentialError> {
    match forced.real_cutoff.filter(|&rc| rc > half_box) {
        Some(rc) => Err(PotentialError::new(
            "real_cutoff",
            format!(
                "{} does not fit the box: it is more than {what} {}",
                num(rc),
                crate::checks::derived(half_box)
            ),
        )),
        None => Ok(()),
    }
}

/// The forced splitting, or [`SPLITTINGS`] values from `0.5 / d` to `5 / d`
/// (`d` the mean site spacing).
fn splittings_to_try(forced: &ForcedMesh, d: f64) -> Vec<f64> {
    match forced.alpha {
        Some(alpha) => vec![alpha],
        None => (0..SPLITTINGS)
            .map(|k| 0.5 / d * 10f64.powf(k as f64 / (SPLITTINGS - 1) as f64))
            .collect(),
    }
}

/// The forced grid (none if an axis is below the order `p`), or the
/// coarsest FFT-friendly grid whose mesh estimate meets `target`.
fn grid_to_try(
    forced: &ForcedMesh,
    (pairs, density, box_lengths): (&[(i32, i32)], f64, &Vector3<f64>),
    (alpha, p): (f64, usize),
    target: f64,
) -> Option<[usize; 3]> {
    match forced.grid {
        Some(grid) if grid.iter().any(|&k| k < p) => None,
        Some(grid) => Some(grid),
        None => {
            let estimate = |h: f64| mesh_estimate(pairs, alpha, &[h; 3], p, density);
            let fine = largest_spacing(estimate, alpha, target)?;
            Some(std::array::from_fn(|a| {
                fft_size(((box_lengths[a] / fine).ceil() as usize).max(p))
            }))
        }
    }
}

/// Forced values whose part of the estimate misses `target`: the accuracy
/// they reach (twice their part) and the choice. Only forced values can
/// miss: the others are chosen to meet the target.
fn forced_miss(
    forced: &ForcedMesh,
    estimate: &MeshEstimate,
    target: f64,
    parameters: MeshParameters,
) -> Option<Missed> {
    let real_part = if forced.real_cutoff.is_some() {
        estimate.real
    } else {
        0.0
    };
    let mesh_part = if forced.grid.is_some() {
        estimate.mesh
    } else {
        0.0
    };
    (real_part.max(mesh_part) > target).then(|| Missed {
        reach: 2.0 * real_part.max(mesh_part),
        mesh_part: mesh_part >= real_part,
        parameters,
    })
}

/// The error of forced values that do not reach `accuracy`: it names the
/// forced grid when its mesh part misses (else the forced real-space
/// cutoff) and says the accuracy reached at best, with the choice that
/// reaches it.
fn not_reached(accuracy: f64, m: &Missed) -> PotentialError {
    let p = &m.parameters;
    let (field, value, rest) = if m.mesh_part {
        (
            "grid",
            format!("{:?} at order {}", p.grid, p.order),
            format!("real_cutoff {:.4}", p.real_cutoff),
        )
    } else {
        (
            "real_cutoff",
            num(p.real_cutoff),
            format!("grid {:?} at order {}", p.grid, p.order),
        )
    };
    PotentialError::new(
        field,
        format!(
            "{value} reaches {} at best (with alpha {:.4}, {rest}), not the requested {}",
            crate::checks::derived(format!("{:.1e}", m.reach).parse().unwrap_or(m.reach)),
            p.alpha,
            num(accuracy)
        ),
    )
}

/// The spline orders to try: `order` if given (refused outside
/// [`super::ORDERS`], naming `order`), else every one.
fn orders_to_try(order: Option<usize>) -> Result<Vec<usize>, PotentialError> {
    match order {
        Some(p) if super::ORDERS.contains(&p) => Ok(vec![p]),
        Some(p) => Err(PotentialError::new(
            "order",
            format!(
                "must be from {} to {}, got {p}",
                super::ORDERS.start(),
                super::ORDERS.end()
            ),
        )),
        None => Ok(super::ORDERS.collect()),
    }
}

/// Halvings of the bracket `[1e-3, 4] / alpha` (in `log h`): after 14 the
/// spacing is known to 0.05 %, finer than the mesh sizes it rounds to.
const BISECTIONS: usize = 14;

/// The largest mesh spacing `h` (between `1e-3 / alpha` and `4 / alpha`)
/// whose `estimate(h)` meets `target`, by bisection in `log h`; `None`
/// when even the finest does not.
fn largest_spacing(estimate: impl Fn(f64) -> f64, alpha: f64, target: f64) -> Option<f64> {
    let (mut fine, mut coarse) = (1e-3 / alpha, 4.0 / alpha);
    if estimate(fine) > target {
        return None;
    }
    for _ in 0..BISECTIONS {
        let middle = (fine * coarse).sqrt();
        if estimate(middle) <= target {
            fine = middle;
        } else {
            coarse = middle;
        }
    }
    Some(fine)
}

/// Refuses, naming `accuracy`, a mesh `grid` over the memory limit.
fn check_mesh_memory(accuracy: f64, grid: [usize; 3]) -> Result<(), PotentialError> {
    crate::memory::check("accuracy", mesh_bytes(grid)).map_err(|e| {
        PotentialError::new(
            "accuracy",
            format!(
                "{} needs a {}x{}x{} mesh: {}",
                num(accuracy),
                grid[0],
                grid[1],
                grid[2],
                e.message
            ),
        )
    })
}
