//! Rust vectors as numpy arrays (moved, not copied, except index conversion to int64).

use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;

pub fn arr2<'py, const N: usize>(py: Python<'py>, v: Vec<[f64; N]>) -> Bound<'py, PyAny> {
    let n = v.len();
    let flat: Vec<f64> = v.into_flattened();
    Array2::from_shape_vec((n, N), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

pub fn arr1<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

pub fn elements_i64<'py>(py: Python<'py>, e: &[[usize; 4]]) -> Bound<'py, PyAny> {
    let flat: Vec<i64> = e.iter().flatten().map(|&i| i as i64).collect();
    Array2::from_shape_vec((e.len(), 4), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

pub fn index_i64<'py>(py: Python<'py>, v: &[usize]) -> Bound<'py, PyAny> {
    let v: Vec<i64> = v.iter().map(|&i| i as i64).collect();
    PyArray1::from_vec(py, v).into_any()
}

/// (c, 4, 2) array of quadrilateral cells (corner coordinates or corner displacements).
pub fn quads<'py>(py: Python<'py>, v: Vec<[[f64; 2]; 4]>) -> Bound<'py, PyAny> {
    let n = v.len();
    let flat: Vec<f64> = v.into_iter().flatten().flatten().collect();
    Array3::from_shape_vec((n, 4, 2), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

/// (n, 2) int64 array of index pairs.
pub fn pairs_i64<'py>(py: Python<'py>, v: impl Iterator<Item = [usize; 2]>) -> Bound<'py, PyAny> {
    let flat: Vec<i64> = v.flat_map(|p| [p[0] as i64, p[1] as i64]).collect();
    let n = flat.len() / 2;
    Array2::from_shape_vec((n, 2), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

/// (rows, cols) float64 array from row-major values.
pub fn table<'py>(py: Python<'py>, rows: usize, cols: usize, v: Vec<f64>) -> Bound<'py, PyAny> {
    Array2::from_shape_vec((rows, cols), v)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

/// int64 array of indices.
pub fn ints<'py>(py: Python<'py>, v: impl Iterator<Item = usize>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v.map(|i| i as i64).collect()).into_any()
}
