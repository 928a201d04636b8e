//! Compressed sparse column (CSC) matrices: the storage of every stiffness matrix, and the parallel
//! builders of CSC column structures (column pointers from lengths, columns filled in chunks)
//! that [`crate::la::Pattern`] and [`crate::la::Reduction`] use.

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
        // counting sort by column into one buffer (entries of a column in input order), then
        // each column sorted by row (stably: duplicates are summed in input order)
        let mut col_ptr = vec![0usize; ncols + 1];
        for &(r, c, _) in trip {
            if r >= nrows || c >= ncols {
                return Err(Error::invalid(
                    "triplet index",
                    &format!("row < {nrows} and col < {ncols}"),
                    format!("({r}, {c})"),
                ));
            }
            col_ptr[c + 1] += 1;
        }
        for c in 0..ncols {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut next = col_ptr.clone();
        let mut sorted = vec![(0usize, 0.0f64); trip.len()];
        for &(r, c, v) in trip {
            sorted[next[c]] = (r, v);
            next[c] += 1;
        }
        let mut row_idx = Vec::with_capacity(trip.len());
        let mut val = Vec::with_capacity(trip.len());
        let mut out_ptr = Vec::with_capacity(ncols + 1);
        out_ptr.push(0);
        for c in 0..ncols {
            let col = &mut sorted[col_ptr[c]..col_ptr[c + 1]];
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
            out_ptr.push(row_idx.len());
        }
        Ok(Self {
            nrows,
            ncols,
            col_ptr: out_ptr,
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

    /// The pattern of A + A^T (values 0), for a symmetric analysis of a non-symmetric pattern:
    /// the transpose by counting, then each column's two sorted row lists merged (O(nnz), no
    /// sort). A rectangular A is taken as its square completion of order max(rows, columns).
    pub fn symmetrised_pattern(&self) -> Self {
        let n = self.ncols.max(self.nrows);
        let mut col_ptr_a = self.col_ptr.clone();
        col_ptr_a.resize(n + 1, *self.col_ptr.last().unwrap_or(&0));
        let a_ptr = &col_ptr_a;
        // A^T: column r of A^T holds the columns c of A with an entry in row r, ascending
        let mut t_ptr = vec![0usize; n + 1];
        for &r in &self.row_idx {
            t_ptr[r + 1] += 1;
        }
        for r in 0..n {
            t_ptr[r + 1] += t_ptr[r];
        }
        let mut next = t_ptr.clone();
        let mut t_idx = vec![0usize; self.row_idx.len()];
        for c in 0..n {
            for &r in &self.row_idx[a_ptr[c]..a_ptr[c + 1]] {
                t_idx[next[r]] = c;
                next[r] += 1;
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::with_capacity(2 * self.row_idx.len());
        for c in 0..n {
            let (a, b) = (
                &self.row_idx[a_ptr[c]..a_ptr[c + 1]],
                &t_idx[t_ptr[c]..t_ptr[c + 1]],
            );
            let (mut i, mut j) = (0, 0);
            while i < a.len() || j < b.len() {
                let r = match (a.get(i), b.get(j)) {
                    (Some(&x), Some(&y)) if x == y => {
                        i += 1;
                        j += 1;
                        x
                    }
                    (Some(&x), Some(&y)) if x < y => {
                        i += 1;
                        x
                    }
                    (Some(&x), None) => {
                        i += 1;
                        x
                    }
                    (_, Some(&y)) => {
                        j += 1;
                        y
                    }
                    (None, None) => unreachable!("the loop condition"),
                };
                row_idx.push(r);
            }
            col_ptr.push(row_idx.len());
        }
        let val = vec![0.0; row_idx.len()];
        Self {
            nrows: n,
            ncols: n,
            col_ptr,
            row_idx,
            val,
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

/// Columns per parallel task when building column structures.
const COLUMN_CHUNK: usize = 8192;

/// Column pointers of an n-column matrix from the column lengths, computed in parallel over
/// chunks of columns (`lengths(cols)` returns the lengths of the columns of one chunk).
/// `init` makes the per-task scratch state.
pub(crate) fn column_pointers<S, I, F>(n: usize, init: I, lengths: F) -> Vec<usize>
where
    I: Fn() -> S + Sync + Send,
    F: Fn(&mut S, std::ops::Range<usize>) -> Vec<usize> + Sync + Send,
{
    let lens: Vec<Vec<usize>> = (0..n.div_ceil(COLUMN_CHUNK))
        .into_par_iter()
        .map_init(init, |st, k| {
            lengths(st, k * COLUMN_CHUNK..((k + 1) * COLUMN_CHUNK).min(n))
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut total = 0;
    for l in lens.iter().flatten() {
        total += l;
        col_ptr.push(total);
    }
    col_ptr
}

/// Runs `fill(cols, seg)` in parallel for the chunks of columns of [`column_pointers`], `seg`
/// being the part of `data` (laid out by `col_ptr`) that holds those columns.
pub(crate) fn for_column_chunks<T, S, I, F>(col_ptr: &[usize], data: &mut [T], init: I, fill: F)
where
    T: Send,
    I: Fn() -> S + Sync + Send,
    F: Fn(&mut S, std::ops::Range<usize>, &mut [T]) + Sync + Send,
{
    let n = col_ptr.len() - 1;
    let mut segs = Vec::with_capacity(n.div_ceil(COLUMN_CHUNK));
    let mut rest = data;
    for k in 0..n.div_ceil(COLUMN_CHUNK) {
        let cols = k * COLUMN_CHUNK..((k + 1) * COLUMN_CHUNK).min(n);
        let (seg, tail) = rest.split_at_mut(col_ptr[cols.end] - col_ptr[cols.start]);
        segs.push((cols, seg));
        rest = tail;
    }
    segs.into_par_iter()
        .for_each_init(init, |st, (cols, seg)| fill(st, cols, seg));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The merged pattern of A + A^T equals the one built from both triplets of every entry
    /// (sorted, unique rows; empty columns kept; the diagonal once); a rectangular A gives its
    /// square completion's.
    #[test]
    fn symmetrised_pattern_is_a_plus_a_transpose() {
        let n = 23;
        let mut seed = 777u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize
        };
        let trip: Vec<(usize, usize, f64)> = (0..90)
            .map(|_| (next() % n, next() % (n - 3), 1.0))
            .chain([(4, 4, 1.0), (0, n - 1, 1.0)])
            .collect();
        let a = CscMatrix::from_triplets(n, n, &trip).unwrap();
        let both: Vec<(usize, usize, f64)> = trip
            .iter()
            .flat_map(|&(r, c, _)| [(r, c, 0.0), (c, r, 0.0)])
            .collect();
        let want = CscMatrix::from_triplets(n, n, &both).unwrap();
        let got = a.symmetrised_pattern();
        assert_eq!(got.col_ptr, want.col_ptr);
        assert_eq!(got.row_idx, want.row_idx);
        assert!(got.val.iter().all(|&v| v == 0.0));
        // rectangular (3 x 5, 5 x 3): the square completion, no panic
        let r35 = CscMatrix::from_triplets(3, 5, &[(0, 4, 1.0), (2, 1, 1.0)]).unwrap();
        let r53 = CscMatrix::from_triplets(5, 3, &[(4, 0, 1.0), (1, 2, 1.0)]).unwrap();
        let sq =
            CscMatrix::from_triplets(5, 5, &[(0, 4, 0.0), (4, 0, 0.0), (2, 1, 0.0), (1, 2, 0.0)])
                .unwrap();
        for r in [r35, r53] {
            let g = r.symmetrised_pattern();
            assert_eq!((g.nrows, g.ncols), (5, 5));
            assert_eq!((&g.col_ptr, &g.row_idx), (&sq.col_ptr, &sq.row_idx));
        }
    }

    #[test]
    fn triplets_sum_duplicates() {
        let a = CscMatrix::from_triplets(2, 2, &[(0, 0, 1.0), (1, 0, 2.0), (0, 0, 3.0)]).unwrap();
        assert_eq!(a.get(0, 0), 4.0);
        assert_eq!(a.get(1, 0), 2.0);
        assert_eq!(a.nnz(), 2);
        assert!(CscMatrix::from_triplets(2, 2, &[(2, 0, 1.0)]).is_err());
    }

    /// Many triplets with many duplicates in scrambled order: each entry is the sum of its
    /// duplicates in input order (bit for bit: the assembly's sums do not depend on how the
    /// triplets are bucketed), rows sorted, no explicit duplicates, empty columns kept.
    #[test]
    fn triplets_sum_duplicates_in_input_order() {
        let (nr, nc) = (7, 9);
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            seed >> 33
        };
        let trip: Vec<(usize, usize, f64)> = (0..500)
            .map(|_| {
                let (r, c) = ((next() % nr as u64) as usize, (next() % 8) as usize);
                (r, c, (next() % 1000) as f64 / 7.0 - 60.0)
            })
            .collect();
        let a = CscMatrix::from_triplets(nr, nc, &trip).unwrap();
        let mut dense = vec![vec![None::<f64>; nc]; nr];
        for &(r, c, v) in &trip {
            dense[r][c] = Some(dense[r][c].map_or(v, |s| s + v));
        }
        assert_eq!(a.col_ptr[8], a.col_ptr[9], "column 8 has no triplet");
        for c in 0..nc {
            let rows = &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]];
            assert!(rows.windows(2).all(|w| w[0] < w[1]));
            for (r, row) in dense.iter().enumerate() {
                match row[c] {
                    Some(v) => assert_eq!(a.get(r, c).to_bits(), v.to_bits(), "({r}, {c})"),
                    None => assert!(!rows.contains(&r)),
                }
            }
        }
    }
}
