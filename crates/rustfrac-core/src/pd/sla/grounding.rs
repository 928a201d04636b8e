//! Detached nodes and debris (docs/design.md, "Detached nodes").
//!
//! A PD node's rows hold only its bonds. When its intact bonds give no stiffness along some
//! direction of its free dofs (all broken, or the remaining ones parallel), the system would be
//! singular although the body has not separated. Such a node is *grounded* along that direction by
//! a spring ([`crate::pd::splice`]'s `Spring`, applied before the bond break that needs it, so
//! every intermediate matrix stays regular): with no external force it carries none there, so no
//! other result changes. A small fragment of free PD nodes connected to no held node (debris, at
//! most [`DEBRIS_LIMIT`] nodes) is grounded in every direction of every node. Here: the groundings
//! applied so far and the bounded fragment search.

use crate::pd::splice::{SpliceModel, Spring};

/// Grounding springs already applied, per node (at most two orthonormal directions each), and the
/// work arrays of the bounded fragment search.
pub(super) struct Grounding {
    dirs: std::collections::HashMap<usize, Vec<[f64; 2]>>,
    /// visit stamps per node (`stamp[n] == epoch`: seen in the current search)
    stamp: Vec<u32>,
    epoch: u32,
}

impl Grounding {
    pub(super) fn new(n_nodes: usize) -> Self {
        Self {
            dirs: Default::default(),
            stamp: vec![0; n_nodes],
            epoch: 0,
        }
    }

    /// The debris fragment containing node `n` under `broken`: its component over intact bonds
    /// when that holds at most `limit` nodes, none of them held ([`SpliceModel::is_held`]).
    /// Breadth-first, stopping at the first held node or when the limit is passed: O(limit x
    /// family). Sorted node ids.
    fn debris_fragment(
        &mut self,
        model: &SpliceModel,
        n: usize,
        broken: &[bool],
        limit: usize,
    ) -> Option<Vec<usize>> {
        if model.is_held(n) {
            return None;
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.epoch = 1;
        }
        let e = self.epoch;
        self.stamp[n] = e;
        let mut seen = vec![n];
        let mut k = 0;
        while k < seen.len() {
            let a = seen[k];
            k += 1;
            for &b in model.bonds_of(a) {
                if broken[b as usize] {
                    continue;
                }
                let bond = &model.bonds[b as usize];
                let o = if bond.i as usize == a { bond.j } else { bond.i } as usize;
                if self.stamp[o] == e {
                    continue;
                }
                if model.is_held(o) || seen.len() >= limit {
                    return None;
                }
                self.stamp[o] = e;
                seen.push(o);
            }
        }
        seen.sort_unstable();
        Some(seen)
    }

    /// The new springs node `n` needs under `broken`: its null directions not yet grounded (the
    /// null space only grows as bonds break, so the missing part is orthogonal to the grounded
    /// one).
    fn needed(&mut self, model: &SpliceModel, n: usize, broken: &[bool]) -> Vec<Spring> {
        let null = model.null_directions(n, broken);
        let have = self.dirs.entry(n).or_default();
        if null.len() <= have.len() {
            return Vec::new();
        }
        let new: Vec<[f64; 2]> = if have.is_empty() {
            null
        } else {
            vec![[-have[0][1], have[0][0]]]
        };
        have.extend(&new);
        new.into_iter().map(|p| Spring { node: n, p }).collect()
    }

    /// The springs that ground node `n` in every direction of its free dofs (debris fragments).
    fn full(&mut self, model: &SpliceModel, n: usize) -> Vec<Spring> {
        let have = self.dirs.entry(n).or_default();
        let free = [!model.mask[2 * n], !model.mask[2 * n + 1]];
        let new: Vec<[f64; 2]> = match have.len() {
            0 => [[1.0, 0.0], [0.0, 1.0]]
                .into_iter()
                .zip(free)
                .filter(|(_, f)| *f)
                .map(|(p, _)| p)
                .collect(),
            1 if free[0] && free[1] => vec![[-have[0][1], have[0][0]]],
            _ => Vec::new(),
        };
        have.extend(&new);
        new.into_iter().map(|p| Spring { node: n, p }).collect()
    }

    /// Springs for node `n` under `broken`: its null directions, then, when it belongs to a debris
    /// fragment of 2..=[`DEBRIS_LIMIT`] nodes, every direction of every node of the fragment.
    pub(super) fn springs(
        &mut self,
        model: &SpliceModel,
        n: usize,
        broken: &[bool],
    ) -> Vec<(usize, Spring)> {
        let mut out: Vec<(usize, Spring)> = self
            .needed(model, n, broken)
            .into_iter()
            .map(|s| (n, s))
            .collect();
        if let Some(frag) = self.debris_fragment(model, n, broken, DEBRIS_LIMIT) {
            if frag.len() > 1 {
                for m in frag {
                    out.extend(self.full(model, m).into_iter().map(|s| (m, s)));
                }
            }
        }
        out
    }
}

/// Largest fragment of free PD nodes grounded as debris; a larger part that comes loose ends the
/// run with status "separated".
pub const DEBRIS_LIMIT: usize = 256;
