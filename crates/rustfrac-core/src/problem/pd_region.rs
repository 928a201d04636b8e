//! The adaptive CCM-PD region's geometry (`pd.region = "adaptive"`): where the PD region
//! starts and how it grows (docs/design.md, "The adaptive region"). The SLA side (when it grows,
//! the re-built model, the state carried over) is [`crate::pd::sla`] (`adaptive.rs`).
//!
//! * **Start**: one square of half-side `size` horizons around each crack tip (the scene's
//!   crack; [`crate::problem::CrackSpec::tips`]).
//! * **Growth**: when the SLA's critical bond has an end node within `margin` horizons of a FEM
//!   node, a square of half-side `size` horizons around the bond's midpoint is added before the
//!   bond breaks. Since the bond is at most one horizon long, the square holds every node within
//!   (size - 1/2) horizons of its ends, so `size >= margin + 1` (the scene's rule) leaves no FEM
//!   node within `margin` horizons of the bond: no bond breaks closer than `margin` horizons to
//!   the interface unless the plate's edge clips the square (then the interface is the edge's).
//! * Every square is snapped outwards to the PD grid's lines (multiples of dx from the plate's
//!   corner), clipped to the plate, and widened to take in the bounding box (plus one cell) of
//!   every hole it comes within two cells of, so a hole is either in the FEM part, clear of the
//!   interface, or inside one PD rectangle (a PD hole, [`crate::pd::splice`]'s rule).
//! * A square inside another rectangle adds nothing and is dropped.

use super::{AdaptiveRegion, Domain, Problem};

/// The square of half-side `size` horizons around `c`, snapped outwards to the grid lines,
/// clipped to the plate and widened over the holes near it.
fn square(d: &Domain, dx: f64, delta: f64, size: f64, c: [f64; 2]) -> [f64; 4] {
    let h = size * delta;
    let snap_lo = |v: f64| ((v / dx + 1e-9).floor() * dx).max(0.0);
    let snap_hi = |v: f64, len: f64| ((v / dx - 1e-9).ceil() * dx).min(len);
    let mut r = [
        snap_lo(c[0] - h),
        snap_lo(c[1] - h),
        snap_hi(c[0] + h, d.width),
        snap_hi(c[1] + h, d.height),
    ];
    // take in the holes it touches (two cells of clearance), until none is cut
    loop {
        let mut changed = false;
        for hole in &d.holes {
            let b = hole.shape.bounding_box();
            let near = b[0] <= r[2] + 2.0 * dx
                && b[2] >= r[0] - 2.0 * dx
                && b[1] <= r[3] + 2.0 * dx
                && b[3] >= r[1] - 2.0 * dx;
            let inside =
                r[0] <= b[0] - dx && r[1] <= b[1] - dx && b[2] + dx <= r[2] && b[3] + dx <= r[3];
            if near && !inside {
                let w = [
                    snap_lo(r[0].min(b[0] - dx)),
                    snap_lo(r[1].min(b[1] - dx)),
                    snap_hi(r[2].max(b[2] + dx), d.width),
                    snap_hi(r[3].max(b[3] + dx), d.height),
                ];
                if w != r {
                    r = w;
                    changed = true;
                }
            }
        }
        if !changed {
            return r;
        }
    }
}

fn contains(outer: &[f64; 4], inner: &[f64; 4]) -> bool {
    outer[0] <= inner[0] && outer[1] <= inner[1] && inner[2] <= outer[2] && inner[3] <= outer[3]
}

/// `regions` with the squares around `centres` added (those inside a rectangle dropped).
pub fn grown(
    d: &Domain,
    dx: f64,
    delta: f64,
    a: &AdaptiveRegion,
    regions: &[[f64; 4]],
    centres: &[[f64; 2]],
) -> Vec<[f64; 4]> {
    let mut out = regions.to_vec();
    for &c in centres {
        let s = square(d, dx, delta, a.size, c);
        if !out.iter().any(|r| contains(r, &s)) {
            out.retain(|r| !contains(&s, r));
            out.push(s);
        }
    }
    out
}

/// The region an adaptive run starts with: the squares around the tips of the problem's crack
/// (none without a crack: the run then starts with no PD and is refused by the CCM-PD rules).
pub fn initial(p: &Problem, dx: f64, m: usize, a: &AdaptiveRegion) -> Vec<[f64; 4]> {
    let tips: Vec<[f64; 2]> = p
        .cracks
        .first()
        .map(|c| c.tips(&p.domain))
        .unwrap_or_default();
    grown(&p.domain, dx, m as f64 * dx, a, &[], &tips)
}
