//! Array arguments at the boundary, converted once: any array-like of
//! numbers (lists, tuples, scalars, float32 or integer arrays,
//! non-contiguous or Fortran-order views) becomes a float64 array (no copy
//! when it already is one), every value checked finite and every
//! quaternion nonzero, with messages naming the argument and the first bad
//! row (`orientations[3]: quaternion is zero`, `dipoles[1][2]: not finite
//! (nan)`). Two views of a converted argument: [`Items`], a batch of `n`
//! items of a fixed shape or one item, and [`Numbers`], the values in C
//! order with their shape. Results go back as arrays through [`array()`],
//! or through [`collect`], which refuses values that overflowed.

use super::args::{invalid, wrong_type};
use nalgebra::{Matrix3, Vector3};
use numpy::ndarray::{ArrayD, ArrayViewD, Axis, Dimension, IxDyn};
use numpy::prelude::*;
use numpy::{AllowTypeChange, PyArrayDyn, PyArrayLikeDyn};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::Quat;

/// What an argument's values must be besides finite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Values {
    /// Any finite numbers.
    Finite,
    /// Quaternions along the last axis (of length 4), none of them zero.
    Quaternions,
}

/// Formats a shape as Python prints it: `(3,)`, `(n, 4)`.
fn shape_str<T: std::fmt::Display>(dims: &[T]) -> String {
    let parts: Vec<String> = dims.iter().map(|d| d.to_string()).collect();
    match parts.len() {
        1 => format!("({},)", parts[0]),
        _ => format!("({})", parts.join(", ")),
    }
}

/// `name[i][j]...` for the multi-index `index`.
fn indexed(name: &str, index: &[usize]) -> String {
    index
        .iter()
        .fold(name.to_string(), |s, i| format!("{s}[{i}]"))
}

/// A non-finite value as numpy prints it: `nan`, `inf`, `-inf`.
fn non_finite(x: f64) -> &'static str {
    match x {
        x if x.is_nan() => "nan",
        x if x > 0.0 => "inf",
        _ => "-inf",
    }
}

/// The C-order multi-index of flat position `k` in `shape`.
fn unravel(mut k: usize, shape: &[usize]) -> Vec<usize> {
    let mut index = vec![0; shape.len()];
    for (i, d) in index.iter_mut().zip(shape).rev() {
        *i = k % d.max(&1);
        k /= d.max(&1);
    }
    index
}

/// The first value of `view` (C order) that is not finite, or with
/// `Values::Quaternions` the first zero quaternion, as an error naming it.
fn check_values(view: &ArrayViewD<'_, f64>, name: &str, values: Values) -> PyResult<()> {
    if let Some((index, x)) = view.indexed_iter().find(|(_, x)| !x.is_finite()) {
        return Err(invalid(
            &indexed(name, index.slice()),
            format!("not finite ({})", non_finite(*x)),
        ));
    }
    let quaternions = values == Values::Quaternions && view.shape().last() == Some(&4);
    if quaternions {
        let last = Axis(view.ndim() - 1);
        let leading = &view.shape()[..view.ndim() - 1];
        if let Some(k) = view
            .lanes(last)
            .into_iter()
            .position(|q| q.iter().all(|x| *x == 0.0))
        {
            return Err(invalid(
                &indexed(name, &unravel(k, leading)),
                "quaternion is zero",
            ));
        }
    }
    Ok(())
}

/// Converts `obj` (argument `name`) once to a float64 array: a `TypeError`
/// for what is not an array of numbers.
fn convert<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyArrayLikeDyn<'py, f64, AllowTypeChange>> {
    let array = obj
        .extract::<PyArrayLikeDyn<'py, f64, AllowTypeChange>>()
        .map_err(|_| wrong_type(obj, name, "an array of numbers"))?;
    Ok(array)
}

/// A float64 argument holding `n` items of shape `item` (shape `(n,
/// *item)`), or a single item (shape `item`).
pub(crate) struct Items<'py> {
    name: &'static str,
    array: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    single: bool,
}

impl<'py> Items<'py> {
    /// Converts `obj` (argument `name`) and checks its shape is `(n, *item)`
    /// or `item`, then its values.
    pub(crate) fn new(
        obj: &Bound<'py, PyAny>,
        name: &'static str,
        item: &[usize],
        values: Values,
    ) -> PyResult<Self> {
        let array = convert(obj, name)?;
        let shape = array.shape();
        let single = shape == item;
        let batched = shape.len() == item.len() + 1 && shape[1..] == *item;
        if !(single || batched) {
            let mut batched = vec!["n".to_string()];
            batched.extend(item.iter().map(|d| d.to_string()));
            let expected = format!("{} or {}", shape_str(&batched), shape_str(item));
            return Err(wrong_shape(name, &expected, shape));
        }
        check_values(&array.as_array(), name, values)?;
        Ok(Items {
            name,
            array,
            single,
        })
    }

    /// [`Items::new`] of finite values for an optional argument.
    pub(crate) fn optional(
        obj: Option<&Bound<'py, PyAny>>,
        name: &'static str,
        item: &[usize],
    ) -> PyResult<Option<Self>> {
        obj.map(|o| Items::new(o, name, item, Values::Finite))
            .transpose()
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

    /// The number of values in one item.
    pub(crate) fn item_len(&self) -> usize {
        let shape = self.array.shape();
        shape[usize::from(!self.single)..].iter().product()
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
                    return Err(invalid(arg.name, format!("{n} items, but {other} has {m}")));
                }
                _ => batch = Some((n, arg.name)),
            }
        }
    }
    Ok(batch.map_or((1, true), |(n, _)| (n, false)))
}

/// An optional argument that must be a single item of shape `item` (not a batch).
pub(crate) fn single<'py>(
    obj: Option<&Bound<'py, PyAny>>,
    name: &'static str,
    item: &[usize],
) -> PyResult<Option<Items<'py>>> {
    let Some(items) = Items::optional(obj, name, item)? else {
        return Ok(None);
    };
    if !common_len(&[&items])?.1 {
        return Err(invalid(
            name,
            format!(
                "expected a single item of shape {}, not a batch",
                shape_str(item)
            ),
        ));
    }
    Ok(Some(items))
}

/// A converted argument's values in C order, with its shape.
pub(crate) struct Numbers {
    name: &'static str,
    pub(crate) shape: Vec<usize>,
    pub(crate) values: Vec<f64>,
}

impl Numbers {
    /// Converts `arg` (argument `name`) and checks its values.
    pub(crate) fn new(
        arg: &Bound<'_, PyAny>,
        name: &'static str,
        values: Values,
    ) -> PyResult<Self> {
        let array = convert(arg, name)?;
        let view = array.as_array();
        check_values(&view, name, values)?;
        Ok(Numbers {
            name,
            shape: view.shape().to_vec(),
            values: view.iter().copied().collect(),
        })
    }

    /// Items of `W` numbers (the last axis), the array having one of the
    /// leading ranks `ranks` (shape `(..., W)`); `expected` spells the shapes
    /// for the message. Returns the items and the leading shape.
    pub(crate) fn items<const W: usize>(
        &self,
        ranks: &[usize],
        expected: &str,
    ) -> PyResult<(Vec<[f64; W]>, Vec<usize>)> {
        let (last, leading) = self.shape.split_last().unwrap_or((&0, &[]));
        if *last != W || !ranks.contains(&leading.len()) {
            return Err(wrong_shape(self.name, expected, &self.shape));
        }
        let items = self
            .values
            .chunks_exact(W)
            .map(|c| std::array::from_fn(|k| c[k]))
            .collect();
        Ok((items, leading.to_vec()))
    }

    /// A one-dimensional array `(n,)`.
    pub(crate) fn series(self) -> PyResult<Vec<f64>> {
        if self.shape.len() == 1 {
            Ok(self.values)
        } else {
            Err(wrong_shape(self.name, "(n,)", &self.shape))
        }
    }

    /// A single value of `W` numbers.
    pub(crate) fn single<const W: usize>(&self, expected: &str) -> PyResult<[f64; W]> {
        Ok(self.items::<W>(&[0], expected)?.0[0])
    }
}

/// The error for argument `name` of a shape other than `expected` (spelled
/// as Python prints shapes), `got` the shape it has.
pub(crate) fn wrong_shape(name: &str, expected: &str, got: &[usize]) -> PyErr {
    invalid(
        name,
        format!("expected shape {expected}, got {}", shape_str(got)),
    )
}

/// The error for a result that is not finite for finite arguments: the
/// arguments overflow float64 (`what` names the result and the item).
pub(crate) fn overflow(what: &str, x: f64) -> PyErr {
    invalid(
        what,
        format!(
            "not finite ({}) for finite arguments: their magnitudes overflow float64",
            non_finite(x)
        ),
    )
}

/// The first non-finite value of `values` as an [`overflow`] error naming
/// `name` and the index of the item of `width` numbers holding it.
pub(crate) fn check_finite(name: &str, values: &[f64], width: usize) -> PyResult<()> {
    match values.iter().position(|x| !x.is_finite()) {
        Some(k) => Err(overflow(
            &format!("{name}[{}]", k / width.max(1)),
            values[k],
        )),
        None => Ok(()),
    }
}

/// A numpy array of `shape` from `values` (C order).
pub(crate) fn array<'py>(
    py: Python<'py>,
    shape: &[usize],
    values: Vec<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    // The callers size `values` from `shape`: a mismatch is a bug here.
    let a = ArrayD::from_shape_vec(IxDyn(shape), values)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// A new array of `n` items of shape `item` (or one item when `single`), item
/// `i` computed by `f(i)` as `K` numbers in C order; a non-finite number is
/// an [`overflow`] error naming the item.
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
    check_finite("result", &data, K)?;
    let shape: Vec<usize> = if single {
        item.to_vec()
    } else {
        std::iter::once(n).chain(item.iter().copied()).collect()
    };
    array(py, &shape, data)
}

/// A 3x3 matrix as 9 numbers in C (row-major) order.
pub(crate) fn row_major(m: &Matrix3<f64>) -> [f64; 9] {
    let t = m.transpose();
    let mut out = [0.0; 9];
    out.copy_from_slice(t.as_slice());
    out
}
