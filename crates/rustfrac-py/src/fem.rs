//! Plain Q4 FEM: the plate run's result for Python, and a grid solve with explicit conditions.

use crate::arrays::{arr1, arr2, elements_i64};
use crate::errors::detached;
use crate::progress::Progress;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::error::Error as CoreError;
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{Dirichlet, FemModel, LinearSystem};
use rustfrac_core::fem_driver;
use rustfrac_core::problem::Problem;
use rustfrac_core::problem::{Elastic, Plane};

/// Runs the FEM plate of `p` and returns its record ([`rustfrac_core::output`]).
pub fn run<'py>(py: Python<'py>, p: &Problem, prog: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let r = detached(py, "fem plate", || {
        prog.report(0, 1, "fem: assemble + factorise + solve", true);
        let r = fem_driver::run(p);
        prog.report(1, 1, "fem: done", true);
        r
    });
    if let Some(err) = prog.take_error() {
        return Err(err);
    }
    crate::record::to_dict(py, r?.into_record(p))
}

/// Solves a uniform rectangular Q4 grid (origin 0, size width x height, nx x ny elements) with
/// explicit Dirichlet conditions `fixed_dofs` -> `fixed_values` (dof = 2 node + component) and
/// nodal forces `forces` (length 2 (nx+1) (ny+1), or empty for none). Nodes are numbered row by
/// row from the bottom-left corner. Too few conditions (a free rigid-body mode, named) or a
/// numerically singular system (pivot-ratio bound above `COND_SINGULAR`) raise
/// `SingularSystemError`.
///
/// Returns a dict: coords, elements, u, reactions, nodal_stress, energy, residual, n_dofs.
#[pyfunction]
#[pyo3(signature = (*, width, height, nx, ny, e, nu, plane = "strain", thickness = 1.0,
                    fixed_dofs, fixed_values, forces = Vec::new()))]
#[allow(clippy::too_many_arguments)]
pub fn solve_fem_grid<'py>(
    py: Python<'py>,
    width: f64,
    height: f64,
    nx: usize,
    ny: usize,
    e: f64,
    nu: f64,
    plane: &str,
    thickness: f64,
    fixed_dofs: Vec<usize>,
    fixed_values: Vec<f64>,
    forces: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (model, sol) = detached(py, "fem grid", || {
        if fixed_dofs.len() != fixed_values.len() {
            return Err(CoreError::SizeMismatch {
                what: "fixed_values".into(),
                expected: fixed_dofs.len(),
                got: fixed_values.len(),
            });
        }
        let mat = Elastic::new(e, nu, Plane::parse(plane)?, thickness)?;
        let mesh = Mesh::uniform(0.0, 0.0, width, height, nx, ny)?;
        let model = FemModel::new(mesh, mat, 2)?;
        let n = model.n_dofs();
        let f = if forces.is_empty() {
            vec![0.0; n]
        } else if forces.len() == n {
            forces
        } else {
            return Err(CoreError::SizeMismatch {
                what: "forces".into(),
                expected: n,
                got: forces.len(),
            });
        };
        let bc = Dirichlet {
            dofs: fixed_dofs.into_iter().zip(fixed_values).collect(),
        };
        bc.check_rigid_modes(&model.mesh.coords)?;
        let sys = LinearSystem::new(model.stiffness(), &bc)?;
        sys.checked_condition("solve", false)?;
        let sol = sys.solve(&f, 1.0)?;
        Ok((model, sol))
    })?;
    let nodal = model.nodal_stresses(&sol.u);
    let d = PyDict::new(py);
    d.set_item("coords", arr2(py, model.mesh.coords.clone()))?;
    d.set_item("elements", elements_i64(py, &model.mesh.elements))?;
    d.set_item("n_dofs", model.n_dofs())?;
    d.set_item("u", arr1(py, sol.u))?;
    d.set_item("reactions", arr1(py, sol.reactions))?;
    d.set_item("nodal_stress", arr2(py, nodal))?;
    d.set_item("energy", sol.energy)?;
    d.set_item("residual", sol.residual)?;
    Ok(d)
}
