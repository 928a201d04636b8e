//! The critical-bond search of an SLA step ([`critical_bonds`]): the bond(s) with the smallest
//! load factor lambda = s0 / s. With `tie_tol > 0` every bond whose load factor is within that
//! relative tolerance of lambda breaks with it. Ties closer than 1e-10 (mirror bonds in mode I)
//! are broken deterministically: the lowest bond index goes first, so two solvers that agree to
//! round-off produce the same sequence.

use super::engine::Engine;
use crate::pd::splice::SpliceModel;

/// The bonds to break in the engine's last state: lambda_b = s0 / s_b for every intact bond in
/// tension (s0 x the bond's factor under the surface correction,
/// [`crate::pd::surface_correction::critical_stretch_scale`]), lmin = min lambda, and every bond
/// with lambda_b <= lmin (1 + max(tie_tol, 1e-10)) in index order (only the first when
/// tie_tol = 0). None when no bond is in tension. `lam` is scratch of one value per bond. The
/// stretches come from [`Engine::stretches`]: a bond it leaves at an upper bound cannot reach
/// that window, so the selection is the one of the exact stretches.
///
/// Without the surface correction the divisions s0 / s_b are taken only where they can decide:
/// a correctly rounded division is monotone, so min_b s0 / s_b = s0 / max_b s_b exactly, and the
/// tie test is made exactly (the same division as before) on the bonds whose stretch passes a
/// looser bound; one division per bond fewer, the same bonds and lmin bit for bit.
pub(super) fn critical_bonds(
    model: &SpliceModel,
    broken: &[bool],
    engine: &mut dyn Engine,
    s0: f64,
    tie_tol: f64,
    lam: &mut [f64],
) -> Option<(f64, Vec<usize>)> {
    let tol = tie_tol.max(1e-10);
    let scale = model.surface.as_ref().map(|sf| &sf.s0_scale[..]);
    // lam holds the stretches (-inf for broken bonds), of the bonds `only` when screened
    let mut only = Vec::new();
    let screened = engine.stretches(model, broken, scale, tol, lam, &mut only);
    let n = if screened {
        only.len()
    } else {
        model.bonds.len()
    };
    let id = |i: usize| if screened { only[i] } else { i };
    let (lmin, mut sel) = match scale {
        Some(sc) => {
            let mut lmin = f64::INFINITY;
            for b in (0..n).map(id) {
                let s = lam[b];
                lam[b] = f64::INFINITY;
                if s > 0.0 {
                    // the surface correction keeps each bond's critical energy
                    lam[b] = s0 * sc[b] / s;
                    lmin = lmin.min(lam[b]);
                }
            }
            if !lmin.is_finite() {
                return None;
            }
            let sel: Vec<usize> = (0..n)
                .map(id)
                .filter(|&b| lam[b] <= lmin * (1.0 + tol))
                .collect();
            (lmin, sel)
        }
        None => critical_by_stretch(lam, (0..n).map(id), s0, tol)?,
    };
    if tie_tol == 0.0 {
        sel.truncate(1);
    }
    Some((lmin, sel))
}

/// [`critical_bonds`] without the surface correction, from the stretches `s` (-inf for a broken
/// bond): lmin = s0 / max s (exactly min_b s0 / s_b: a correctly rounded division is monotone) and
/// the bonds with s0 / s_b <= lmin (1 + tol) in index order, the division made only for the bonds
/// whose stretch passes a looser cut.
fn critical_by_stretch(
    s: &[f64],
    bonds: impl Iterator<Item = usize> + Clone,
    s0: f64,
    tol: f64,
) -> Option<(f64, Vec<usize>)> {
    let smax = bonds
        .clone()
        .fold(0.0f64, |m, b| if s[b] > m { s[b] } else { m });
    let lmin = s0 / smax;
    if !(smax > 0.0 && lmin.is_finite()) {
        return None;
    }
    let bound = lmin * (1.0 + tol);
    // s0 / s <= bound needs s >= s0 / bound up to rounding: a looser cut, then the test
    let cut = if bound > 0.0 {
        s0 / bound * (1.0 - 1e-6)
    } else {
        0.0
    };
    let sel = bonds
        .filter(|&b| s[b] > 0.0 && s[b] >= cut && s0 / s[b] <= bound)
        .collect();
    Some((lmin, sel))
}

#[cfg(test)]
mod tests {
    use super::critical_by_stretch;

    /// The reference: lambda_b = s0 / s_b for every bond in tension, lmin = min, the bonds within
    /// the tolerance in index order (the rule as it was written before the one-division form).
    fn reference(s: &[f64], s0: f64, tol: f64) -> Option<(f64, Vec<usize>)> {
        let lam: Vec<f64> = s
            .iter()
            .map(|&v| if v > 0.0 { s0 / v } else { f64::INFINITY })
            .collect();
        let lmin = lam.iter().copied().fold(f64::INFINITY, f64::min);
        if !lmin.is_finite() {
            return None;
        }
        let sel = (0..s.len())
            .filter(|&b| lam[b] <= lmin * (1.0 + tol))
            .collect();
        Some((lmin, sel))
    }

    /// Random stretches (tension, compression, broken, exact and near ties, one-ulp neighbours,
    /// tiny and huge values): the same lmin bit for bit and the same bonds as the reference.
    #[test]
    fn one_division_form_selects_what_the_reference_selects() {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..400 {
            let n = 1 + (rnd() * 300.0) as usize;
            let scale = 10f64.powi((rnd() * 40.0) as i32 - 20);
            let mut s: Vec<f64> = (0..n)
                .map(|_| match (rnd() * 10.0) as u32 {
                    0 => f64::NEG_INFINITY,
                    1 => -rnd() * scale,
                    2 => 0.0,
                    _ => rnd() * scale,
                })
                .collect();
            // ties: copies of the largest, its one-ulp neighbours, values just inside and outside
            // the tolerance
            let m = s.iter().copied().fold(0.0f64, f64::max);
            if m > 0.0 && n > 4 {
                s[0] = m;
                s[1] = f64::from_bits(m.to_bits() - 1);
                s[2] = m / (1.0 + 1e-10);
                s[3] = m / (1.0 + 2e-10);
            }
            let s0 = 10f64.powi((rnd() * 8.0) as i32 - 6) * (1.0 + rnd());
            for tol in [1e-10, 1e-6, 1e-2, 0.5] {
                let got = critical_by_stretch(&s, 0..s.len(), s0, tol);
                let want = reference(&s, s0, tol);
                match (&got, &want) {
                    (Some((a, sa)), Some((b, sb))) => {
                        assert_eq!(a.to_bits(), b.to_bits(), "case {case} tol {tol}");
                        assert_eq!(sa, sb, "case {case} tol {tol}");
                    }
                    (None, None) => {}
                    _ => panic!("case {case} tol {tol}: {got:?} against {want:?}"),
                }
            }
        }
        assert!(critical_by_stretch(&[-1.0, f64::NEG_INFINITY, 0.0], 0..3, 1e-3, 1e-10).is_none());
    }
}
