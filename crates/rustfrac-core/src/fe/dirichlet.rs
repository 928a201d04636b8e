//! Dirichlet conditions (prescribed dof values, eliminated with their values in
//! [`crate::fe::LinearSystem`]) and the check, before any factorisation, that they remove the
//! three rigid-body modes of a plane body.

use crate::error::{Error, Result};

/// Prescribed dof values (Dirichlet conditions): (dof, value) pairs; a dof listed twice must
/// carry the same value.
#[derive(Debug, Clone, Default)]
pub struct Dirichlet {
    pub dofs: Vec<(usize, f64)>,
}

impl Dirichlet {
    /// Prescribes component `comp` (0: u1, 1: u2) of `nodes` to `value` (dof = 2 n + comp).
    pub fn fix(&mut self, nodes: &[usize], comp: usize, value: f64) {
        for &n in nodes {
            self.dofs.push((2 * n + comp, value));
        }
    }

    /// (mask, values) over `n` dofs; refuses conflicting or out-of-range entries.
    pub fn to_mask(&self, n: usize) -> Result<(Vec<bool>, Vec<f64>)> {
        let mut mask = vec![false; n];
        let mut vals = vec![0.0; n];
        for &(d, v) in &self.dofs {
            if d >= n {
                return Err(Error::invalid("Dirichlet dof", &format!("< {n}"), d));
            }
            if !v.is_finite() {
                return Err(Error::invalid(
                    "prescribed displacement",
                    "a finite number",
                    v,
                ));
            }
            if mask[d] && vals[d] != v {
                return Err(Error::invalid(
                    "Dirichlet conditions",
                    "one value per dof",
                    format!("dof {d} prescribed to {} and {v}", vals[d]),
                ));
            }
            mask[d] = true;
            vals[d] = v;
        }
        Ok((mask, vals))
    }

    /// Checks that the prescribed dofs remove the three rigid-body modes of the plane body whose
    /// nodes are `node_xy` (dofs 2 n + comp; dofs beyond 2 node_xy.len(), e.g. XFEM enrichment,
    /// have no rigid modes of their own and are ignored), before any factorisation; a free mode
    /// is [`Error::Singular`] naming it.
    ///
    /// A prescribed u1 at (x, y) removes the combinations of the modes (x1 translation, x2
    /// translation, rotation about the centre) with r^T c = 0, r = [1, 0, -y'], a prescribed u2
    /// r = [0, 1, x'], with (x', y') the position relative to the centre of the nodes' bounding box
    /// divided by its half diagonal (scale and translation invariant). The modes are all removed
    /// iff N = sum r r^T has rank 3: every eigenvalue above 1e-10 x the largest (a geometrically
    /// degenerate set, e.g. two u1 conditions 1e-5 of the plate size apart as the only rotation
    /// restraint, counts as free).
    pub fn check_rigid_modes(&self, node_xy: &[[f64; 2]]) -> Result<()> {
        let (centre, half) = normalising_frame(node_xy);
        let n = self.rigid_mode_normal_matrix(node_xy, centre, half);
        let (lam, vecs) = sym3_eigen(n);
        let lmax = lam.iter().fold(0.0f64, |a, &l| a.max(l));
        let null: Vec<[f64; 3]> = (0..3)
            .filter(|&k| lam[k].is_nan() || lam[k] <= 1e-10 * lmax)
            .map(|k| vecs[k])
            .collect();
        if null.is_empty() {
            return Ok(());
        }
        let modes = name_free_modes(&null, centre, half).join(", ");
        Err(Error::Singular {
            detail: format!(
                "the Dirichlet conditions leave {} rigid-body mode(s) free: {modes} (prescribe \
                 displacements that remove the x1 and x2 translations and the rotation)",
                null.len()
            ),
        })
    }

    /// [`Dirichlet::check_rigid_modes`] on every connected part of a body whose stiffness links
    /// the nodes pairwise by `links` (PD bonds, FEM element edges): the largest part and each
    /// of more than `small` nodes must be held against its own three rigid-body modes by the conditions on its
    /// own nodes (a body cut in two by a hole is two parts; smaller fragments are left to the
    /// caller, e.g. PD's debris grounding). Nodes in no link carry no stiffness and are skipped.
    /// The error names the free mode(s), the part's node count and its bounding box.
    pub fn check_rigid_modes_by_part(
        &self,
        node_xy: &[[f64; 2]],
        links: impl IntoIterator<Item = [usize; 2]>,
        small: usize,
    ) -> Result<()> {
        let n = node_xy.len();
        let mut parent: Vec<usize> = (0..n).collect();
        let mut linked = vec![false; n];
        fn root(p: &mut [usize], mut a: usize) -> usize {
            while p[a] != a {
                p[a] = p[p[a]];
                a = p[a];
            }
            a
        }
        for [a, b] in links {
            if a >= n || b >= n {
                continue;
            }
            linked[a] = true;
            linked[b] = true;
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
        let mut parts: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for k in (0..n).filter(|&k| linked[k]) {
            parts.entry(root(&mut parent, k)).or_default().push(k);
        }
        let mut bc_of: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for &(d, v) in &self.dofs {
            if d / 2 < n {
                bc_of[d / 2].push((d, v));
            }
        }
        let largest = parts.values().map(Vec::len).max().unwrap_or(0);
        let checked = |p: &&Vec<usize>| p.len() > small || p.len() == largest;
        let several = parts.len() > 1;
        for nodes in parts.values().filter(checked) {
            let part = Dirichlet {
                dofs: nodes
                    .iter()
                    .flat_map(|&k| bc_of[k].iter().copied())
                    .collect(),
            };
            if let Err(Error::Singular { detail }) = part.check_rigid_modes(node_xy) {
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for &k in nodes {
                    for c in 0..2 {
                        lo[c] = lo[c].min(node_xy[k][c]);
                        hi[c] = hi[c].max(node_xy[k][c]);
                    }
                }
                let what = if several {
                    "a part of the body (the holes or cracks cut it off)"
                } else {
                    "the body"
                };
                return Err(Error::Singular {
                    detail: format!(
                        "{what} of {} nodes in [{:.4}, {:.4}] x [{:.4}, {:.4}]: {detail}",
                        nodes.len(),
                        lo[0],
                        hi[0],
                        lo[1],
                        hi[1]
                    ),
                });
            }
        }
        Ok(())
    }

    /// N = sum r r^T over the prescribed dofs of the nodes (see
    /// [`Dirichlet::check_rigid_modes`]), positions relative to `centre` divided by `half`.
    fn rigid_mode_normal_matrix(
        &self,
        node_xy: &[[f64; 2]],
        centre: [f64; 2],
        half: f64,
    ) -> [[f64; 3]; 3] {
        let mut n = [[0.0f64; 3]; 3];
        for &(d, _) in &self.dofs {
            let node = d / 2;
            if node >= node_xy.len() {
                continue;
            }
            let x = (node_xy[node][0] - centre[0]) / half;
            let y = (node_xy[node][1] - centre[1]) / half;
            let r = if d % 2 == 0 {
                [1.0, 0.0, -y]
            } else {
                [0.0, 1.0, x]
            };
            for i in 0..3 {
                for j in 0..3 {
                    n[i][j] += r[i] * r[j];
                }
            }
        }
        n
    }
}

/// The centre of the bounding box of the nodes and its half diagonal (1 for a degenerate box):
/// the frame in which [`Dirichlet::check_rigid_modes`] measures positions (scale and translation
/// invariant).
fn normalising_frame(node_xy: &[[f64; 2]]) -> ([f64; 2], f64) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in node_xy {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let half = 0.5 * ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
    let half = if half.is_finite() && half > 0.0 {
        half
    } else {
        1.0
    };
    (centre, half)
}

/// Names of the free rigid-body modes spanning `null` (unit vectors in the (x1 translation, x2
/// translation, rotation) basis of [`Dirichlet::check_rigid_modes`]).
fn name_free_modes(null: &[[f64; 3]], centre: [f64; 2], half: f64) -> Vec<String> {
    // canonical modes lying in the null space by name, then the rest of the null space
    // (orthogonal to them) described as a translation direction or a rotation centre
    const NAMES: [&str; 3] = ["x1 translation", "x2 translation", "rotation"];
    let mut basis: Vec<[f64; 3]> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for m in 0..3 {
        if null.iter().map(|v| v[m] * v[m]).sum::<f64>() > 1.0 - 1e-6 {
            let mut e = [0.0; 3];
            e[m] = 1.0;
            basis.push(e);
            names.push(NAMES[m].to_string());
        }
    }
    for v in null {
        let mut w = *v;
        for b in &basis {
            let d: f64 = (0..3).map(|i| w[i] * b[i]).sum();
            for i in 0..3 {
                w[i] -= d * b[i];
            }
        }
        let nw = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        if basis.len() == null.len() || nw < 0.5 {
            continue;
        }
        let w = [w[0] / nw, w[1] / nw, w[2] / nw];
        basis.push(w);
        names.push(if w[2].abs() < 1e-6 {
            format!("translation along ({:.3}, {:.3})", w[0], w[1])
        } else {
            // u = (w0 - w2 y', w1 + w2 x') vanishes at x' = -w1 / w2, y' = w0 / w2
            format!(
                "rotation about ({:.6e}, {:.6e})",
                centre[0] - half * w[1] / w[2],
                centre[1] + half * w[0] / w[2]
            )
        });
    }
    names
}

/// Eigenvalues and unit eigenvectors (`vecs[k]` belongs to `lam[k]`) of a symmetric 3 x 3 matrix
/// by cyclic Jacobi rotations (converges quadratically; 50 sweeps is far beyond need).
fn sym3_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-36 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = 0.5 * (a[q][q] - a[p][p]) / a[p][q];
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A <- J^T A J with J the rotation in the (p, q) plane
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for (k, (apk, aqk)) in rp.iter().zip(&rq).enumerate() {
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let lam = [a[0][0], a[1][1], a[2][2]];
    let vecs = [
        [v[0][0], v[1][0], v[2][0]],
        [v[0][1], v[1][1], v[2][1]],
        [v[0][2], v[1][2], v[2][2]],
    ];
    (lam, vecs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_eigen_3x3() {
        let a = [[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]];
        let (lam, v) = sym3_eigen(a);
        for k in 0..3 {
            for i in 0..3 {
                let av: f64 = (0..3).map(|j| a[i][j] * v[k][j]).sum();
                assert!((av - lam[k] * v[k][i]).abs() < 1e-12, "{lam:?}");
            }
        }
    }

    #[test]
    fn rigid_modes_are_named() {
        // unit square's corners, scaled and shifted far away: the check is scale invariant
        let (s, o) = (1e-7, 1e5);
        let xy: Vec<[f64; 2]> = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .iter()
            .map(|p| [o + s * p[0], o + s * p[1]])
            .collect();
        let err = |dofs: &[usize]| {
            let bc = Dirichlet {
                dofs: dofs.iter().map(|&d| (d, 0.0)).collect(),
            };
            match bc.check_rigid_modes(&xy) {
                Ok(()) => String::new(),
                Err(Error::Singular { detail }) => detail,
                Err(e) => panic!("{e}"),
            }
        };
        // u2 on the bottom and top, u1 nowhere: x1 translation free
        let e = err(&[1, 3, 5, 7]);
        assert!(
            e.contains("1 rigid-body mode(s) free: x1 translation"),
            "{e}"
        );
        assert_eq!(err(&[1, 3, 5, 7, 0]), "");
        // one u1 only (node 0): x2 translation and rotation about any point of the line y = y0
        let e = err(&[0]);
        assert!(
            e.contains("2 rigid-body mode(s) free: x2 translation, rotation about (")
                && e.contains(", 1.000000e5)"),
            "{e}"
        );
        // u1 on two nodes of a vertical line: rotation removed too, x2 translation free
        let e = err(&[0, 6]);
        assert!(
            e.contains("1 rigid-body mode(s) free: x2 translation ("),
            "{e}"
        );
        // nothing
        let e = err(&[]);
        assert!(
            e.contains("x1 translation, x2 translation, rotation"),
            "{e}"
        );
        // node 0 pinned: rotation about it
        let e = err(&[0, 1]);
        assert!(
            e.contains("1 rigid-body mode(s) free: rotation about (1.000000e5, 1.000000e5)"),
            "{e}"
        );
        // enriched dofs (beyond the nodes) are ignored
        assert!(err(&[1, 3, 100]).contains("x1 translation"));
    }
}
