//! The structured tensor grid of Q4 elements a FEM or XFEM problem states ([`FeGrid`]; `fe`
//! builds its mesh, [`crate::fe::Mesh::of_grid`]) and the largest grid accepted.

/// Largest grid accepted (elements), so that a mistyped size is refused at once instead of
/// exhausting the memory: 1000 x 1000 Q4 elements (2e6 dofs) take about 5 GB and 25 s for one FEM
/// solve on a 2-core machine (sparse Cholesky fill grows as n log n), so 2e6 elements is about as
/// much as a 16-32 GB machine holds.
pub const MAX_ELEMENTS: usize = 2_000_000;

/// A structured tensor grid of Q4 elements over the domain: uniform (`xs`, `ys` empty) or on the
/// given grid lines (then `nx`, `ny` are their counts - 1).
#[derive(Debug, Clone, PartialEq)]
pub struct FeGrid {
    pub nx: usize,
    pub ny: usize,
    /// vertical grid lines (empty: uniform)
    pub xs: Vec<f64>,
    /// horizontal grid lines (empty: uniform)
    pub ys: Vec<f64>,
}

impl FeGrid {
    /// The uniform nx x ny grid.
    pub fn uniform(nx: usize, ny: usize) -> Self {
        Self {
            nx,
            ny,
            xs: Vec::new(),
            ys: Vec::new(),
        }
    }
}
