//! numpy arguments at the boundary: dtype and shape checked once, with
//! messages naming the argument (`TypeError` for the dtype, `ValueError` for
//! the shape); a batch of `n` items of a fixed shape, or one item.

use nalgebra::{Matrix3, Vector3};
use numpy::ndarray::{ArrayD, ArrayViewD, Axis, IxDyn};
use numpy::prelude::*;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArray};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::Quat;

/// A read-only float64 argument holding `n` items of shape `item` (shape
/// `(n, *item)`), or a single item (shape `item`).
pub(crate) struct Items<'py> {
    name: &'static str,
    array: PyReadonlyArrayDyn<'py, f64>,
    single: bool,
}

/// Formats a shape as Python prints it: `(3,)`, `(n, 4)`.
fn shape_str<T: std::fmt::Display>(dims: &[T]) -> String {
    let parts: Vec<String> = dims.iter().map(|d| d.to_string()).collect();
    match parts.len() {
        1 => format!("({},)", parts[0]),
        _ => format!("({})", parts.join(", ")),
    }
}

impl<'py> Items<'py> {
    /// Checks `obj` (argument `name`) is a float64 ndarray of shape `(n, *item)` or `item`.
    pub(crate) fn new(
        obj: &Bound<'py, PyAny>,
        name: &'static str,
        item: &[usize],
    ) -> PyResult<Self> {
        let array = match obj.cast::<PyArrayDyn<f64>>() {
            Ok(a) => a.readonly(),
            Err(_) => {
                let got = match obj.cast::<PyUntypedArray>() {
                    Ok(a) => format!("an array of dtype {}", a.dtype()),
                    Err(_) => format!("{}", obj.get_type().name()?),
                };
                return Err(PyTypeError::new_err(format!(
                    "{name}: expected a numpy array of dtype float64, got {got}"
                )));
            }
        };
        let shape = array.shape();
        let single = shape == item;
        let batched = shape.len() == item.len() + 1 && shape[1..] == *item;
        if !(single || batched) {
            let mut batched = vec!["n".to_string()];
            batched.extend(item.iter().map(|d| d.to_string()));
            return Err(PyValueError::new_err(format!(
                "{name}: expected shape {} or {}, got {}",
                shape_str(&batched),
                shape_str(item),
                shape_str(shape)
            )));
        }
        Ok(Items {
            name,
            array,
            single,
        })
    }

    /// The number of items, `None` for a single item.
    fn len(&self) -> Option<usize> {
        (!self.single).then(|| self.array.shape()[0])
    }

    /// Item `i` (the whole array for a single item).
    fn item(&self, i: usize) -> ArrayViewD<'_, f64> {
        let view = self.array.as_array();
        if self.single {
            view
        } else {
            view.index_axis_move(Axis(0), i)
        }
    }

    /// Item `i` flattened in C order into `K` numbers.
    fn values<const K: usize>(&self, i: usize) -> [f64; K] {
        let mut out = [0.0; K];
        for (o, x) in out.iter_mut().zip(self.item(i).iter()) {
            *o = *x;
        }
        out
    }

    /// Item `i` as a quaternion `(q0, q1, q2, q3)`.
    pub(crate) fn quat(&self, i: usize) -> Quat {
        Quat(self.values(i))
    }

    /// Item `i` as a 3-vector.
    pub(crate) fn vector(&self, i: usize) -> Vector3<f64> {
        Vector3::from(self.values::<3>(i))
    }

    /// Item `i` as a 3x3 matrix (rows of the numpy array are rows).
    pub(crate) fn matrix(&self, i: usize) -> Matrix3<f64> {
        Matrix3::from_row_slice(&self.values::<9>(i))
    }

    /// Item `i` as a scalar.
    pub(crate) fn scalar(&self, i: usize) -> f64 {
        self.values::<1>(i)[0]
    }

    /// How to name item `i` in a message: `r[3]`, or `r` for a single item.
    pub(crate) fn label(&self, i: usize) -> String {
        if self.single {
            self.name.to_string()
        } else {
            format!("{}[{i}]", self.name)
        }
    }
}

/// The common batch of several arguments: `(n, single)`. Single items go with
/// any batch; batches must have the same length.
pub(crate) fn common_len(args: &[&Items<'_>]) -> PyResult<(usize, bool)> {
    let mut batch: Option<(usize, &'static str)> = None;
    for arg in args {
        if let Some(n) = arg.len() {
            match batch {
                Some((m, other)) if m != n => {
                    return Err(PyValueError::new_err(format!(
                        "{}: {n} items, but {other} has {m}",
                        arg.name
                    )));
                }
                _ => batch = Some((n, arg.name)),
            }
        }
    }
    Ok(batch.map_or((1, true), |(n, _)| (n, false)))
}

/// A new array of `n` items of shape `item` (or one item when `single`), item
/// `i` computed by `f(i)` as `K` numbers in C order.
pub(crate) fn collect<'py, const K: usize>(
    py: Python<'py>,
    (n, single): (usize, bool),
    item: &[usize],
    mut f: impl FnMut(usize) -> PyResult<[f64; K]>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let mut data = Vec::with_capacity(n * K);
    for i in 0..n {
        data.extend_from_slice(&f(i)?);
    }
    let shape: Vec<usize> = if single {
        item.to_vec()
    } else {
        std::iter::once(n).chain(item.iter().copied()).collect()
    };
    let array = ArrayD::from_shape_vec(IxDyn(&shape), data)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// A 3x3 matrix as 9 numbers in C (row-major) order.
pub(crate) fn row_major(m: &Matrix3<f64>) -> [f64; 9] {
    let t = m.transpose();
    let mut out = [0.0; 9];
    out.copy_from_slice(t.as_slice());
    out
}

/// An optional argument that must be a single item of shape `item` (not a batch).
pub(crate) fn single<'py>(
    obj: Option<&Bound<'py, PyAny>>,
    name: &'static str,
    item: &[usize],
) -> PyResult<Option<Items<'py>>> {
    let Some(obj) = obj else { return Ok(None) };
    let items = Items::new(obj, name, item)?;
    if !common_len(&[&items])?.1 {
        return Err(PyValueError::new_err(format!(
            "{name}: expected a single item of shape {}, not a batch",
            shape_str(item)
        )));
    }
    Ok(Some(items))
}
