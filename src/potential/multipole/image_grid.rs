//! The periodic images of sites within a cutoff, found by binning the
//! sites into cells (the scan of the pair table's build).

use nalgebra::Vector3;

/// One interacting image found for a row: partner, image shift `n`, offset.
pub(super) type Image = (u32, [i64; 3], Vector3<f64>);

/// Sites wrapped into a periodic box and binned into cells at least `cutoff`
/// wide (one cell along an axis shorter than the cutoff). The cells within
/// `reach` of a site's own, unwrapped across the box faces (cell index `u`
/// is cell `u mod cells` shifted by `floor(u / cells)` boxes), hold each
/// image of each site at most once and every image inside the cutoff, so one
/// scan serves large boxes (27 cells, O(N)) and small ones (an image loop).
pub(super) struct ImageGrid {
    cells: [usize; 3],
    reach: [i64; 3],
    box_lengths: Vector3<f64>,
    pub cutoff: f64,
    /// Sites wrapped into `[0, L)`.
    wrapped: Vec<Vector3<f64>>,
    /// Cell of each site.
    home: Vec<[usize; 3]>,
    /// Site indices of each cell, ascending.
    members: Vec<Vec<u32>>,
}

impl ImageGrid {
    pub fn new(sites: &[Vector3<f64>], box_lengths: &Vector3<f64>, cutoff: f64) -> Self {
        // At most N^(1/3) + 1 cells per axis: a tiny cutoff in a large box
        // must not allocate many more cells than there are sites.
        let most = (sites.len() as f64).cbrt().ceil() as usize + 1;
        let cells = [0, 1, 2].map(|a| ((box_lengths[a] / cutoff).floor() as usize).clamp(1, most));
        let reach = [0, 1, 2].map(|a| (cutoff * cells[a] as f64 / box_lengths[a]).ceil() as i64);
        let wrapped: Vec<_> = sites
            .iter()
            .map(|s| s.zip_map(box_lengths, |x, l| x - l * (x / l).floor()))
            .collect();
        let home: Vec<_> = wrapped
            .iter()
            .map(|w| {
                [0, 1, 2]
                    .map(|a| ((w[a] / box_lengths[a] * cells[a] as f64) as usize).min(cells[a] - 1))
            })
            .collect();
        let flat = |[x, y, z]: [usize; 3]| (x * cells[1] + y) * cells[2] + z;
        let mut members = vec![Vec::new(); cells.iter().product()];
        for (i, h) in home.iter().enumerate() {
            members[flat(*h)].push(i as u32);
        }
        ImageGrid {
            cells,
            reach,
            box_lengths: *box_lengths,
            cutoff,
            wrapped,
            home,
            members,
        }
    }

    /// The images `(j, n)` with `j > i`, or `j == i` and `n` lexicographically
    /// positive, within the cutoff of site `i`, by ascending `j` (the images
    /// of one partner in scan order).
    pub fn row(&self, i: usize, out: &mut Vec<Image>) {
        out.clear();
        let [kx, ky, kz] = self.reach;
        let cut2 = self.cutoff * self.cutoff;
        for dx in -kx..=kx {
            for dy in -ky..=ky {
                for dz in -kz..=kz {
                    let unwrapped = [(dx, 0), (dy, 1), (dz, 2)].map(|(d, a)| {
                        let (u, c) = (self.home[i][a] as i64 + d, self.cells[a] as i64);
                        (u.rem_euclid(c) as usize, u.div_euclid(c))
                    });
                    let cell = unwrapped.map(|(c, _)| c);
                    let n = unwrapped.map(|(_, n)| n);
                    let shift = Vector3::from_fn(|a, _| n[a] as f64 * self.box_lengths[a]);
                    let from = self.wrapped[i] - shift;
                    let positive_shift = n > [0; 3];
                    let members = &self.members
                        [(cell[0] * self.cells[1] + cell[1]) * self.cells[2] + cell[2]];
                    // Members ascend: skip those before `i` at once.
                    let after = members.partition_point(|&j| (j as usize) < i);
                    for &j in &members[after..] {
                        if j as usize == i && !positive_shift {
                            continue;
                        }
                        let offset = self.wrapped[j as usize] - from;
                        if offset.norm_squared() <= cut2 {
                            out.push((j, n, offset));
                        }
                    }
                }
            }
        }
        out.sort_by_key(|&(j, _, _)| j);
    }
}
