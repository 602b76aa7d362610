//! The cost fits of the examples: measured CPU seconds against counts of
//! the work a sum does, by least squares (nalgebra's SVD).

use nalgebra::{DMatrix, DVector};

/// The per-unit costs `x` minimising `|A x - b|` for the design rows
/// `design` (`columns` counts per measured case, row after row) and the
/// measured `seconds`, and the fit's relative residual `|A x - b| / |b|`.
pub fn fit(design: &[f64], columns: usize, seconds: &[f64]) -> (DVector<f64>, f64) {
    let a = DMatrix::from_row_slice(seconds.len(), columns, design);
    let b = DVector::from_column_slice(seconds);
    let x = a
        .clone()
        .svd(true, true)
        .solve(&b, 1e-300)
        .expect("least squares");
    let residual = (&a * &x - &b).norm() / b.norm();
    (x, residual)
}
