//! Exact partial volumes of the family (paper section 2.2.1, eq. 54).
//!
//! The family of a node is every grid node whose cell overlaps the horizon disc of radius
//! `delta = m dx` (eq. 57); its partial-volume factor `beta` is the *exact* fraction of that cell
//! inside the disc (circle / square intersection in closed form, [`cell_fraction`]). Cells whose
//! centre lies outside the disc but which overlap it carry their (small) fraction too: this is the
//! choice that reproduces the paper's gamma. The offsets and factors of one family form a fixed
//! stencil ([`family_stencil`]), the same for every node of the uniform grid.

/// Area of {0 <= X <= x, 0 <= Y <= y} inside the disc of radius r centred at the origin (x, y >= 0).
fn corner_area(x: f64, y: f64, r: f64) -> f64 {
    let x = x.min(r);
    let y = y.min(r);
    if x <= 0.0 || y <= 0.0 {
        return 0.0;
    }
    if x * x + y * y <= r * r {
        return x * y;
    }
    // sqrt(r^2 - X^2) = y at X = xc; for X < xc the height is y, beyond it the arc
    let xc = (r * r - y * y).max(0.0).sqrt();
    let prim = |t: f64| 0.5 * (t * (r * r - t * t).max(0.0).sqrt() + r * r * (t / r).asin());
    y * xc + (prim(x) - prim(xc))
}

fn signed_corner(x: f64, y: f64, r: f64) -> f64 {
    x.signum() * y.signum() * corner_area(x.abs(), y.abs(), r)
}

/// Exact area of the rectangle [x0, x1] x [y0, y1] inside the disc of radius r centred at the
/// origin (inclusion-exclusion of signed corner areas, each in closed form).
pub fn rect_disc_area(x0: f64, x1: f64, y0: f64, y1: f64, r: f64) -> f64 {
    signed_corner(x1, y1, r) - signed_corner(x0, y1, r) - signed_corner(x1, y0, r)
        + signed_corner(x0, y0, r)
}

/// Exact fraction of the unit cell centred at (a, b) (grid units) inside the disc of radius m.
pub fn cell_fraction(a: f64, b: f64, m: f64) -> f64 {
    rect_disc_area(a - 0.5, a + 0.5, b - 0.5, b + 0.5, m).clamp(0.0, 1.0)
}

/// One stencil entry: grid offset (di, dj) and its partial-volume factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StencilEntry {
    pub di: i32,
    pub dj: i32,
    pub beta: f64,
}

/// The family stencil of horizon m (grid units): every offset != (0, 0) whose cell overlaps the
/// disc, with its exact partial-volume factor; sorted by (dj, di).
pub fn family_stencil(m: usize) -> Vec<StencilEntry> {
    let r = m as i32 + 1;
    let mut out = Vec::new();
    for dj in -r..=r {
        for di in -r..=r {
            if di == 0 && dj == 0 {
                continue;
            }
            let beta = cell_fraction(di as f64, dj as f64, m as f64);
            if beta > 0.0 {
                out.push(StencilEntry { di, dj, beta });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn exact_areas() {
        // whole disc
        let a = rect_disc_area(-2.0, 2.0, -2.0, 2.0, 1.0);
        assert!((a - PI).abs() < 1e-14);
        // quarter disc
        assert!((rect_disc_area(0.0, 1.0, 0.0, 1.0, 1.0) - PI / 4.0).abs() < 1e-14);
        // half disc
        assert!((rect_disc_area(-1.0, 1.0, 0.0, 3.0, 1.0) - PI / 2.0).abs() < 1e-14);
        // sum of cell fractions = disc area
        let m = 4usize;
        let s: f64 = family_stencil(m).iter().map(|e| e.beta).sum::<f64>()
            + cell_fraction(0.0, 0.0, m as f64);
        assert!((s - PI * 16.0).abs() < 1e-11, "{s}");
    }
}
