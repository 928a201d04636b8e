//! Dirichlet elimination on the matrix level: the free-free block K_ff gathered from the full
//! matrix through a position map built once, the reduced right-hand side f_f - K_fc u_c and the
//! expansion of the reduced solution.

use super::csc::{column_pointers, for_column_chunks, CscMatrix};
use crate::error::{Error, Result};
use rayon::prelude::*;

/// Dirichlet elimination: the free-free block K_ff of a square matrix, gathered from the full
/// matrix through a position map built once (the constrained dofs never change within a run).
#[derive(Debug, Clone)]
pub struct Reduction {
    /// full dof -> reduced index, or `usize::MAX` for a constrained dof
    pub map: Vec<usize>,
    /// reduced index -> full dof
    pub free: Vec<usize>,
    /// pattern of K_ff (values empty)
    pub reduced: CscMatrix,
    /// for each entry of K_ff, its position in the full matrix's `val`
    gather: Vec<u32>,
}

impl Reduction {
    /// `constrained[d]` is true for a prescribed dof.
    pub fn new(full: &CscMatrix, constrained: &[bool]) -> Result<Self> {
        if constrained.len() != full.ncols {
            return Err(Error::SizeMismatch {
                what: "constrained dof mask".into(),
                expected: full.ncols,
                got: constrained.len(),
            });
        }
        let mut map = vec![usize::MAX; full.ncols];
        let mut free = Vec::new();
        for (d, &c) in constrained.iter().enumerate() {
            if !c {
                map[d] = free.len();
                free.push(d);
            }
        }
        let nf = free.len();
        if full.nnz() > u32::MAX as usize {
            return Err(Error::invalid(
                "matrix for the Dirichlet elimination",
                &format!("at most {} stored entries", u32::MAX),
                full.nnz(),
            ));
        }
        // K_ff column by column (parallel chunks, lengths first, then rows written in place);
        // each entry remembers its position in the full matrix
        let free_rows = |c: usize| {
            (full.col_ptr[free[c]]..full.col_ptr[free[c] + 1])
                .filter(|&k| map[full.row_idx[k]] != usize::MAX)
        };
        let col_ptr = column_pointers(
            nf,
            || (),
            |_, cols| cols.map(|c| free_rows(c).count()).collect(),
        );
        let mut row_idx = vec![0usize; col_ptr[nf]];
        let mut gather = vec![0u32; col_ptr[nf]];
        for_column_chunks(
            &col_ptr,
            &mut row_idx,
            || (),
            |_, cols, seg| {
                let mut i = 0;
                for c in cols {
                    for k in free_rows(c) {
                        seg[i] = map[full.row_idx[k]];
                        i += 1;
                    }
                }
            },
        );
        for_column_chunks(
            &col_ptr,
            &mut gather,
            || (),
            |_, cols, seg| {
                let mut i = 0;
                for c in cols {
                    for k in free_rows(c) {
                        seg[i] = k as u32;
                        i += 1;
                    }
                }
            },
        );
        Ok(Self {
            map,
            free,
            reduced: CscMatrix {
                nrows: nf,
                ncols: nf,
                col_ptr,
                row_idx,
                val: Vec::new(),
            },
            gather,
        })
    }

    /// K_ff values from the full matrix (same pattern as at construction).
    pub fn reduce(&self, full: &CscMatrix) -> CscMatrix {
        CscMatrix {
            val: self.values(full),
            ..self.reduced.clone()
        }
    }

    /// The entries of K_ff, in the order of `reduced`.
    fn values(&self, full: &CscMatrix) -> Vec<f64> {
        self.gather
            .par_iter()
            .map(|&k| full.val[k as usize])
            .collect()
    }

    /// Calls `f` with K_ff (values from `full`) without copying the reduced pattern: the values
    /// are set in `reduced` for the duration of the call.
    pub fn with_reduced<R>(&mut self, full: &CscMatrix, f: impl FnOnce(&CscMatrix) -> R) -> R {
        self.reduced.val = self.values(full);
        let r = f(&self.reduced);
        self.reduced.val = Vec::new();
        r
    }

    /// Right-hand side of the reduced system: f_f - K_fc u_c, with `u_c` the full vector holding
    /// the prescribed values (anything at free dofs is ignored).
    pub fn rhs(&self, full: &CscMatrix, f: &[f64], u_prescribed: &[f64]) -> Vec<f64> {
        let mut uc = u_prescribed.to_vec();
        for &d in &self.free {
            uc[d] = 0.0;
        }
        let kuc = full.matvec(&uc);
        self.free.iter().map(|&d| f[d] - kuc[d]).collect()
    }

    /// Full vector from the reduced solution and the prescribed values.
    pub fn expand(&self, uf: &[f64], u_prescribed: &[f64]) -> Vec<f64> {
        let mut u = u_prescribed.to_vec();
        for (i, &d) in self.free.iter().enumerate() {
            u[d] = uf[i];
        }
        u
    }
}
