//! Rust vectors as numpy arrays for the grid solve (moved, not copied, except index conversion
//! to int64); a run's result crosses as a record ([`crate::record`]).

use numpy::ndarray::Array2;
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
