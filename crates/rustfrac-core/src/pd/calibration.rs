//! The calibration of the critical stretch s0 (scene key `pd.s0_calibration`;
//! docs/design.md, "The bond-based PD model and gamma").
//!
//! Eq. 48, s0 = sqrt(5 pi G0 / (12 E delta)), makes the *continuum* energy of the bonds crossing a
//! line equal G0. On a grid the fracture energy differs: the bonds of the stencil crossing a line
//! carry another energy ([`grid_energy_ratio`]), and the SLA releases more than the energy of the
//! bonds it breaks (each break snaps: [`sla_energy_ratio`]). Between breaks the SLA is linear and
//! one s0 applies to every bond, so the order of breaks does not depend on s0, every load factor
//! scales with s0 and every released energy with s0^2. Calibrating s0 so that a reference energy
//! G_ref (computed with eq. 48's s0) equals G0 is therefore the rescaling
//! s0' = s0 sqrt(G0 / G_ref) ([`Calibration::factor`]); c is not touched.
//!
//! * `"continuum"` ([`S0Calibration::Continuum`], the default, the paper's): eq. 48.
//! * `"grid"`: G_ref = the discrete fracture energy of the grid stencil: the energy
//!   1/2 c s0^2 |xi| beta V^2 of the bonds crossing a straight x1-parallel line between node rows,
//!   per unit area (the paper's crack direction; for other directions the same x1 line is used).
//!   A bond of offset (di, dj), dj > 0, crosses such a line dj times per grid column, so
//!   G_ref / G0 = 2 gamma / m^4 sum_{dj > 0} dj |(di, dj)| beta  (grid units; with eq. 47's c and
//!   eq. 48's s0, c s0^2 = 4 gamma G0 / (h m^4 dx^4)), independent of dx; the continuum integral
//!   (beta = 1 inside the disc, gamma = 1) gives 1.
//! * `"sla"`: G_ref = the energy the SLA releases per unit of new crack area while a pure-PD
//!   reference strip ([`reference_strip`]: [`STRIP_WIDTH`] x [`STRIP_HEIGHT`] horizons, free
//!   grips, an edge pre-crack of [`STRIP_PRECRACK`] horizons at mid-height) breaks across until it
//!   separates; the release of each break is 1/2 D^2 (K_before - K_after) with P = sigma22 W t,
//!   D = 2 u0, K = P / D (as `rustfrac.energy`). The SLA is scale-free (a strip in cells gives the
//!   same ratio for any dx, E, G0), so it is run once per m per process, on dx = 1
//!   ([`sla_energy_ratio`], memoised).

use crate::error::{Error, Result};
use crate::pd::family_stencil;
use crate::pd::gamma;
use crate::pd::sla::{self, SlaStatus};
use crate::problem::schema::check_horizon_factor;
use crate::problem::value::{Table, Value};
pub use crate::problem::Calibration;
use crate::problem::{Problem, S0Calibration};
use std::collections::HashMap;
use std::sync::Mutex;

/// The calibration of `rule` for horizon factor m (`pd.m`'s range).
pub fn calibration(rule: S0Calibration, m: usize) -> Result<Calibration> {
    let g = match rule {
        S0Calibration::Continuum => 1.0,
        S0Calibration::Grid => grid_energy_ratio(m)?,
        S0Calibration::Sla => sla_energy_ratio(m)?,
    };
    Ok(Calibration {
        rule,
        factor: if rule == S0Calibration::Continuum {
            1.0
        } else {
            (1.0 / g).sqrt()
        },
        g_ref_over_g0: g,
    })
}

/// The grid's discrete fracture energy over G0 with eq. 48's s0 and eq. 47's c (with gamma):
/// 2 gamma / m^4 sum_{dj > 0} dj |(di, dj)| beta over the family stencil (module docs).
pub fn grid_energy_ratio(m: usize) -> Result<f64> {
    check_horizon_factor(m)?;
    let s: f64 = family_stencil(m)
        .iter()
        .filter(|e| e.dj > 0)
        .map(|e| {
            let (a, b) = (e.di as f64, e.dj as f64);
            b * a.hypot(b) * e.beta
        })
        .sum();
    Ok(2.0 * gamma(m)? / (m as f64).powi(4) * s)
}

/// Width of the reference strip in horizons (x1, the direction the crack crosses).
pub const STRIP_WIDTH: usize = 6;
/// Height of the reference strip in horizons (x2, between the grips).
pub const STRIP_HEIGHT: usize = 8;
/// Edge pre-crack of the reference strip in horizons (plus half a cell: its tip lies between
/// node columns).
pub const STRIP_PRECRACK: usize = 1;

/// The reference strip of the `"sla"` rule: pure PD, `width` x `height` horizons of cells of size
/// dx, free grips, an edge pre-crack of `precrack` horizons + dx/2 along the line between the
/// middle node rows, the SLA run until the strip separates.
pub fn reference_strip(
    m: usize,
    dx: f64,
    width: usize,
    height: usize,
    precrack: usize,
) -> Result<Problem> {
    check_horizon_factor(m)?;
    let (nw, nh) = ((width * m) as f64, (height * m) as f64);
    let mut t = Table::new();
    let sec = |kv: &[(&str, Value)]| {
        Value::Table(kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
    };
    t.insert("method".into(), Value::Str("pd".into()));
    t.insert(
        "plate".into(),
        sec(&[
            ("width", Value::Float(nw * dx)),
            ("height", Value::Float(nh * dx)),
        ]),
    );
    let y = ((nh / 2.0).floor() + 0.5) * dx;
    let a0 = ((precrack * m) as f64 + 0.5) * dx;
    t.insert(
        "crack".into(),
        sec(&[
            ("kind", Value::Str("edge".into())),
            ("a0", Value::Float(a0)),
            ("y", Value::Float(y)),
        ]),
    );
    t.insert(
        "pd".into(),
        sec(&[
            ("dx", Value::Float(dx)),
            ("m", Value::Int(m as i64)),
            (
                "sla_steps",
                Value::Int(crate::problem::schema::MAX_STEPS as i64),
            ),
        ]),
    );
    Problem::from_scene(&t)
}

/// The energy the SLA releases per unit of new crack area while `p` (a pure-PD plate under
/// grips with an edge pre-crack, e.g. [`reference_strip`]) breaks across, over G0: the sum of
/// 1/2 D_k^2 (K_k - K_k+1) (K after the last break 0) over t (W - a0) G0. Errors if the run does
/// not end separated.
pub fn strip_release_ratio(p: &Problem) -> Result<f64> {
    // the strip's own rule is eq. 48 (`reference_strip` sets no pd.s0_calibration)
    let r = sla::run_calibrated(p, Calibration::continuum(), &|_| true)?;
    if r.run.status != SlaStatus::Separated {
        return Err(Error::Internal {
            detail: format!(
                "s0 calibration 'sla': the reference strip did not separate ({} after {} steps)",
                r.run.status.name(),
                r.history.len()
            ),
        });
    }
    let d = &p.domain;
    let t = p.material.elastic.thickness;
    let [a, b] = p
        .boundary
        .work_conjugate(d.width, t)
        .ok_or_else(|| Error::Internal {
            detail: "s0 calibration 'sla': the reference strip needs displacement grips".into(),
        })?;
    let k: Vec<(f64, f64)> = r
        .history
        .iter()
        .map(|s| {
            let (pp, dd) = (a * s.sigma22, b * s.u0);
            (dd, pp / dd)
        })
        .collect();
    let mut e = 0.0;
    for (i, &(dd, kk)) in k.iter().enumerate() {
        let after = k.get(i + 1).map_or(0.0, |x| x.1);
        e += 0.5 * dd * dd * (kk - after);
    }
    let a0 = p.cracks.first().map_or(0.0, |c| c.a0);
    Ok(e / (t * (d.width - a0)) / p.material.g0)
}

/// G_ref / G0 of the `"sla"` rule for horizon factor m: [`strip_release_ratio`] of the
/// [`reference_strip`] on dx = 1, computed once per m per process.
pub fn sla_energy_ratio(m: usize) -> Result<f64> {
    check_horizon_factor(m)?;
    static MEMO: Mutex<Option<HashMap<usize, f64>>> = Mutex::new(None);
    let cached = |m| {
        MEMO.lock()
            .ok()
            .and_then(|g| g.as_ref().and_then(|h| h.get(&m).copied()))
    };
    if let Some(v) = cached(m) {
        return Ok(v);
    }
    let p = reference_strip(m, 1.0, STRIP_WIDTH, STRIP_HEIGHT, STRIP_PRECRACK)?;
    let v = strip_release_ratio(&p)?;
    if let Ok(mut g) = MEMO.lock() {
        g.get_or_insert_with(HashMap::new).insert(m, v);
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pd::partial_volume::cell_fraction;

    /// The continuum limit of the grid sum: with beta from a fine disc (large m) the ratio
    /// tends to 1 (and gamma to 1).
    #[test]
    fn grid_ratio_tends_to_one() {
        let r12 = grid_energy_ratio(12).unwrap();
        assert!((r12 - 1.0).abs() < 0.01, "{r12}");
        // independent count: bonds from the nodes of one column at or below row 0 to the nodes
        // at or above row 1 (the line between rows 0 and 1 crossed)
        let m = 3usize;
        let mut s = 0.0;
        let r = m as i32 + 1;
        for j in -2 * r..=0 {
            for dj in 1..=2 * r {
                if j + dj < 1 {
                    continue;
                }
                for di in -r..=r {
                    let beta = cell_fraction(di as f64, dj as f64, m as f64);
                    s += (di as f64).hypot(dj as f64) * beta;
                }
            }
        }
        let direct = 2.0 * gamma(m).unwrap() / (m as f64).powi(4) * s;
        assert!((direct - grid_energy_ratio(m).unwrap()).abs() < 1e-12);
    }
}
