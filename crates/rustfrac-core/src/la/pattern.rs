//! The sparsity pattern built once from element (or bond) dof blocks, and race-free parallel value
//! assembly on it.
//!
//! Assembly colours the blocks so that two blocks of one colour share no dof; the blocks of a colour
//! are then scattered in parallel (rayon) without locks or atomics, and the result is deterministic
//! (each entry receives its contributions in the same order at every run).

use super::csc::{column_pointers, for_column_chunks, CscMatrix};
use crate::error::{Error, Result};
use rayon::prelude::*;

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
    /// `colours[c]` = blocks of colour c; two blocks of one colour write no common row.
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
        // each column: union of the block rows, sorted unique; built in two parallel passes
        // (lengths, then rows written in place) with a marker array per task for the duplicates
        let rows_of_col = |c: usize, mark: &mut Vec<usize>, out: &mut dyn FnMut(usize)| {
            mark[c] = c;
            out(c);
            for &b in &blocks_of_col[cnt[c]..cnt[c + 1]] {
                for &r in &rows_of[b] {
                    if mark[r] != c {
                        mark[r] = c;
                        out(r);
                    }
                }
            }
        };
        let marker = || vec![usize::MAX; n];
        let col_ptr = column_pointers(n, marker, |mark, cols| {
            cols.map(|c| {
                let mut len = 0;
                rows_of_col(c, mark, &mut |_| len += 1);
                len
            })
            .collect()
        });
        let mut row_idx = vec![0usize; col_ptr[n]];
        for_column_chunks(&col_ptr, &mut row_idx, marker, |mark, cols, seg| {
            let mut k = 0;
            for c in cols {
                let start = k;
                rows_of_col(c, mark, &mut |r| {
                    seg[k] = r;
                    k += 1;
                });
                seg[start..k].sort_unstable();
            }
        });
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
    /// `block(b, out)` writes the dense block of `b` into `out` (row-major, `rows_of[b].len()`
    /// x `cols_of[b].len()`). Blocks of one colour share no row, so the parallel scatter is
    /// race-free.
    pub fn assemble<F>(&self, rows_of: &[Vec<usize>], cols_of: &[Vec<usize>], block: F) -> CscMatrix
    where
        F: Fn(usize, &mut Vec<f64>) + Sync,
    {
        CscMatrix {
            nrows: self.n,
            ncols: self.n,
            col_ptr: self.col_ptr.clone(),
            row_idx: self.row_idx.clone(),
            val: self.values(rows_of, cols_of, block),
        }
    }

    /// As [`Pattern::assemble`] for a pattern used once: the matrix takes over its structure.
    pub fn into_matrix<F>(
        self,
        rows_of: &[Vec<usize>],
        cols_of: &[Vec<usize>],
        block: F,
    ) -> CscMatrix
    where
        F: Fn(usize, &mut Vec<f64>) + Sync,
    {
        let val = self.values(rows_of, cols_of, block);
        CscMatrix {
            nrows: self.n,
            ncols: self.n,
            col_ptr: self.col_ptr,
            row_idx: self.row_idx,
            val,
        }
    }

    /// The assembled values, in the order of `row_idx`.
    fn values<F>(&self, rows_of: &[Vec<usize>], cols_of: &[Vec<usize>], block: F) -> Vec<f64>
    where
        F: Fn(usize, &mut Vec<f64>) + Sync,
    {
        let mut val = vec![0.0; self.row_idx.len()];
        let ptr = SyncPtr(val.as_mut_ptr());
        let col_ptr = &self.col_ptr;
        let row_idx = &self.row_idx;
        for colour in &self.colours {
            colour
                .par_iter()
                .for_each_init(Scratch::default, |Scratch { buf, order, pos }, &b| {
                    buf.clear();
                    block(b, buf);
                    let (rows, cols) = (&rows_of[b], &cols_of[b]);
                    debug_assert_eq!(buf.len(), rows.len() * cols.len());
                    // the block's rows in increasing order, so that each column's positions are
                    // found by one merge along the (sorted) column instead of a search per entry
                    order.clear();
                    order.extend(0..rows.len());
                    order.sort_unstable_by_key(|&i| rows[i]);
                    pos.resize(rows.len(), 0);
                    for (j, &c) in cols.iter().enumerate() {
                        let (c0, c1) = (col_ptr[c], col_ptr[c + 1]);
                        let mut k = c0;
                        for &i in order.iter() {
                            while row_idx[k] < rows[i] {
                                k += 1;
                                assert!(k < c1, "entry in pattern");
                            }
                            assert!(row_idx[k] == rows[i], "entry in pattern");
                            pos[i] = k;
                        }
                        for (i, &k) in pos.iter().enumerate() {
                            let v = buf[i * cols.len() + j];
                            if v == 0.0 {
                                continue;
                            }
                            // SAFETY: blocks of one colour write disjoint rows, so no two
                            // threads touch the same entry `k`; `k` < nnz (checked above).
                            unsafe { *ptr.get().add(k) += v };
                        }
                    }
                });
        }
        val
    }
}

/// Per-thread buffers of [`Pattern::assemble`]: the block values, its rows in increasing order and
/// their positions in the current column.
#[derive(Default)]
struct Scratch {
    buf: Vec<f64>,
    order: Vec<usize>,
    pos: Vec<usize>,
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
    // per dof: bitset of the colours of the blocks writing it; word 0 flat (the common case),
    // further words only when a dof meets more than 64 colours
    let mut first = vec![0u64; n];
    let mut more: Vec<Vec<u64>> = vec![Vec::new(); n];
    let mut colours: Vec<Vec<usize>> = Vec::new();
    for (b, rows) in rows_of.iter().enumerate() {
        let m0 = rows.iter().fold(0u64, |m, &d| m | first[d]);
        let c = if m0 != u64::MAX {
            (!m0).trailing_zeros() as usize
        } else {
            let mut w = 1usize;
            loop {
                let m = rows
                    .iter()
                    .fold(0u64, |m, &d| m | more[d].get(w - 1).copied().unwrap_or(0));
                if m != u64::MAX {
                    break 64 * w + (!m).trailing_zeros() as usize;
                }
                w += 1;
            }
        };
        let (w, bit) = (c / 64, c % 64);
        for &d in rows {
            if w == 0 {
                first[d] |= 1u64 << bit;
            } else {
                if more[d].len() < w {
                    more[d].resize(w, 0);
                }
                more[d][w - 1] |= 1u64 << bit;
            }
        }
        if colours.len() <= c {
            colours.resize(c + 1, Vec::new());
        }
        colours[c].push(b);
    }
    colours
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
        // a star: 100 blocks sharing dof 0 need 100 colours (beyond one 64-bit word)
        let star: Vec<Vec<usize>> = (1..=100).map(|i| vec![0, i]).collect();
        let ps = Pattern::symmetric(101, &star).unwrap();
        assert_eq!(ps.colours.len(), 100);
        let a = ps.assemble(&star, &star, |_, out| {
            out.extend_from_slice(&[1.0, -1.0, -1.0, 1.0])
        });
        assert_eq!(a.get(0, 0), 100.0);
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
}
