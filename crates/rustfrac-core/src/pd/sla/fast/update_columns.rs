//! The stored update columns W of the Sherman-Morrison-Woodbury solver (`smw.rs`): x = v + W y.

/// Columns of a panel of W.
pub(super) const PANEL: usize = 64;

/// The stored update columns W = S_0^{-1} A (n x k), in panels of [`PANEL`] columns, each
/// row-major, so that the value of x at one unknown, v_p + W_p y, reads k / 8 whole cache
/// lines (the step needs x only where a stretch can be critical, `screening.rs`); a new column
/// fills the last panel or starts one (no copy of the stored ones).
#[derive(Default)]
pub(super) struct UpdateColumns {
    n: usize,
    k: usize,
    /// panels, n x PANEL row-major each; kept across condensations for reuse
    panels: Vec<Vec<f64>>,
}

impl UpdateColumns {
    /// Number of stored columns.
    pub(super) fn len(&self) -> usize {
        self.k
    }
    /// Drops the columns (a new condensation); the panels are kept for the next ones.
    pub(super) fn clear(&mut self) {
        self.k = 0;
    }
    /// Appends the column `w`.
    pub(super) fn push(&mut self, w: &[f64]) {
        if w.len() != self.n {
            self.n = w.len();
            self.panels.clear();
            self.k = 0;
        }
        let (pi, j) = (self.k / PANEL, self.k % PANEL);
        if pi == self.panels.len() {
            self.panels.push(vec![0.0; self.n * PANEL]);
        }
        let panel = &mut self.panels[pi];
        for (r, &v) in w.iter().enumerate() {
            panel[r * PANEL + j] = v;
        }
        self.k += 1;
    }
    /// The stored panels with their column counts.
    pub(super) fn used(&self) -> impl Iterator<Item = (&[f64], usize)> {
        let k = self.k;
        self.panels
            .iter()
            .take(k.div_ceil(PANEL))
            .enumerate()
            .map(move |(i, p)| (&p[..], (k - i * PANEL).min(PANEL)))
    }
    /// W_p . y (row p of W against the k values of y).
    pub(super) fn row_dot(&self, p: usize, y: &[f64]) -> f64 {
        self.used()
            .zip(y.chunks(PANEL))
            .map(|((panel, c), yc)| dot4(&panel[p * PANEL..p * PANEL + c], yc))
            .sum()
    }
    /// out[j] -= alpha W[p][j] for the k stored columns.
    pub(super) fn row_sub(&self, p: usize, alpha: f64, out: &mut [f64]) {
        for ((panel, c), oc) in self.used().zip(out.chunks_mut(PANEL)) {
            for (o, &w) in oc.iter_mut().zip(&panel[p * PANEL..p * PANEL + c]) {
                *o -= alpha * w;
            }
        }
    }
}

/// a . b with four partial sums (a fixed order: the same bits on every call).
pub(super) fn dot4(a: &[f64], b: &[f64]) -> f64 {
    let (mut s0, mut s1, mut s2, mut s3) = (0.0, 0.0, 0.0, 0.0);
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        s0 += x[0] * y[0];
        s1 += x[1] * y[1];
        s2 += x[2] * y[2];
        s3 += x[3] * y[3];
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (s0 + s1) + (s2 + s3) + tail
}
