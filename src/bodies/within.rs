//! The partners of one site within reach of the pair terms, compacted: of
//! a site's listed partners (within the list's reach, `cutoff + skin`),
//! those closer than the terms' largest cutoff, with their separations by
//! component in contiguous rows, so that the pair kernels load four pairs'
//! separations in one instruction per component and spend no lanes on the
//! listed pairs beyond every cutoff (about 30 % of a list with a skin of
//! 0.3 at a cutoff of 2.5: the shell's share `1 - (2.5 / 2.8)^3`).
//!
//! A separation is `x_i - x_j - shift`, the shift `c L` of the pair's image
//! counts `c` (zero for most pairs, their own minimum image): the bits of
//! [`super::neighbours::NeighbourList::half_pairs`]' separations.

use super::lanes::{Lanes, LANES, V4};
use nalgebra::Vector3;

/// The shifts `c L_k` of the image counts `c` along one axis `k`, at index
/// `c as u8`.
pub(super) type Shifts = [f64; 256];

/// One site's partners within reach and their separations, padded to whole
/// rows of [`LANES`] by repeating the last (the padding's results are
/// dropped by the kernels' mask of used lanes).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Within {
    /// The partners.
    pub partner: Vec<usize>,
    /// The separations' components and squared lengths.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
    pub r2: Vec<f64>,
    /// How many partners are within reach (the rows hold more: padding).
    pub count: usize,
}

impl Within {
    /// Keeps the partners `partners` (image counts `images`) of the site at
    /// `x` among `positions` whose squared separation is below `reach2`,
    /// in their listed order.
    #[inline(always)]
    pub fn collect(
        &mut self,
        x: &Vector3<f64>,
        (partners, images): (&[u32], &[[i8; 3]]),
        positions: &[Vector3<f64>],
        shifts: &[Shifts],
        reach2: f64,
    ) {
        // Room for every listed partner and a row of padding: each partner
        // is stored at the count, which advances only if it is within reach
        // (no branch; the count, at most the partners so far, is clamped to
        // the rows only so that no write needs a bounds check).
        let room = partners.len() + LANES;
        if self.partner.len() < room {
            self.partner.resize(room, 0);
            for v in [&mut self.x, &mut self.y, &mut self.z, &mut self.r2] {
                v.resize(room, 0.0);
            }
        }
        let partner = &mut self.partner[..room];
        let (xs, ys, zs, r2s) = (
            &mut self.x[..room],
            &mut self.y[..room],
            &mut self.z[..room],
            &mut self.r2[..room],
        );
        let (sx, sy, sz) = (&shifts[0], &shifts[1], &shifts[2]);
        let mut n = 0;
        for (&j, c) in partners.iter().zip(images) {
            let j = j as usize;
            let shift = Vector3::new(
                sx[c[0] as u8 as usize],
                sy[c[1] as u8 as usize],
                sz[c[2] as u8 as usize],
            );
            let r = x - positions[j] - shift;
            let r2 = r.x * r.x + r.y * r.y + r.z * r.z;
            let k = n.min(room - 1);
            (partner[k], xs[k], ys[k], zs[k], r2s[k]) = (j, r.x, r.y, r.z, r2);
            n += usize::from(r2 < reach2);
        }
        self.count = n;
        if n > 0 {
            for k in n..n.next_multiple_of(LANES) {
                (partner[k], xs[k], ys[k], zs[k], r2s[k]) =
                    (partner[n - 1], xs[n - 1], ys[n - 1], zs[n - 1], r2s[n - 1]);
            }
        }
    }

    /// The row of four pairs from the kept pair `start`: the partners,
    /// the separations and their squared lengths.
    #[inline(always)]
    pub fn row<T: Lanes>(&self, start: usize) -> ([usize; LANES], V4<T>, T) {
        let row = start..start + LANES;
        let load = |v: &[f64]| T::from_array(v[row.clone()].try_into().unwrap_or_default());
        let r = V4 {
            x: load(&self.x),
            y: load(&self.y),
            z: load(&self.z),
        };
        let js = self.partner[row.clone()].try_into().unwrap_or_default();
        (js, r, load(&self.r2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Of five listed partners in a periodic box of side 10, those within
    /// reach 2 are kept in their order with the separations written out
    /// here (two of them through their images; two beyond reach, one
    /// across the box where its zero image counts leave it), and the last row is
    /// padded with the last kept; none is kept of a partner beyond reach.
    #[test]
    fn keeps_the_partners_within_reach_with_their_separations() {
        let positions = [
            Vector3::new(0.5, 0.5, 0.5),
            Vector3::new(1.5, 0.5, 0.5),
            Vector3::new(9.5, 0.5, 0.5),
            Vector3::new(3.0, 0.5, 0.5),
            Vector3::new(0.5, 9.0, 0.5),
            Vector3::new(0.5, 0.5, 9.0),
        ];
        let mut shifts = vec![[0.0; 256]; 3];
        for row in shifts.iter_mut() {
            for (c, s) in row.iter_mut().enumerate() {
                *s = 10.0 * f64::from(c as u8 as i8);
            }
        }
        let partners = [1, 2, 3, 4, 5];
        let images = [[0; 3], [-1, 0, 0], [0; 3], [0, 0, 0], [0, 0, -1]];
        let mut within = Within::default();
        within.collect(
            &positions[0],
            (&partners, &images),
            &positions,
            &shifts,
            4.0,
        );
        assert_eq!(within.count, 3);
        assert_eq!(&within.partner[..LANES], &[1, 2, 5, 5]);
        assert_eq!(&within.x[..LANES], &[-1.0, 1.0, 0.0, 0.0]);
        assert_eq!(&within.z[..LANES], &[0.0, 0.0, 1.5, 1.5]);
        assert_eq!(&within.r2[..LANES], &[1.0, 1.0, 2.25, 2.25]);
        within.collect(&positions[0], (&[3], &[[0; 3]]), &positions, &shifts, 4.0);
        assert_eq!(within.count, 0);
    }
}
