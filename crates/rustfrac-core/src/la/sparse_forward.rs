//! Forward substitution with a sparse right-hand side: w = L^{-1} P S b for a factorised SPD
//! matrix A (S A S = P^T L L^T P, [`Cholesky`]) and a b with few nonzeros.
//!
//! The nonzeros of L^{-1} c are the ancestors, in the elimination tree, of the nonzeros of c
//! (Gilbert and Peierls 1988): here whole supernodes, so w is stored as the dense segments of the
//! supernodes on the union of the tree paths from c's rows to the root ([`SparseColumn`]). Only
//! those supernodes are touched, so the cost is that of the paths (a few separators of a nested
//! dissection), not of the factor. With w_i = L^{-1} P S b_i,
//! b_i^T A^{-1} b_j = w_i . w_j ([`SparseColumn::dot`]): the quantity of a Schur complement
//! K_ES K_SS^{-1} K_SE built column by column ([`crate::xfem`] growth).

use super::cholesky::Cholesky;
use crate::error::{Error, Result};
use faer::dyn_stack::MemStack;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Accum, Conj, Mat, MatMut, MatRef, Par};

/// L^{-1} P S b as dense runs of consecutive (permuted) columns: the supernodes on the tree paths,
/// merged where they are adjacent.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseColumn {
    /// (first column, end column, offset of the run in `values`), increasing
    runs: Vec<(u32, u32, u32)>,
    values: Vec<f64>,
}

impl SparseColumn {
    /// Number of stored values.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Number of runs of consecutive columns.
    pub fn n_runs(&self) -> usize {
        self.runs.len()
    }

    /// Whether nothing is stored (b = 0).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Appends the values of columns `begin..begin + v.len()` (after every stored column).
    fn push(&mut self, begin: usize, v: &[f64]) {
        let (b, e) = (begin as u32, (begin + v.len()) as u32);
        match self.runs.last_mut() {
            Some(last) if last.1 == b => last.1 = e,
            _ => self.runs.push((b, e, self.values.len() as u32)),
        }
        self.values.extend_from_slice(v);
    }

    /// z += alpha w (z dense, in the factor's column order).
    pub fn axpy_into(&self, alpha: f64, z: &mut [f64]) {
        for &(b, e, o) in &self.runs {
            let v = &self.values[o as usize..(o + e - b) as usize];
            for (zi, vi) in z[b as usize..e as usize].iter_mut().zip(v) {
                *zi += alpha * vi;
            }
        }
    }

    /// w_i . w_j over the columns both store (elsewhere one of them is zero).
    pub fn dot(&self, other: &SparseColumn) -> f64 {
        let (a, b) = (&self.runs, &other.runs);
        let (mut i, mut j, mut sum) = (0, 0, 0.0);
        while i < a.len() && j < b.len() {
            let (lo, hi) = (a[i].0.max(b[j].0), a[i].1.min(b[j].1));
            if lo < hi {
                let x =
                    &self.values[(a[i].2 + lo - a[i].0) as usize..(a[i].2 + hi - a[i].0) as usize];
                let y =
                    &other.values[(b[j].2 + lo - b[j].0) as usize..(b[j].2 + hi - b[j].0) as usize];
                sum += dot(x, y);
            }
            if a[i].1 <= b[j].1 {
                i += 1;
            } else {
                j += 1;
            }
        }
        sum
    }
}

/// x . y with four partial sums (vectorisable).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    let mut acc = [0.0f64; 4];
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// The scratch space of [`SparseForward::solve`]: a dense vector and the supernodes' marks, both
/// left clear by every solve.
pub struct ForwardWork {
    x: Vec<f64>,
    mark: Vec<bool>,
}

/// The elimination tree of a factor's supernodes (a simplicial factor: one column each), for
/// forward solves with sparse right-hand sides ([`SparseForward::solve`]); built for one
/// factorisation and valid with it only.
pub struct SparseForward {
    /// permuted column -> its supernode
    sn_of: Vec<u32>,
    /// parent supernode (u32::MAX at a root)
    parent: Vec<u32>,
    /// original unknown -> permuted column
    inv: Vec<usize>,
}

/// One supernode's columns, off-diagonal rows and values (column-major, leading dimension
/// `nrows`).
struct Node<'a> {
    begin: usize,
    ncols: usize,
    nrows: usize,
    rows: &'a [usize],
    vals: &'a [f64],
}

/// The forward elimination of one supernode's columns in x (x[begin..begin + ncols] become the
/// solution's entries; the rows below the supernode are updated): the kernel of every forward
/// solve here, dense or along the elimination-tree paths.
fn eliminate(nd: &Node<'_>, x: &mut [f64]) {
    let (b0, nc, nr) = (nd.begin, nd.ncols, nd.nrows);
    for j in 0..nc {
        let col = &nd.vals[j * nr..(j + 1) * nr];
        let xj = x[b0 + j] / col[j];
        x[b0 + j] = xj;
        if xj == 0.0 {
            continue;
        }
        for i in j + 1..nc {
            x[b0 + i] -= col[i] * xj;
        }
        for (p, &r) in nd.rows.iter().enumerate() {
            x[r] -= col[nc + p] * xj;
        }
    }
}

fn n_nodes(chol: &Cholesky) -> usize {
    match chol.symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => sn.n_supernodes(),
        SymbolicCholeskyRaw::Simplicial(_) => chol.n,
    }
}

/// Supernode `s` of the factor (simplicial: column s, whose stored rows start with the
/// diagonal, as faer's sparse triangular solves require).
fn node(chol: &Cholesky, s: usize) -> Node<'_> {
    match chol.symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => {
            let (b, e, cpv) = (
                sn.supernode_begin()[s],
                sn.supernode_end()[s],
                sn.col_ptr_for_val(),
            );
            let rows = sn.supernode(s).pattern();
            Node {
                begin: b,
                ncols: e - b,
                nrows: e - b + rows.len(),
                rows,
                vals: &chol.values[cpv[s]..cpv[s + 1]],
            }
        }
        SymbolicCholeskyRaw::Simplicial(sm) => {
            let (cp, ri) = (sm.col_ptr(), sm.row_idx());
            let (lo, hi) = (cp[s], cp[s + 1]);
            Node {
                begin: s,
                ncols: 1,
                nrows: hi - lo,
                rows: &ri[lo + 1..hi],
                vals: &chol.values[lo..hi],
            }
        }
    }
}

impl SparseForward {
    /// The tree of a factorised `chol`.
    pub fn new(chol: &Cholesky) -> Result<Self> {
        if !chol.factorised {
            return Err(Error::Internal {
                detail: "SparseForward needs a factorised matrix".into(),
            });
        }
        let n = chol.n;
        let inv = match chol.symbolic.perm() {
            Some(p) => p.arrays().1.to_vec(),
            None => (0..n).collect(),
        };
        let ns = n_nodes(chol);
        let mut sn_of = vec![0u32; n];
        let mut parent = vec![u32::MAX; ns];
        for s in 0..ns {
            let nd = node(chol, s);
            sn_of[nd.begin..nd.begin + nd.ncols].fill(s as u32);
        }
        for (s, p) in parent.iter_mut().enumerate() {
            if let Some(&r) = node(chol, s).rows.first() {
                *p = sn_of[r];
            }
        }
        Ok(Self { sn_of, parent, inv })
    }

    /// The scratch space of [`SparseForward::solve`].
    pub fn work(&self) -> ForwardWork {
        ForwardWork {
            x: vec![0.0; self.inv.len()],
            mark: vec![false; self.parent.len()],
        }
    }

    /// w = L^{-1} P S b with the factor `chol` this tree was built from, for b given as
    /// (unknown, value) pairs (repeated unknowns add up); `work` is a zero vector of
    /// [`SparseForward::work`], left zero.
    pub fn solve(
        &self,
        chol: &Cholesky,
        b: &[(usize, f64)],
        work: &mut ForwardWork,
    ) -> SparseColumn {
        let ForwardWork { x, mark } = work;
        let mut nodes: Vec<u32> = Vec::new();
        for &(i, v) in b {
            let k = self.inv[i];
            x[k] += v * chol.scale[i];
            let mut s = self.sn_of[k];
            while s != u32::MAX && !mark[s as usize] {
                mark[s as usize] = true;
                nodes.push(s);
                s = self.parent[s as usize];
            }
        }
        nodes.sort_unstable();
        let mut out = SparseColumn::default();
        for &s in &nodes {
            mark[s as usize] = false;
            let nd = node(chol, s as usize);
            eliminate(&nd, x);
            let (b0, nc) = (nd.begin, nd.ncols);
            out.push(b0, &x[b0..b0 + nc]);
            x[b0..b0 + nc].fill(0.0);
        }
        out
    }
}

impl SparseForward {
    /// The dense forward solve v = L^-1 P S b (b in the original unknowns; v in the factor's
    /// column order), e.g. to combine it with sparse columns before [`SparseForward::backward`].
    pub fn forward_dense(&self, chol: &Cholesky, b: &[f64]) -> Vec<f64> {
        let mut x = vec![0.0; b.len()];
        for (i, &v) in b.iter().enumerate() {
            x[self.inv[i]] = v * chol.scale[i];
        }
        for s in 0..self.parent.len() {
            eliminate(&node(chol, s), &mut x);
        }
        x
    }

    /// The backward half of a solve: x = S P^T L^-T v (v in the factor's column order, x in
    /// the original unknowns), so that A^-1 b = backward(forward(b)). A supernodal factor takes
    /// faer's L^T solve (its kernels dispatched to the machine's SIMD width at run time); a
    /// simplicial one the column-by-column sweep below.
    pub fn backward(&self, chol: &Cholesky, mut v: Vec<f64>) -> Result<Vec<f64>> {
        if let SymbolicCholeskyRaw::Supernodal(sn) = chol.symbolic.raw() {
            l_transpose_solve(sn, chol, &mut v, 1)?;
            return Ok(self
                .inv
                .iter()
                .zip(&chol.scale)
                .map(|(&k, s)| v[k] * s)
                .collect());
        }
        let mut below: Vec<f64> = Vec::new();
        for s in (0..self.parent.len()).rev() {
            let nd = node(chol, s);
            let (b0, nc, nr) = (nd.begin, nd.ncols, nd.nrows);
            // the ancestors' values this supernode reads, gathered once
            below.clear();
            below.extend(nd.rows.iter().map(|&r| v[r]));
            for j in (0..nc).rev() {
                let col = &nd.vals[j * nr..(j + 1) * nr];
                let acc = v[b0 + j] - dot(&col[j + 1..nc], &v[b0 + j + 1..b0 + nc]);
                v[b0 + j] = (acc - dot(&col[nc..], &below)) / col[j];
            }
        }
        Ok(self
            .inv
            .iter()
            .zip(&chol.scale)
            .map(|(&k, s)| v[k] * s)
            .collect())
    }

    /// [`SparseForward::solve`] for several right-hand sides at once, blocked: the union of
    /// their tree paths is solved as one dense block per supernode (a triangular solve and a
    /// product, BLAS-3), and every w stores that union (zeros where its own path does not
    /// reach). A simplicial factor solves them one by one.
    pub fn solve_many(
        &self,
        chol: &Cholesky,
        bs: &[Vec<(usize, f64)>],
        work: &mut ForwardWork,
    ) -> Vec<SparseColumn> {
        if matches!(chol.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)) || bs.len() < 2 {
            return bs.iter().map(|b| self.solve(chol, b, work)).collect();
        }
        let ForwardWork { x: loc, mark } = work;
        let mut nodes: Vec<u32> = Vec::new();
        for b in bs {
            for &(i, _) in b {
                let mut s = self.sn_of[self.inv[i]];
                while s != u32::MAX && !mark[s as usize] {
                    mark[s as usize] = true;
                    nodes.push(s);
                    s = self.parent[s as usize];
                }
            }
        }
        nodes.sort_unstable();
        // local row of every column of the union (kept in `loc` as f64, cleared at the end)
        let mut m = 0usize;
        for &s in &nodes {
            let nd = node(chol, s as usize);
            for c in 0..nd.ncols {
                loc[nd.begin + c] = (m + c) as f64;
            }
            m += nd.ncols;
        }
        let k = bs.len();
        let mut xm = Mat::<f64>::zeros(m, k);
        for (j, b) in bs.iter().enumerate() {
            for &(i, v) in b {
                xm[(loc[self.inv[i]] as usize, j)] += v * chol.scale[i];
            }
        }
        let mut tmp = Mat::<f64>::zeros(0, 0);
        for &s in &nodes {
            mark[s as usize] = false;
            let nd = node(chol, s as usize);
            let (nc, nr) = (nd.ncols, nd.nrows);
            let r0 = loc[nd.begin] as usize;
            let lss = MatRef::from_column_major_slice_with_stride(nd.vals, nc, nc, nr);
            solve_lower_triangular_in_place(lss, xm.as_mut().subrows_mut(r0, nc), Par::Seq);
            let np = nd.rows.len();
            if np == 0 {
                continue;
            }
            let lps = MatRef::from_column_major_slice_with_stride(&nd.vals[nc..], np, nc, nr);
            tmp.resize_with(np, k, |_, _| 0.0);
            matmul(
                tmp.as_mut(),
                Accum::Replace,
                lps,
                xm.as_ref().subrows(r0, nc),
                1.0,
                Par::Seq,
            );
            for (p, &r) in nd.rows.iter().enumerate() {
                let lr = loc[r] as usize;
                for j in 0..k {
                    xm[(lr, j)] -= tmp[(p, j)];
                }
            }
        }
        let out = (0..k)
            .map(|j| {
                let mut w = SparseColumn::default();
                let col = xm.col(j);
                for &s in &nodes {
                    let nd = node(chol, s as usize);
                    let r0 = loc[nd.begin] as usize;
                    let v: Vec<f64> = (0..nd.ncols).map(|c| col[r0 + c]).collect();
                    w.push(nd.begin, &v);
                }
                w
            })
            .collect();
        for &s in &nodes {
            let nd = node(chol, s as usize);
            loc[nd.begin..nd.begin + nd.ncols].fill(0.0);
        }
        out
    }
}

/// The unit vectors e_c of R^n for c in `cols`, column-major (n x k): the right-hand sides of
/// columns of an inverse.
pub fn unit_vectors(n: usize, cols: &[usize]) -> Vec<f64> {
    let mut x = written_zeros(n * cols.len());
    for (j, &c) in cols.iter().enumerate() {
        x[j * n + c] = 1.0;
    }
    x
}

impl SparseForward {
    /// Columns `cols` of A^-1 (column-major, n x k): the forward halves along the tree paths of
    /// the unit right-hand sides ([`SparseForward::solve_many`]: only the supernodes on the union
    /// of their paths), the backward halves blocked over the whole factor (faer's supernodal
    /// L^T solve). A simplicial factor takes the whole solve. The pure PD SLA's batches of
    /// columns of S_0^-1 (`pd/sla/fast/columns.rs`): their unit vectors lie near the crack tip, so
    /// the paths are a few separators and the forward half costs little beside the backward.
    pub fn solve_unit_columns(
        &self,
        chol: &Cholesky,
        cols: &[usize],
        work: &mut ForwardWork,
    ) -> Result<Vec<f64>> {
        let n = chol.n;
        let k = cols.len();
        if cols.iter().any(|&c| c >= n) {
            return Err(Error::Internal {
                detail: format!("a column of A^-1 beyond its {n} unknowns"),
            });
        }
        let SymbolicCholeskyRaw::Supernodal(sn) = chol.symbolic.raw() else {
            let mut x = unit_vectors(n, cols);
            chol.solve_in_place(&mut x)?;
            return Ok(x);
        };
        let bs: Vec<Vec<(usize, f64)>> = cols.iter().map(|&c| vec![(c, 1.0)]).collect();
        let fw = self.solve_many(chol, &bs, work);
        // the backward solve's kernels read, then write every entry
        let mut v = written_zeros(n * k);
        for (w, vj) in fw.iter().zip(v.chunks_mut(n.max(1))) {
            w.axpy_into(1.0, vj);
        }
        l_transpose_solve(sn, chol, &mut v, k)?;
        // x = P^T D v column by column in place, through one column of scratch
        let mut xj = vec![0.0; n];
        for vj in v.chunks_mut(n.max(1)) {
            for ((xi, &kk), s) in xj.iter_mut().zip(&self.inv).zip(&chol.scale) {
                *xi = vj[kk] * s;
            }
            vj.copy_from_slice(&xj);
        }
        super::checks::check_solution(&v)?;
        Ok(v)
    }
}

/// v <- L^-T v for the `k` columns of v (n x k, column-major, in the factor's column order):
/// faer's supernodal solve, blocked over the whole factor.
fn l_transpose_solve(
    sn: &SymbolicSupernodalCholesky<usize>,
    chol: &Cholesky,
    v: &mut [f64],
    k: usize,
) -> Result<()> {
    crate::error::catch_panic("faer supernodal backward solve", || {
        let par = faer::get_global_parallelism();
        let req = sn.solve_in_place_scratch::<f64>(k, par);
        let mut mem = super::checks::workspace(req, "the backward solve's workspace")?;
        let llt = SupernodalLltRef::<usize, f64>::new(sn, &chol.values);
        llt.l_transpose_solve_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(v, chol.n, k),
            par,
            MemStack::new(&mut mem),
        );
        Ok(())
    })
}

/// `len` zeros, each page written once, for a vector that is read before it is written (solved
/// in place, accumulated into): a calloc'ed block's pages are mapped on first access, to the
/// shared zero page when that access is a read, and the first write then faults again and
/// flushes the other cores' TLBs.
pub fn written_zeros(len: usize) -> Vec<f64> {
    let mut v = vec![0.0; len];
    for i in (0..len).step_by(PAGE_F64) {
        v[i] = std::hint::black_box(0.0); // opaque: the store stays
    }
    if let Some(last) = v.last_mut() {
        *last = std::hint::black_box(0.0); // the last page, if the stride stepped over it
    }
    v
}

/// f64 values in a 4 kB page.
const PAGE_F64: usize = 512;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::la::CscMatrix;

    /// A 2D grid Laplacian plus a diagonal shift, n = nx * ny (full symmetric storage).
    fn grid(nx: usize, ny: usize) -> (CscMatrix, Vec<[f64; 2]>) {
        let n = nx * ny;
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for j in 0..ny {
            for i in 0..nx {
                let c = j * nx + i;
                cols[c].push((c, 4.1 + 0.01 * (c % 7) as f64));
                for (di, dj) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                    let (a, b) = (i as i64 + di, j as i64 + dj);
                    if a >= 0 && b >= 0 && (a as usize) < nx && (b as usize) < ny {
                        cols[c].push((b as usize * nx + a as usize, -1.0));
                    }
                }
                cols[c].sort_by_key(|x| x.0);
            }
        }
        let mut col_ptr = vec![0];
        let (mut row_idx, mut val) = (Vec::new(), Vec::new());
        for col in &cols {
            for &(r, v) in col {
                row_idx.push(r);
                val.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        let xy = (0..n).map(|c| [(c % nx) as f64, (c / nx) as f64]).collect();
        (
            CscMatrix {
                nrows: n,
                ncols: n,
                col_ptr,
                row_idx,
                val,
            },
            xy,
        )
    }

    /// b_i^T A^-1 b_j from sparse forward solves equals the dense solve's value, on a
    /// supernodal (nested dissection, 60 x 50) and a small (AMD) factor.
    #[test]
    fn dots_match_full_solves() {
        for (nx, ny, nd) in [(60, 50, true), (5, 4, false)] {
            let (a, xy) = grid(nx, ny);
            let chol = Cholesky::new_with(&a, nd.then_some(&xy[..])).unwrap();
            let tree = SparseForward::new(&chol).unwrap();
            let n = nx * ny;
            let bs: Vec<Vec<(usize, f64)>> = vec![
                vec![(0, 1.0), (1, -0.5)],
                vec![(n / 2, 2.0), (n / 2 + nx, 1.0), (n / 2, 0.25)],
                vec![(n - 1, 3.0)],
            ];
            let mut work = tree.work();
            let ws: Vec<SparseColumn> =
                bs.iter().map(|b| tree.solve(&chol, b, &mut work)).collect();
            let many = tree.solve_many(&chol, &bs, &mut work);
            // backward(forward(b) - w_0) = A^-1 (b - b_0)
            let b: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 - 5.0).collect();
            let mut v = tree.forward_dense(&chol, &b);
            ws[0].axpy_into(-1.0, &mut v);
            let x = tree.backward(&chol, v).unwrap();
            let mut b0 = b.clone();
            for &(k, val) in &bs[0] {
                b0[k] -= val;
            }
            let xr = chol.solve(&b0).unwrap();
            let xn = xr.iter().map(|v| v.abs()).fold(0.0, f64::max);
            for (p, q) in x.iter().zip(&xr) {
                assert!((p - q).abs() <= 1e-12 * xn, "backward: {p} vs {q}");
            }
            for (i, wi) in many.iter().enumerate() {
                for (j, wj) in ws.iter().enumerate() {
                    let (a, b) = (wi.dot(wj), ws[i].dot(wj));
                    assert!((a - b).abs() <= 1e-13 * b.abs().max(1e-3), "many ({i},{j})");
                }
            }
            assert!(work.x.iter().all(|&v| v == 0.0) && work.mark.iter().all(|&m| !m));
            for (i, bi) in bs.iter().enumerate() {
                let mut dense = vec![0.0; n];
                for &(k, v) in bi {
                    dense[k] += v;
                }
                let x = chol.solve(&dense).unwrap();
                for (j, bj) in bs.iter().enumerate() {
                    let exact: f64 = bj.iter().map(|&(k, v)| v * x[k]).sum();
                    let got = ws[i].dot(&ws[j]);
                    assert!(
                        (got - exact).abs() <= 1e-13 * exact.abs().max(1e-3),
                        "{nx}x{ny} ({i},{j}): {got} vs {exact}"
                    );
                }
            }
        }
    }

    /// `written_zeros` gives `len` zeros, whatever `len` is against the page's values.
    #[test]
    fn written_zeros_are_zeros_of_any_length() {
        for len in [0, 1, PAGE_F64 - 1, PAGE_F64, PAGE_F64 + 1, 3 * PAGE_F64 + 7] {
            let v = written_zeros(len);
            assert_eq!(v.len(), len);
            assert!(v.iter().all(|&x| x == 0.0));
        }
    }

    /// Columns of A^-1 by sparse forward + blocked backward equal the whole solves of unit
    /// vectors, on a supernodal factor (a PD-like family of radius 3 on 60 x 50, nested
    /// dissection) and a simplicial one; a column beyond the unknowns is refused.
    #[test]
    fn unit_columns_match_full_solves() {
        // every node coupled to its neighbours within distance 3, diagonally dominant
        let family_grid = |nx: usize, ny: usize| {
            let mut trip = Vec::new();
            for c in 0..nx * ny {
                let (i, j) = ((c % nx) as i64, (c / nx) as i64);
                trip.push((c, c, 30.0 + 0.01 * (c % 7) as f64));
                for di in -3i64..=3 {
                    for dj in -3i64..=3 {
                        let (a, b) = (i + di, j + dj);
                        let inside = a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64;
                        if (di, dj) != (0, 0) && di * di + dj * dj <= 9 && inside {
                            trip.push((
                                c,
                                b as usize * nx + a as usize,
                                -1.0 / (di * di + dj * dj) as f64,
                            ));
                        }
                    }
                }
            }
            let xy = (0..nx * ny)
                .map(|c| [(c % nx) as f64, (c / nx) as f64])
                .collect::<Vec<_>>();
            (
                CscMatrix::from_triplets(nx * ny, nx * ny, &trip).unwrap(),
                xy,
            )
        };
        for (nx, ny, nd) in [(60, 50, true), (5, 4, false)] {
            let (a, xy) = if nd {
                family_grid(nx, ny)
            } else {
                grid(nx, ny)
            };
            let chol = Cholesky::new_with(&a, nd.then_some(&xy[..])).unwrap();
            assert_eq!(chol.is_supernodal(), nd);
            let tree = SparseForward::new(&chol).unwrap();
            let n = nx * ny;
            let cols = [n / 2, 0, n / 2 + 1, n - 1, n / 2 + nx];
            let mut work = tree.work();
            let x = tree.solve_unit_columns(&chol, &cols, &mut work).unwrap();
            assert!(work.x.iter().all(|&v| v == 0.0) && work.mark.iter().all(|&m| !m));
            for (j, &c) in cols.iter().enumerate() {
                let mut e = vec![0.0; n];
                e[c] = 1.0;
                let xr = chol.solve(&e).unwrap();
                let xn = xr.iter().map(|v| v.abs()).fold(0.0, f64::max);
                for (p, q) in x[j * n..(j + 1) * n].iter().zip(&xr) {
                    assert!(
                        (p - q).abs() <= 1e-13 * xn,
                        "{nx}x{ny} column {c}: {p} vs {q}"
                    );
                }
            }
            assert!(tree.solve_unit_columns(&chol, &[n], &mut work).is_err());
        }
    }
}
