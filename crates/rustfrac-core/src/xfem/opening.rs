//! Evaluation of the enriched displacement field (eq. 3) at a point, the opening of a crack
//! (the normal displacement jump across its faces) and the crack mouth opening displacement
//! (CMOD) reported by the plate driver.

use super::model::{BasisBuf, XfemModel};
use crate::error::{Error, Result};
use crate::geometry::{dot, norm, sub, unit};

impl XfemModel {
    /// Displacement of the enriched field at a point (None outside the plate).
    pub fn displacement_at(&self, u: &[f64], x: [f64; 2]) -> Option<[f64; 2]> {
        let (e, xi, eta) = self.mesh.locate(x[0], x[1])?;
        let en = self.enriched(e);
        let mut b = BasisBuf::default();
        self.basis(e, en, xi, eta, &mut b);
        let dofs = self.element_dofs(e);
        let mut r = [0.0; 2];
        for (f, v) in b.vals.iter().enumerate() {
            r[0] += v * u[dofs[2 * f]];
            r[1] += v * u[dofs[2 * f + 1]];
        }
        Some(r)
    }

    /// Opening (normal displacement jump, upper minus lower face) at a point of the crack, from
    /// the enriched field evaluated just off both faces.
    pub fn opening_at(&self, u: &[f64], x: [f64; 2], normal: [f64; 2]) -> Result<f64> {
        let eps = 1e-8 * self.mesh.min_spacing();
        let p = [x[0] + eps * normal[0], x[1] + eps * normal[1]];
        let m = [x[0] - eps * normal[0], x[1] - eps * normal[1]];
        match (self.displacement_at(u, p), self.displacement_at(u, m)) {
            (Some(a), Some(b)) => Ok(dot(sub(a, b), normal)),
            _ => Err(Error::invalid(
                "opening point",
                "a point inside the plate",
                format!("{x:?}"),
            )),
        }
    }

    /// The jump of the enriched displacement (upper minus lower face: [normal opening, sliding
    /// along the crack's direction]) across crack `c` at the crack point nearest `x`.
    pub fn jump_at(&self, u: &[f64], c: usize, x: [f64; 2]) -> Result<[f64; 2]> {
        let crack = self
            .cracks
            .get(c)
            .ok_or_else(|| Error::invalid("probe.crack", &format!("< {}", self.cracks.len()), c))?;
        let mut best = (f64::INFINITY, [0.0; 2], [1.0, 0.0]);
        for w in crack.points.windows(2) {
            let d = sub(w[1], w[0]);
            let l2 = dot(d, d);
            let s = (dot(sub(x, w[0]), d) / l2).clamp(0.0, 1.0);
            let q = [w[0][0] + s * d[0], w[0][1] + s * d[1]];
            let dist = norm(sub(x, q));
            if dist < best.0 {
                best = (dist, q, unit(d));
            }
        }
        let (_, q, t) = best;
        let n = [-t[1], t[0]];
        let eps = 1e-8 * self.mesh.min_spacing();
        // a hair inside along the crack, so both faces lie on the plate at a mouth
        let q = [
            q[0] + 1e-6 * self.mesh.min_spacing() * t[0],
            q[1] + 1e-6 * self.mesh.min_spacing() * t[1],
        ];
        let p = [q[0] + eps * n[0], q[1] + eps * n[1]];
        let m = [q[0] - eps * n[0], q[1] - eps * n[1]];
        match (self.displacement_at(u, p), self.displacement_at(u, m)) {
            (Some(a), Some(b)) => {
                let j = sub(a, b);
                Ok([dot(j, n), dot(j, t)])
            }
            _ => Err(Error::invalid(
                "probe.point",
                "a point whose nearest crack point lies inside the plate",
                format!("{x:?}"),
            )),
        }
    }

    /// Where the crack's first segment a -> b enters the material: `a` itself without holes or
    /// when `a` lies in the material, else the first point of the segment outside every hole
    /// (bisection on the domain's level set, to 1e-12 of the segment; a crack drawn from the
    /// plate's edge through a notch opens at the notch's tip).
    fn mouth_in_material(&self, a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
        let Some(fd) = &self.fictitious else {
            return a;
        };
        let at = |t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        if fd.in_material(a) || !fd.in_material(b) {
            return a;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        while hi - lo > 1e-12 {
            let mid = 0.5 * (lo + hi);
            if fd.in_material(at(mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        at(hi)
    }

    /// CMOD of the primary crack (`cracks[0]`): see [`Self::crack_opening`].
    pub fn cmod(&self, u: &[f64]) -> Result<f64> {
        self.crack_opening(u, 0)
    }

    /// The opening of crack `c` at the mouth of an edge crack (`points[0]`; with holes, where the
    /// crack enters the material), or at the middle of an interior crack (arc-length midpoint).
    pub fn crack_opening(&self, u: &[f64], c: usize) -> Result<f64> {
        let Some(crack) = self.cracks.get(c) else {
            return Err(Error::invalid(
                "crack index",
                &format!("< {}", self.cracks.len()),
                c,
            ));
        };
        let p = &crack.points;
        if crack.mouth {
            let t = unit(sub(p[1], p[0]));
            // a hair inside the plate along the crack (well above the normal offset of
            // `opening_at`) so both evaluation points lie inside the plate
            let eps = 1e-6 * self.mesh.min_spacing();
            let m = self.mouth_in_material(p[0], p[1]);
            let x = [m[0] + eps * t[0], m[1] + eps * t[1]];
            return self.opening_at(u, x, [-t[1], t[0]]);
        }
        let half = 0.5 * crack.length();
        let mut s = 0.0;
        for w in p.windows(2) {
            let l = norm(sub(w[1], w[0]));
            if s + l >= half {
                let f = (half - s) / l;
                let x = [
                    w[0][0] + f * (w[1][0] - w[0][0]),
                    w[0][1] + f * (w[1][1] - w[0][1]),
                ];
                let t = unit(sub(w[1], w[0]));
                return self.opening_at(u, x, [-t[1], t[0]]);
            }
            s += l;
        }
        Err(Error::Internal {
            detail: "crack midpoint not found".into(),
        })
    }
}
