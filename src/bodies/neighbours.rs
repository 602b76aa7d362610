//! Verlet neighbour lists of sites built through a cell list: every pair of
//! sites of different bodies closer than `cutoff + skin`, rebuilt when a
//! site has moved more than half the skin since the last build (then no
//! pair can have come within the cutoff unseen).
//!
//! Cost and memory O(N): cells at least `cutoff + skin` wide (wider in open
//! space when the sites' bounding box would need more than
//! [`CELLS_PER_SITE`] cells per site), each site compared with the
//! higher-numbered sites of its 27 neighbouring cells. The list is a half
//! list (each pair once, under its lower site, for sums that use Newton's
//! third law); a full view (each pair under both sites, for per-site sums
//! without shared writes) is derived from it when asked for at construction.
//! A list may hold some sites only ([`NeighbourList::listing`]: the
//! Lennard-Jones sites when no electrostatic sum reads the list, so that
//! rigid water's hydrogens, whose charges a mesh sum pairs itself, are
//! neither scanned nor anyone's partners, nor make the list stale).

pub use super::cells::CELLS_PER_SITE;
use super::cells::{Cells, Near};
use super::checkpoint::{bad, take_values, whole};
use super::space::Space;
use crate::checks::{non_negative, positive, InputError};
use crate::integrators::checkpoint::write_values;
use crate::integrators::IntegratorError;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Sites per parallel task of a build.
const SITES_PER_TASK: usize = 512;

/// A Verlet list of the sites: the half list, and the full view if kept.
#[derive(Clone, Debug)]
pub struct NeighbourList {
    cutoff: f64,
    skin: f64,
    /// Each pair once, under its lower site.
    half: Pairs,
    /// Each pair under both sites (`None` for a list made [`NeighbourList::half_only`]).
    full: Option<Pairs>,
    /// The space of the last build.
    space: Space,
    /// Site positions at the last build.
    reference: Vec<Vector3<f64>>,
    /// The sites the list holds (all for `None`): the others have no
    /// partners and are no one's.
    listed: Option<Vec<bool>>,
    builds: u64,
}

/// Pairs stored by site: site `i`'s partners are `partner[start[i]..start[i + 1]]`.
#[derive(Clone, Debug, Default)]
struct Pairs {
    start: Vec<usize>,
    partner: Vec<u32>,
    /// For each pair, the box lengths between its separation and that
    /// separation's minimum image at the build (within the cutoff, it stays
    /// the minimum image until the list goes stale). Sites are never more
    /// than a body's size outside the box, so the counts fit.
    image: Vec<[i8; 3]>,
}

impl NeighbourList {
    /// An empty list for pairs within `cutoff` (> 0) with a skin (>= 0),
    /// keeping the full view.
    pub fn new(cutoff: f64, skin: f64) -> Result<Self, InputError> {
        Ok(NeighbourList {
            cutoff: positive(cutoff).map_err(|e| e.at("cutoff"))?,
            skin: non_negative(skin).map_err(|e| e.at("skin"))?,
            half: Pairs::default(),
            full: Some(Pairs::default()),
            space: Space::Open,
            reference: Vec::new(),
            listed: None,
            builds: 0,
        })
    }

    /// The list of the sites `listed` only (those whose pairs some sum
    /// reads): the others have no partners and are no one's, and their
    /// moves do not make the list stale.
    pub fn listing(mut self, listed: Vec<bool>) -> Self {
        self.listed = Some(listed);
        self
    }

    /// The list without its full view (half the memory and no
    /// transposition per build), for users of [`NeighbourList::half_pairs`] only.
    pub fn half_only(mut self) -> Self {
        self.full = None;
        self
    }

    /// `cutoff + skin`: the reach of the list.
    pub fn reach(&self) -> f64 {
        self.cutoff + self.skin
    }

    /// How many times the list was built.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// The number of pairs of the half list.
    pub fn pairs(&self) -> usize {
        self.half.partner.len()
    }

    /// The partners `j` of site `i` with the separations `x_i - x_j` of
    /// `positions` (those of the sites the list was built for, moved since)
    /// in the image of the build: the minimum image, the same bits as
    /// [`Space::minimum_image`], for every pair within the cutoff, without
    /// its divisions and roundings. Every partner of `i` in the full view
    /// (none for a list made [`NeighbourList::half_only`]).
    #[inline]
    pub fn separations<'a>(
        &'a self,
        i: usize,
        positions: &'a [Vector3<f64>],
    ) -> impl Iterator<Item = (usize, Vector3<f64>)> + 'a {
        let full = self.full.as_ref().filter(|f| f.start.len() > i + 1);
        let pairs = full.unwrap_or(&self.half);
        let range = full.map_or(0..0, |f| f.start[i]..f.start[i + 1]);
        pairs.separations(i, range, positions, self.space)
    }

    /// [`NeighbourList::separations`] of the half list: the partners `j`
    /// listed under site `i` (each pair once over all sites).
    #[inline]
    pub fn half_pairs<'a>(
        &'a self,
        i: usize,
        positions: &'a [Vector3<f64>],
    ) -> impl Iterator<Item = (usize, Vector3<f64>)> + 'a {
        let range = self.half.start[i]..self.half.start[i + 1];
        self.half.separations(i, range, positions, self.space)
    }

    /// The partners listed under site `i` in the half list (the lane
    /// kernels' form of [`NeighbourList::half_pairs`], which take each
    /// pair's minimum image: `super::within`).
    #[inline]
    pub(crate) fn half_run(&self, i: usize) -> &[u32] {
        &self.half.partner[self.half.start[i]..self.half.start[i + 1]]
    }

    /// The space of the last build.
    pub fn space(&self) -> &Space {
        &self.space
    }

    /// The box lengths of the last build's space (zero in open space): the
    /// minimum images' of [`NeighbourList::half_run`]'s partners.
    pub(crate) fn image_lengths(&self) -> Vector3<f64> {
        match self.space {
            Space::Periodic(l) => l,
            Space::Open => Vector3::zeros(),
        }
    }

    /// Where site `i`'s pairs start in the half list (`i` up to the number
    /// of sites): the pairs of sites `a..b` are `half_start(b) -
    /// half_start(a)`.
    pub fn half_start(&self, i: usize) -> usize {
        self.half.start[i]
    }

    /// Whether the list must be rebuilt for `sites` in `space`: never
    /// built, another number of sites, another space (its image counts
    /// would be wrong), or a site more than half the skin from where it was
    /// at the last build.
    pub fn is_stale(&self, sites: &[Vector3<f64>], space: &Space) -> bool {
        let limit = (0.5 * self.skin).powi(2);
        let listed = self.listed.as_deref();
        self.reference.len() != sites.len()
            || self.half.start.is_empty()
            || self.space != *space
            || sites
                .par_iter()
                .zip(&self.reference)
                .enumerate()
                .any(|(i, (x, x0))| listed.is_none_or(|l| l[i]) && (x - x0).norm_squared() > limit)
    }

    /// Builds the list of `sites` (`body[i]` the body of site `i`; pairs
    /// within one body are left out).
    pub fn build(&mut self, sites: &[Vector3<f64>], body: &[u32], space: &Space) {
        let reach = self.reach();
        let listed = self.listed.as_deref();
        let cells = Cells::new(sites, listed, space, reach);
        let scan = Scan {
            cells: &cells,
            sites,
            body,
            listed,
            reach2: reach * reach,
        };
        let tasks: Vec<Task> = (0..sites.len().div_ceil(SITES_PER_TASK))
            .into_par_iter()
            .map(|task| {
                scan.task(task * SITES_PER_TASK..((task + 1) * SITES_PER_TASK).min(sites.len()))
            })
            .collect();
        let half = &mut self.half;
        half.start.clear();
        half.start.push(0);
        half.partner.clear();
        half.image.clear();
        for (counts, partners, images) in tasks {
            for c in counts {
                half.start.push(half.start.last().copied().unwrap_or(0) + c);
            }
            half.partner.extend_from_slice(&partners);
            half.image.extend_from_slice(&images);
        }
        if let Some(full) = &mut self.full {
            full.fill_from(&self.half);
        }
        self.space = *space;
        self.reference.clear();
        self.reference.extend_from_slice(sites);
        self.builds += 1;
    }
}

/// The pairs of a range of sites: each site's count, the partners, their
/// image counts.
type Task = (Vec<usize>, Vec<u32>, Vec<[i8; 3]>);

/// A build's scan: the cells of the sites, their positions and bodies,
/// and the square of the list's reach.
struct Scan<'a> {
    cells: &'a Cells,
    sites: &'a [Vector3<f64>],
    body: &'a [u32],
    /// The sites listed (all for `None`).
    listed: Option<&'a [bool]>,
    reach2: f64,
}

impl Scan<'_> {
    /// The pairs of the sites `range` with the higher sites of other bodies
    /// within `sqrt(reach2)`, compiled for AVX2 where the CPU has it (the
    /// same pairs in the same order: only the distances' loop is vectorised).
    fn task(&self, range: std::ops::Range<usize>) -> Task {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, checked just above.
            return unsafe { self.task_avx2(range) };
        }
        self.sites_of(range)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn task_avx2(&self, range: std::ops::Range<usize>) -> Task {
        self.sites_of(range)
    }

    #[inline(always)]
    fn sites_of(&self, range: std::ops::Range<usize>) -> Task {
        let (sites, body) = (self.sites, self.body);
        let mut counts = Vec::with_capacity(range.len());
        let (mut partners, mut images) = (Vec::new(), Vec::new());
        // The neighbours of the last site's cell (the sites of a body,
        // which follow each other, are often in one cell), the sites
        // taken in ascending order (as `scan_above` needs).
        let mut near: Option<Near> = None;
        for i in range {
            if self.listed.is_some_and(|l| !l[i]) {
                counts.push(0);
                continue;
            }
            let cell = self.cells.cell_of(i);
            let near = match &mut near {
                Some(n) if n.cell == cell => n,
                _ => near.insert(self.cells.near(cell, i)),
            };
            let (before, own) = (partners.len(), body[i]);
            let wanted = |j: usize| body[j] != own;
            self.cells
                .scan_above((i, &sites[i]), near, self.reach2, wanted, |j, image| {
                    partners.push(j);
                    images.push(image);
                });
            counts.push(partners.len() - before);
        }
        (counts, partners, images)
    }
}

impl Pairs {
    /// The partners of site `i` at `range` with their separations (see
    /// [`NeighbourList::separations`]).
    #[inline]
    fn separations<'a>(
        &'a self,
        i: usize,
        range: std::ops::Range<usize>,
        positions: &'a [Vector3<f64>],
        space: Space,
    ) -> impl Iterator<Item = (usize, Vector3<f64>)> + 'a {
        let x = positions[i];
        self.partner[range.clone()]
            .iter()
            .zip(&self.image[range])
            .map(move |(&j, counts)| {
                let j = j as usize;
                let counts = Vector3::from_fn(|k, _| f64::from(counts[k]));
                (j, x - positions[j] - space.shift(&counts))
            })
    }

    /// The full view of a half list: each site's partners below it (in
    /// ascending order, their image counts negated), then those above.
    fn fill_from(&mut self, half: &Pairs) {
        let n = half.start.len() - 1;
        self.start.clear();
        self.start.resize(n + 1, 0);
        for i in 0..n {
            self.start[i + 1] += half.start[i + 1] - half.start[i];
            for &j in &half.partner[half.start[i]..half.start[i + 1]] {
                self.start[j as usize + 1] += 1;
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        let total = self.start[n];
        self.partner.clear();
        self.partner.resize(total, 0);
        self.image.clear();
        self.image.resize(total, [0; 3]);
        let mut fill = self.start[..n].to_vec();
        for i in 0..n {
            for p in half.start[i]..half.start[i + 1] {
                let j = half.partner[p] as usize;
                self.partner[fill[j]] = i as u32;
                self.image[fill[j]] = half.image[p].map(|c| -c);
                fill[j] += 1;
            }
            // Site `i`'s own (higher) partners follow all the lower ones,
            // which came from sites before it.
            let own = half.start[i + 1] - half.start[i];
            let at = self.start[i + 1] - own;
            self.partner[at..at + own]
                .copy_from_slice(&half.partner[half.start[i]..half.start[i + 1]]);
            self.image[at..at + own].copy_from_slice(&half.image[half.start[i]..half.start[i + 1]]);
        }
    }

    fn clear(&mut self) {
        self.start.clear();
        self.partner.clear();
        self.image.clear();
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
            self.half.clear();
            if let Some(full) = &mut self.full {
                full.clear();
            }
            self.reference.clear();
        } else {
            self.build(&reference, body, space);
        }
        self.builds = builds;
        Ok(rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The pairs of the full view are exactly those a direct double loop
    /// finds within the reach (different bodies only), periodic and open,
    /// for boxes with 2, 3 and more cells per edge; the half list holds each
    /// of them once, under its lower site.
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
                let mut half_pairs = Vec::new();
                for i in 0..n {
                    let mut found: Vec<usize> = list.separations(i, &sites).map(|p| p.0).collect();
                    found.sort_unstable();
                    let direct: Vec<usize> = (0..n)
                        .filter(|&j| {
                            body[j] != body[i]
                                && space.minimum_image(sites[i] - sites[j]).norm() < 2.5
                        })
                        .collect();
                    assert_eq!(found, direct, "site {i} in {space:?}");
                    half_pairs.extend(list.half_pairs(i, &sites).map(|(j, _)| (i, j)));
                    assert_eq!(
                        list.half_start(i + 1) - list.half_start(i),
                        direct.iter().filter(|&&j| j > i).count()
                    );
                }
                let mut each_once: Vec<(usize, usize)> = half_pairs
                    .iter()
                    .map(|&(i, j)| (i.min(j), i.max(j)))
                    .collect();
                each_once.sort_unstable();
                each_once.dedup();
                assert_eq!(each_once.len(), half_pairs.len(), "a pair listed twice");
                assert_eq!(
                    2 * list.pairs(),
                    (0..n)
                        .map(|i| list.separations(i, &sites).count())
                        .sum::<usize>()
                );
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
        let cells = Cells::new(&sites, None, &Space::Open, 1.0);
        assert!(cells.cells() <= 27 + CELLS_PER_SITE * 10);
    }
}
