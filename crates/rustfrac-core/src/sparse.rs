//! Compressed sparse column (CSC) matrices, the sparsity pattern built once from element (or bond)
//! dof blocks, and race-free parallel value assembly.
//!
//! Assembly colours the blocks so that two blocks of one colour share no dof; the blocks of a colour
//! are then scattered in parallel (rayon) without locks or atomics, and the result is deterministic
//! (each entry receives its contributions in the same order at every run).

use crate::error::{Error, Result};
use rayon::prelude::*;

/// A square or rectangular CSC matrix with sorted, unique row indices in every column.
#[derive(Debug, Clone, PartialEq)]
pub struct CscMatrix {
    pub nrows: usize,
    pub ncols: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    pub val: Vec<f64>,
}

impl CscMatrix {
    /// Builds a matrix from (row, col, value) triplets; duplicates are summed, indices sorted.
    pub fn from_triplets(nrows: usize, ncols: usize, trip: &[(usize, usize, f64)]) -> Result<Self> {
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); ncols];
        for &(r, c, v) in trip {
            if r >= nrows || c >= ncols {
                return Err(Error::invalid(
                    "triplet index",
                    &format!("row < {nrows} and col < {ncols}"),
                    format!("({r}, {c})"),
                ));
            }
            cols[c].push((r, v));
        }
        let mut col_ptr = Vec::with_capacity(ncols + 1);
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        col_ptr.push(0);
        for col in cols.iter_mut() {
            col.sort_by_key(|e| e.0);
            let mut last = usize::MAX;
            for &(r, v) in col.iter() {
                if r == last {
                    *val.last_mut().unwrap() += v;
                } else {
                    row_idx.push(r);
                    val.push(v);
                    last = r;
                }
            }
            col_ptr.push(row_idx.len());
        }
        Ok(Self {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            val,
        })
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Position of entry (r, c) in `val`, if stored.
    #[inline]
    pub fn find(&self, r: usize, c: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[c], self.col_ptr[c + 1]);
        self.row_idx[a..b].binary_search(&r).ok().map(|k| a + k)
    }

    /// Entry (r, c), zero if not stored.
    pub fn get(&self, r: usize, c: usize) -> f64 {
        self.find(r, c).map_or(0.0, |k| self.val[k])
    }

    /// y = A x.
    pub fn matvec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.nrows];
        for (c, &xc) in x.iter().enumerate().take(self.ncols) {
            if xc == 0.0 {
                continue;
            }
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                y[self.row_idx[k]] += self.val[k] * xc;
            }
        }
        y
    }

    /// Largest |A - A^T| entry relative to the largest |A| entry (0 for a symmetric matrix).
    pub fn asymmetry(&self) -> f64 {
        let mut amax: f64 = 0.0;
        let mut dmax: f64 = 0.0;
        for c in 0..self.ncols {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[k];
                amax = amax.max(self.val[k].abs());
                dmax = dmax.max((self.val[k] - self.get(c, r)).abs());
            }
        }
        if amax == 0.0 {
            0.0
        } else {
            dmax / amax
        }
    }

    /// Dense copy (tests and small systems only).
    pub fn to_dense(&self) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; self.ncols]; self.nrows];
        for (c, w) in self.col_ptr.windows(2).enumerate() {
            for k in w[0]..w[1] {
                d[self.row_idx[k]][c] += self.val[k];
            }
        }
        d
    }
}

/// Sparsity pattern of a matrix assembled from dof blocks (an element's dofs, a bond's dofs),
/// with the block colouring used for parallel assembly. Built once, reused for every re-assembly.
///
/// `rows_of[b]` are the dofs whose *rows* block `b` writes and `cols_of[b]` the dofs of its columns.
/// For symmetric FEM assembly they are the same list; the splice coupling writes only the rows of
/// the nodes of one kind (DESIGN.md section 4), so rows and columns differ there.
#[derive(Debug, Clone)]
pub struct Pattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// colours[c] = blocks of colour c; two blocks of one colour write no common row.
    pub colours: Vec<Vec<usize>>,
}

impl Pattern {
    /// Builds the pattern of the square n x n matrix receiving the blocks. Each block writes the
    /// full product rows x cols. Diagonal entries are always present (so a Dirichlet row or an
    /// isolated dof can still be factorised or reported).
    pub fn new(n: usize, rows_of: &[Vec<usize>], cols_of: &[Vec<usize>]) -> Result<Self> {
        if rows_of.len() != cols_of.len() {
            return Err(Error::SizeMismatch {
                what: "pattern blocks (rows vs cols)".into(),
                expected: rows_of.len(),
                got: cols_of.len(),
            });
        }
        // column -> blocks touching it as a column
        let mut cnt = vec![0usize; n + 1];
        for cols in cols_of {
            for &c in cols {
                if c >= n {
                    return Err(Error::invalid("dof index", &format!("< {n}"), c));
                }
                cnt[c + 1] += 1;
            }
        }
        for r in rows_of {
            for &d in r {
                if d >= n {
                    return Err(Error::invalid("dof index", &format!("< {n}"), d));
                }
            }
        }
        for i in 0..n {
            cnt[i + 1] += cnt[i];
        }
        let mut fill = cnt.clone();
        let mut blocks_of_col = vec![0usize; cnt[n]];
        for (b, cols) in cols_of.iter().enumerate() {
            for &c in cols {
                blocks_of_col[fill[c]] = b;
                fill[c] += 1;
            }
        }
        // each column: union of the block rows, sorted unique (parallel over columns)
        let cols: Vec<Vec<usize>> = (0..n)
            .into_par_iter()
            .map(|c| {
                let mut rows: Vec<usize> = vec![c];
                for &b in &blocks_of_col[cnt[c]..cnt[c + 1]] {
                    rows.extend_from_slice(&rows_of[b]);
                }
                rows.sort_unstable();
                rows.dedup();
                rows
            })
            .collect();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut total = 0;
        for c in &cols {
            total += c.len();
            col_ptr.push(total);
        }
        let mut row_idx = Vec::with_capacity(total);
        for c in cols {
            row_idx.extend(c);
        }
        let colours = colour_blocks(n, rows_of);
        Ok(Self {
            n,
            col_ptr,
            row_idx,
            colours,
        })
    }

    /// Symmetric case: every block writes rows and columns of the same dofs.
    pub fn symmetric(n: usize, blocks: &[Vec<usize>]) -> Result<Self> {
        Self::new(n, blocks, blocks)
    }

    /// A zero matrix with this pattern.
    pub fn zeros(&self) -> CscMatrix {
        CscMatrix {
            nrows: self.n,
            ncols: self.n,
            col_ptr: self.col_ptr.clone(),
            row_idx: self.row_idx.clone(),
            val: vec![0.0; self.row_idx.len()],
        }
    }

    /// Assembles `A = sum_b scatter(block_b)` into a matrix with this pattern, in parallel.
    ///
    /// `block(b, out)` writes the dense block of `b` into `out` (row-major, rows_of[b].len() x
    /// cols_of[b].len()). Blocks of one colour share no row, so the parallel scatter is race-free.
    pub fn assemble<F>(&self, rows_of: &[Vec<usize>], cols_of: &[Vec<usize>], block: F) -> CscMatrix
    where
        F: Fn(usize, &mut Vec<f64>) + Sync,
    {
        let mut a = self.zeros();
        let ptr = SyncPtr(a.val.as_mut_ptr());
        let col_ptr = &a.col_ptr;
        let row_idx = &a.row_idx;
        for colour in &self.colours {
            colour.par_iter().for_each_init(Vec::new, |buf, &b| {
                buf.clear();
                block(b, buf);
                let (rows, cols) = (&rows_of[b], &cols_of[b]);
                debug_assert_eq!(buf.len(), rows.len() * cols.len());
                for (j, &c) in cols.iter().enumerate() {
                    let seg = &row_idx[col_ptr[c]..col_ptr[c + 1]];
                    for (i, &r) in rows.iter().enumerate() {
                        let v = buf[i * cols.len() + j];
                        if v == 0.0 {
                            continue;
                        }
                        let k = col_ptr[c] + seg.binary_search(&r).expect("entry in pattern");
                        // SAFETY: blocks of one colour write disjoint rows, so no two threads
                        // touch the same entry `k`; `k` < nnz by construction of the pattern.
                        unsafe { *ptr.get().add(k) += v };
                    }
                }
            });
        }
        a
    }
}

#[derive(Clone, Copy)]
struct SyncPtr(*mut f64);
// SAFETY: used only for disjoint writes (see `Pattern::assemble`).
unsafe impl Sync for SyncPtr {}
unsafe impl Send for SyncPtr {}
impl SyncPtr {
    #[inline]
    fn get(self) -> *mut f64 {
        self.0
    }
}

/// Greedy colouring of the blocks: a block takes the lowest colour not yet used by a block that
/// shares one of its row dofs.
fn colour_blocks(n: usize, rows_of: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut used: Vec<Vec<u64>> = vec![Vec::new(); n]; // per dof: bitset of colours (64 per word)
    let mut colours: Vec<Vec<usize>> = Vec::new();
    for (b, rows) in rows_of.iter().enumerate() {
        let mut c = 0usize;
        loop {
            let (w, bit) = (c / 64, c % 64);
            let taken = rows
                .iter()
                .any(|&d| used[d].get(w).is_some_and(|m| m & (1u64 << bit) != 0));
            if !taken {
                break;
            }
            c += 1;
        }
        let (w, bit) = (c / 64, c % 64);
        for &d in rows {
            if used[d].len() <= w {
                used[d].resize(w + 1, 0);
            }
            used[d][w] |= 1u64 << bit;
        }
        if colours.len() <= c {
            colours.resize(c + 1, Vec::new());
        }
        colours[c].push(b);
    }
    colours
}

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
    gather: Vec<usize>,
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
        let mut col_ptr = Vec::with_capacity(nf + 1);
        let mut row_idx = Vec::new();
        let mut gather = Vec::new();
        col_ptr.push(0);
        for &c in &free {
            for k in full.col_ptr[c]..full.col_ptr[c + 1] {
                let r = map[full.row_idx[k]];
                if r != usize::MAX {
                    row_idx.push(r);
                    gather.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let val = vec![0.0; row_idx.len()];
        Ok(Self {
            map,
            free,
            reduced: CscMatrix {
                nrows: nf,
                ncols: nf,
                col_ptr,
                row_idx,
                val,
            },
            gather,
        })
    }

    /// K_ff values from the full matrix (same pattern as at construction).
    pub fn reduce(&self, full: &CscMatrix) -> CscMatrix {
        let mut r = self.reduced.clone();
        r.val = self.gather.iter().map(|&k| full.val[k]).collect();
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assembly_matches_serial_sum() {
        // 1D chain of 2-dof blocks
        let n = 50;
        let blocks: Vec<Vec<usize>> = (0..n - 1).map(|i| vec![i, i + 1]).collect();
        let p = Pattern::symmetric(n, &blocks).unwrap();
        assert!(p.colours.len() == 2);
        let a = p.assemble(&blocks, &blocks, |b, out| {
            let k = 1.0 + b as f64;
            out.extend_from_slice(&[k, -k, -k, k]);
        });
        for i in 1..n - 1 {
            assert_eq!(a.get(i, i), i as f64 + (i + 1) as f64);
            assert_eq!(a.get(i, i + 1), -((i + 1) as f64));
        }
        assert_eq!(a.asymmetry(), 0.0);
    }

    #[test]
    fn triplets_sum_duplicates() {
        let a = CscMatrix::from_triplets(2, 2, &[(0, 0, 1.0), (1, 0, 2.0), (0, 0, 3.0)]).unwrap();
        assert_eq!(a.get(0, 0), 4.0);
        assert_eq!(a.get(1, 0), 2.0);
        assert_eq!(a.nnz(), 2);
        assert!(CscMatrix::from_triplets(2, 2, &[(2, 0, 1.0)]).is_err());
    }
}
