//! Overlapping sites at the start: two Lennard-Jones sites of different
//! bodies closer than [`OVERLAP_FRACTION`] of their pair's sigma (mixed as
//! the term mixes) start in the steep core of the repulsion, where a step of
//! any usual size blows up; such a start is refused.

use super::evaluate::Evaluation;
use super::system::BodySystem;

/// Lennard-Jones sites of different bodies closer than this fraction of
/// their pair's sigma overlap (the repulsion there is `4 eps 2^12`, about
/// 1.6e4 eps, and its force 2e5 eps / sigma).
pub const OVERLAP_FRACTION: f64 = 0.5;

/// The closest overlapping pair of sites.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    /// The two bodies (the lower index first).
    pub bodies: (usize, usize),
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
        let term = self.lennard_jones.as_ref()?.clone();
        self.evaluate(&mut Evaluation::default());
        let positions = &self.scratch.multipoles.positions;
        let mut worst: Option<(f64, Overlap)> = None;
        for (i, kind) in self.lj_kind.iter().enumerate() {
            let Some(a) = kind else { continue };
            for &j in self.neighbours.partners(i) {
                let j = j as usize;
                let Some(b) = self.lj_kind[j] else { continue };
                let sigma = term.sigma(*a as usize, b as usize);
                let distance = self.space.minimum_image(positions[i] - positions[j]).norm();
                let ratio = distance / sigma;
                if ratio < OVERLAP_FRACTION && worst.is_none_or(|(w, _)| ratio < w) {
                    let (p, q) = (self.site_body[i] as usize, self.site_body[j] as usize);
                    let overlap = Overlap {
                        bodies: (p.min(q), p.max(q)),
                        distance,
                        sigma,
                    };
                    worst = Some((ratio, overlap));
                }
            }
        }
        worst.map(|(_, o)| o)
    }
}
