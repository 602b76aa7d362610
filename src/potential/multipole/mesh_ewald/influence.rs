//! The influence function of smooth PME (Essmann et al. 1995, eqs 3.9 and
//! 4.7): on the mesh mode `m` with wave vector `k = 2 pi (m_x / L_x, m_y /
//! L_y, m_z / L_z)` (`m_a` folded into `-K_a / 2..K_a / 2`),
//! `G(m) = (4 pi / V) exp(-k^2 / 4 alpha^2) / k^2 |b_x(m_x) b_y(m_y) b_z(m_z)|^2`,
//! `G(0) = 0` (conducting or neutralised `k = 0` term; the surface and
//! background terms are added apart), on the half spectrum of
//! [`crate::potential::multipole::fft3::RealFft3`].

use super::bspline::euler_moduli;
use crate::potential::multipole::ewald_terms::mode_weight;
use crate::potential::multipole::fft3::RealFft3;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// `G` on the half spectrum of `fft` (layout `[k_z][k_y][k_x]`).
pub(crate) fn influence(
    fft: &RealFft3,
    box_lengths: &Vector3<f64>,
    alpha: f64,
    order: usize,
) -> Vec<f64> {
    let n = fft.dims();
    let moduli: [Vec<f64>; 3] = std::array::from_fn(|a| euler_moduli(order, n[a]));
    let wave = |a: usize, m: usize| {
        let signed = if m <= n[a] / 2 {
            m as f64
        } else {
            m as f64 - n[a] as f64
        };
        2.0 * PI * signed / box_lengths[a]
    };
    let scale = 4.0 * PI / box_lengths.product();
    let mut out = vec![0.0; fft.spectrum_len()];
    for mz in 0..=n[2] / 2 {
        for my in 0..n[1] {
            for mx in 0..n[0] {
                if mx == 0 && my == 0 && mz == 0 {
                    continue;
                }
                let k2 = wave(0, mx).powi(2) + wave(1, my).powi(2) + wave(2, mz).powi(2);
                out[fft.spectrum_index([mx, my, mz])] =
                    scale * mode_weight(alpha, k2) * moduli[0][mx] * moduli[1][my] * moduli[2][mz];
            }
        }
    }
    out
}
