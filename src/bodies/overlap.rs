//! Overlapping sites at the start: two Lennard-Jones sites of different
//! bodies closer than [`OVERLAP_FRACTION`] of their pair's sigma (mixed as
//! the term mixes) start in the steep core of the repulsion, where a step of
//! any usual size blows up; such a start is refused.

use super::evaluate::Evaluation;
use super::system::BodySystem;
use super::within::Within;

/// Lennard-Jones sites of different bodies closer than this fraction of
/// their pair's sigma overlap (the repulsion there is `4 eps 2^12`, about
/// 1.6e4 eps, and its force 2e5 eps / sigma).
pub const OVERLAP_FRACTION: f64 = 0.5;

/// A pair of Lennard-Jones sites of different bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    /// The two bodies (the lower index first).
    pub bodies: (usize, usize),
    /// The two sites as (body, index of the site in its body), in the
    /// order of `bodies`.
    pub sites: [(usize, usize); 2],
    /// The distance of the sites.
    pub distance: f64,
    /// Their pair's sigma.
    pub sigma: f64,
}

impl BodySystem {
    /// The pair of Lennard-Jones sites of different bodies closest relative
    /// to their sigma, if that is below [`OVERLAP_FRACTION`] (one
    /// evaluation, which builds the neighbour list).
    pub fn first_overlap(&mut self) -> Option<Overlap> {
        let _ = self.lennard_jones.as_ref()?;
        self.evaluate(&mut Evaluation::default());
        self.closest_pair()
            .filter(|o| o.distance < OVERLAP_FRACTION * o.sigma)
    }

    /// The pair of Lennard-Jones sites of different bodies closest relative
    /// to their sigma at the last evaluation (its site positions and
    /// neighbour list, the separations gathered as the pair pass gathers
    /// them), pairs at a non-finite distance left out; `None`
    /// without such a pair or before the first evaluation.
    pub fn closest_pair(&self) -> Option<Overlap> {
        let term = self.lennard_jones.as_ref()?;
        let positions = &self.scratch.multipoles.positions;
        if positions.len() != self.sites() {
            return None;
        }
        let lengths = self.neighbours.image_lengths();
        // Each site's listed partners with their separations in rows
        // (every one at a finite distance: none is beyond an infinite reach).
        let mut near = Within::default();
        // The smallest (r / sigma)^2 as (r^2, sigma^2), compared without
        // divisions; one square root at the end.
        let mut worst: Option<(f64, f64, usize, usize, f64)> = None;
        for (i, kind) in self.lj_kind.iter().enumerate() {
            let Some(a) = kind else { continue };
            let run = self.neighbours.half_run(i);
            near.collect(&positions[i], run, positions, &lengths, f64::INFINITY);
            for (j, r2) in near.kept() {
                let Some(b) = self.lj_kind[j] else { continue };
                let sigma = term.sigma(*a as usize, b as usize);
                let sigma2 = sigma * sigma;
                let closer = match worst {
                    None => true,
                    Some((w_r2, w_sigma2, ..)) => r2 * w_sigma2 < w_r2 * sigma2,
                };
                if closer {
                    worst = Some((r2, sigma2, i, j, sigma));
                }
            }
        }
        let (r2, _, i, j, sigma) = worst?;
        let distance = r2.sqrt();
        let site = |s: usize| {
            let body = self.site_body[s];
            let first = self.site_body.partition_point(|&b| b < body);
            (body as usize, s - first)
        };
        let (p, q) = (site(i), site(j));
        let sites = if p.0 <= q.0 { [p, q] } else { [q, p] };
        Some(Overlap {
            bodies: (sites[0].0, sites[1].0),
            sites,
            distance,
            sigma,
        })
    }
}
