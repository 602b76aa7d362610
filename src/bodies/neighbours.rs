//! Verlet neighbour lists of sites built through a cell list: every pair of
//! sites of different bodies closer than `cutoff + skin`, rebuilt when a
//! site has moved more than half the skin since the last build (then no
//! pair can have come within the cutoff unseen).
//!
//! Cost and memory O(N): cells at least `cutoff + skin` wide (wider in open
//! space when the sites' bounding box would need more than
//! [`CELLS_PER_SITE`] cells per site), each site compared with the sites of
//! its 27 neighbouring cells. The list is full (each pair listed from both
//! ends), so per-site sums need no shared writes: the results are the same
//! bit for bit for any number of threads.

use super::checkpoint::{bad, take_values, whole};
use super::space::Space;
use crate::checks::{non_negative, positive, InputError};
use crate::integrators::checkpoint::write_values;
use crate::integrators::IntegratorError;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Open space: at most this many cells per site (plus 27).
pub const CELLS_PER_SITE: usize = 8;
/// Sites per parallel task of a build.
const SITES_PER_TASK: usize = 512;

/// A full Verlet list of the sites.
#[derive(Clone, Debug)]
pub struct NeighbourList {
    cutoff: f64,
    skin: f64,
    /// Site `i`'s partners are `partner[start[i]..start[i + 1]]`.
    start: Vec<usize>,
    partner: Vec<u32>,
    /// For each pair, the box lengths between its separation and that
    /// separation's minimum image at the build (within the cutoff, it stays
    /// the minimum image until the list goes stale). Sites are never more
    /// than a body's size outside the box, so the counts fit.
    image: Vec<[i8; 3]>,
    /// The space of the last build.
    space: Space,
    /// Site positions at the last build.
    reference: Vec<Vector3<f64>>,
    builds: u64,
}

/// A grid of cells over the sites.
struct Cells {
    counts: [usize; 3],
    /// Sites of cell `c` are `order[first[c]..first[c + 1]]`.
    first: Vec<usize>,
    order: Vec<u32>,
    cell_of: Vec<usize>,
    periodic: bool,
}

impl NeighbourList {
    /// An empty list for pairs within `cutoff` (> 0) with a skin (>= 0).
    pub fn new(cutoff: f64, skin: f64) -> Result<Self, InputError> {
        Ok(NeighbourList {
            cutoff: positive(cutoff).map_err(|e| e.at("cutoff"))?,
            skin: non_negative(skin).map_err(|e| e.at("skin"))?,
            start: Vec::new(),
            partner: Vec::new(),
            image: Vec::new(),
            space: Space::Open,
            reference: Vec::new(),
            builds: 0,
        })
    }

    /// `cutoff + skin`: the reach of the list.
    pub fn reach(&self) -> f64 {
        self.cutoff + self.skin
    }

    /// How many times the list was built.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// The partners of site `i`.
    #[inline]
    pub fn partners(&self, i: usize) -> &[u32] {
        &self.partner[self.start[i]..self.start[i + 1]]
    }

    /// The partners `j` of site `i` with the separations `x_i - x_j` of
    /// `positions` (those of the sites the list was built for, moved since)
    /// in the image of the build: the minimum image, the same bits as
    /// [`Space::minimum_image`], for every pair within the cutoff, without
    /// its divisions and roundings.
    #[inline]
    pub fn separations<'a>(
        &'a self,
        i: usize,
        positions: &'a [Vector3<f64>],
    ) -> impl Iterator<Item = (usize, Vector3<f64>)> + 'a {
        let range = self.start[i]..self.start[i + 1];
        let (x, space) = (positions[i], self.space);
        self.partner[range.clone()]
            .iter()
            .zip(&self.image[range])
            .map(move |(&j, counts)| {
                let j = j as usize;
                let counts = Vector3::from_fn(|k, _| f64::from(counts[k]));
                (j, x - positions[j] - space.shift(&counts))
            })
    }

    /// Whether the list must be rebuilt for `sites` in `space`: never
    /// built, another number of sites, another space (its image counts
    /// would be wrong), or a site more than half the skin from where it was
    /// at the last build.
    pub fn is_stale(&self, sites: &[Vector3<f64>], space: &Space) -> bool {
        let limit = (0.5 * self.skin).powi(2);
        self.reference.len() != sites.len()
            || self.start.is_empty()
            || self.space != *space
            || sites
                .par_iter()
                .zip(&self.reference)
                .any(|(x, x0)| (x - x0).norm_squared() > limit)
    }

    /// Builds the list of `sites` (`body[i]` the body of site `i`; pairs
    /// within one body are left out).
    pub fn build(&mut self, sites: &[Vector3<f64>], body: &[u32], space: &Space) {
        let reach = self.reach();
        let cells = Cells::new(sites, space, reach);
        let reach2 = reach * reach;
        type Task = (Vec<usize>, Vec<u32>, Vec<[i8; 3]>);
        let tasks: Vec<Task> = (0..sites.len().div_ceil(SITES_PER_TASK))
            .into_par_iter()
            .map(|task| {
                let range = task * SITES_PER_TASK..((task + 1) * SITES_PER_TASK).min(sites.len());
                let mut counts = Vec::with_capacity(range.len());
                let (mut partners, mut images) = (Vec::new(), Vec::new());
                for i in range {
                    let before = partners.len();
                    for c in cells.neighbours(cells.cell_of[i]) {
                        for &j in cells.sites(c) {
                            let ju = j as usize;
                            if ju == i || body[ju] == body[i] {
                                continue;
                            }
                            let d = sites[i] - sites[ju];
                            let image = space.image_counts(d);
                            if (d - space.shift(&image)).norm_squared() < reach2 {
                                partners.push(j);
                                images.push([0, 1, 2].map(|k| image[k] as i8));
                            }
                        }
                    }
                    counts.push(partners.len() - before);
                }
                (counts, partners, images)
            })
            .collect();
        self.start.clear();
        self.start.push(0);
        self.partner.clear();
        self.image.clear();
        for (counts, partners, images) in tasks {
            for c in counts {
                self.start.push(self.start.last().copied().unwrap_or(0) + c);
            }
            self.partner.extend_from_slice(&partners);
            self.image.extend_from_slice(&images);
        }
        self.space = *space;
        self.reference.clear();
        self.reference.extend_from_slice(sites);
        self.builds += 1;
    }
}

impl NeighbourList {
    /// Appends the list's state for a checkpoint: the number of builds,
    /// the number of sites at the last build (0 before the first) and their
    /// positions then. The pairs are not stored: [`NeighbourList::restore`]
    /// rebuilds them from those positions.
    pub(crate) fn write_checkpoint(&self, out: &mut Vec<f64>) {
        out.push(self.builds as f64);
        out.push(self.reference.len() as f64);
        write_values(&self.reference, out);
    }

    /// Reads back [`NeighbourList::write_checkpoint`]'s output from the
    /// front of `data` for the sites of bodies `body` in `space`, returning
    /// the rest. A build depends only on the positions, `body` and `space`,
    /// so the list rebuilt from the saved positions is the one the run had,
    /// pair for pair and in the same order (the force sums then add in the
    /// same order), and it goes stale at the same step.
    pub(crate) fn restore<'a>(
        &mut self,
        data: &'a [f64],
        body: &[u32],
        space: &Space,
    ) -> Result<&'a [f64], IntegratorError> {
        let [builds, sites, rest @ ..] = data else {
            return Err(bad("the neighbour list's counts are missing"));
        };
        let builds = whole(*builds, "the neighbour list's number of builds")?;
        let sites = whole(*sites, "the neighbour list's number of sites")?;
        if sites != 0 && sites != body.len() as u64 {
            return Err(bad(&format!(
                "the neighbour list was built for {sites} sites, the system has {}",
                body.len()
            )));
        }
        let mut reference = vec![Vector3::zeros(); sites as usize];
        let rest = take_values(rest, &mut reference, "the neighbour list's site positions")?;
        if sites == 0 {
            self.start.clear();
            self.partner.clear();
            self.image.clear();
            self.reference.clear();
        } else {
            self.build(&reference, body, space);
        }
        self.builds = builds;
        Ok(rest)
    }
}

impl Cells {
    fn new(sites: &[Vector3<f64>], space: &Space, reach: f64) -> Cells {
        let (origin, width, counts, periodic) = match space {
            Space::Periodic(l) => {
                let counts = [0, 1, 2].map(|k| ((l[k] / reach).floor() as usize).max(1));
                let width = Vector3::from_fn(|k, _| l[k] / counts[k] as f64);
                (Vector3::zeros(), width, counts, true)
            }
            Space::Open => {
                let (lo, hi) = sites.iter().fold(
                    (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
                    |(lo, hi), x| (lo.inf(x), hi.sup(x)),
                );
                let extent = (hi - lo).sup(&Vector3::zeros());
                let limit = 27 + CELLS_PER_SITE * sites.len();
                let mut size = reach;
                let count = |size: f64| [0, 1, 2].map(|k| (extent[k] / size) as usize + 1);
                while count(size).iter().product::<usize>() > limit {
                    size *= 1.5;
                }
                (lo, Vector3::repeat(size), count(size), false)
            }
        };
        let index = |x: &Vector3<f64>| {
            let mut c = [0; 3];
            for k in 0..3 {
                let mut u = (x[k] - origin[k]) / width[k];
                if periodic {
                    u = u.rem_euclid(counts[k] as f64);
                }
                c[k] = (u.max(0.0) as usize).min(counts[k] - 1);
            }
            (c[0] * counts[1] + c[1]) * counts[2] + c[2]
        };
        let cell_of: Vec<usize> = sites.iter().map(index).collect();
        let total = counts.iter().product::<usize>();
        let mut first = vec![0; total + 1];
        for &c in &cell_of {
            first[c + 1] += 1;
        }
        for c in 0..total {
            first[c + 1] += first[c];
        }
        let mut fill = first.clone();
        let mut order = vec![0; sites.len()];
        for (i, &c) in cell_of.iter().enumerate() {
            order[fill[c]] = i as u32;
            fill[c] += 1;
        }
        Cells {
            counts,
            first,
            order,
            cell_of,
            periodic,
        }
    }

    fn sites(&self, c: usize) -> &[u32] {
        &self.order[self.first[c]..self.first[c + 1]]
    }

    /// The distinct cells next to `c` (itself included), ascending.
    fn neighbours(&self, c: usize) -> Vec<usize> {
        let [_, ny, nz] = self.counts;
        let own = [c / (ny * nz), (c / nz) % ny, c % nz];
        let mut out = Vec::with_capacity(27);
        for dx in -1i64..=1 {
            for dy in -1i64..=1 {
                for dz in -1i64..=1 {
                    let mut cell = [0usize; 3];
                    let mut inside = true;
                    for (k, d) in [dx, dy, dz].into_iter().enumerate() {
                        let n = self.counts[k] as i64;
                        let u = own[k] as i64 + d;
                        if self.periodic {
                            cell[k] = u.rem_euclid(n) as usize;
                        } else if (0..n).contains(&u) {
                            cell[k] = u as usize;
                        } else {
                            inside = false;
                        }
                    }
                    if inside {
                        out.push((cell[0] * ny + cell[1]) * nz + cell[2]);
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The pairs of the list are exactly those a direct double loop finds
    /// within the reach (different bodies only), periodic and open, for
    /// boxes with 2, 3 and more cells per edge.
    #[test]
    fn the_list_holds_exactly_the_pairs_within_reach() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for (lengths, n) in [([5.0, 6.5, 12.0], 300), ([5.2, 5.2, 5.2], 40)] {
            let lengths = Vector3::from(lengths);
            let sites: Vec<Vector3<f64>> = (0..n)
                .map(|_| Vector3::from_fn(|k, _| rng.random::<f64>() * lengths[k] * 1.2 - 0.1))
                .collect();
            let body: Vec<u32> = (0..n as u32).map(|i| i / 2).collect();
            for space in [Space::Periodic(lengths), Space::Open] {
                let mut list = NeighbourList::new(2.0, 0.5).unwrap();
                list.build(&sites, &body, &space);
                for i in 0..n {
                    let mut found: Vec<u32> = list.partners(i).to_vec();
                    found.sort_unstable();
                    let direct: Vec<u32> = (0..n as u32)
                        .filter(|&j| {
                            body[j as usize] != body[i]
                                && space.minimum_image(sites[i] - sites[j as usize]).norm() < 2.5
                        })
                        .collect();
                    assert_eq!(found, direct, "site {i} in {space:?}");
                }
            }
        }
    }

    /// After the sites have moved (each by less than half the skin, across
    /// the box's faces too), the list's separations of every pair within
    /// the cutoff are the minimum images bit for bit, and no pair within
    /// the cutoff is missing.
    #[test]
    fn separations_are_the_minimum_images_until_stale() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (n, lengths, cutoff, skin) = (400, Vector3::new(6.0, 6.5, 7.0), 2.0, 0.6);
        let space = Space::Periodic(lengths);
        let mut sites: Vec<Vector3<f64>> = (0..n)
            .map(|_| Vector3::from_fn(|k, _| rng.random::<f64>() * lengths[k]))
            .collect();
        let body: Vec<u32> = (0..n as u32).collect();
        let mut list = NeighbourList::new(cutoff, skin).unwrap();
        list.build(&sites, &body, &space);
        for x in &mut sites {
            *x += Vector3::from_fn(|_, _| (rng.random::<f64>() - 0.5) * 0.3);
        }
        assert!(!list.is_stale(&sites, &space));
        let mut within = 0;
        for i in 0..n {
            let listed: Vec<(usize, Vector3<f64>)> = list.separations(i, &sites).collect();
            for j in (0..n).filter(|&j| j != i) {
                let image = space.minimum_image(sites[i] - sites[j]);
                if image.norm() < cutoff {
                    within += 1;
                    let found = listed.iter().find(|(k, _)| *k == j).map(|(_, r)| *r);
                    assert_eq!(
                        found.map(|r| r.map(f64::to_bits)),
                        Some(image.map(f64::to_bits)),
                        "{i} {j}"
                    );
                }
            }
        }
        assert!(within > 10 * n, "{within} pairs within the cutoff");
    }

    /// The list is stale once a site has moved more than half the skin, not
    /// before, and in another space.
    #[test]
    fn the_list_is_stale_after_half_a_skin() {
        let (mut sites, space) = (
            vec![Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)],
            Space::Open,
        );
        let mut list = NeighbourList::new(1.0, 0.4).unwrap();
        assert!(list.is_stale(&sites, &space));
        list.build(&sites, &[0, 1], &space);
        sites[1].y = 0.19;
        assert!(!list.is_stale(&sites, &space));
        sites[1].y = 0.21;
        assert!(list.is_stale(&sites, &space));
        sites[1].y = 0.0;
        assert!(list.is_stale(&sites, &Space::Periodic(Vector3::repeat(5.0))));
    }

    /// Open space with sites spread along a line far longer than the
    /// reach: the cells stay within the bound per site.
    #[test]
    fn open_cells_stay_within_the_bound() {
        let sites: Vec<Vector3<f64>> = (0..10)
            .map(|k| Vector3::new(1e6 * k as f64, 0.0, 0.0))
            .collect();
        let cells = Cells::new(&sites, &Space::Open, 1.0);
        assert!(cells.first.len() - 1 <= 27 + CELLS_PER_SITE * 10);
    }
}
