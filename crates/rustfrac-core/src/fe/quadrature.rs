//! Gauss-Legendre rules on [-1, 1] and tensor-product rules on sub-squares of the reference
//! element (the sub-quad integration of eqs. 34-35).

/// Points and weights of the n-point Gauss-Legendre rule on [-1, 1], n = 1..=5.
pub fn gauss_1d(n: usize) -> (Vec<f64>, Vec<f64>) {
    match n {
        1 => (vec![0.0], vec![2.0]),
        2 => {
            let a = 1.0 / 3f64.sqrt();
            (vec![-a, a], vec![1.0, 1.0])
        }
        3 => {
            let a = (0.6f64).sqrt();
            (vec![-a, 0.0, a], vec![5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0])
        }
        4 => {
            let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let wa = (18.0 + 30f64.sqrt()) / 36.0;
            let wb = (18.0 - 30f64.sqrt()) / 36.0;
            (vec![-b, -a, a, b], vec![wb, wa, wa, wb])
        }
        5 => {
            let a = (5.0 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
            let b = (5.0 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
            let w0 = 128.0 / 225.0;
            let wa = (322.0 + 13.0 * 70f64.sqrt()) / 900.0;
            let wb = (322.0 - 13.0 * 70f64.sqrt()) / 900.0;
            (vec![-b, -a, 0.0, a, b], vec![wb, wa, w0, wa, wb])
        }
        _ => panic!("gauss_1d: n must be 1..=5"),
    }
}

/// A quadrature point in natural coordinates with its weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QPoint {
    pub xi: f64,
    pub eta: f64,
    pub w: f64,
}

/// Tensor-product rule: the reference square split into `nsub x nsub` sub-squares, each with an
/// `ng x ng` Gauss rule (eq. 35). `nsub = 1` is the plain Gauss rule.
pub fn subquad_rule(nsub: usize, ng: usize) -> Vec<QPoint> {
    let (g, w) = gauss_1d(ng);
    let h = 2.0 / nsub as f64;
    let mut pts = Vec::with_capacity(nsub * nsub * ng * ng);
    for sj in 0..nsub {
        for si in 0..nsub {
            let (x0, y0) = (-1.0 + si as f64 * h, -1.0 + sj as f64 * h);
            for (b, gy) in g.iter().enumerate() {
                for (a, gx) in g.iter().enumerate() {
                    pts.push(QPoint {
                        xi: x0 + 0.5 * h * (gx + 1.0),
                        eta: y0 + 0.5 * h * (gy + 1.0),
                        w: w[a] * w[b] * 0.25 * h * h,
                    });
                }
            }
        }
    }
    pts
}

/// A rule on the reference triangle: barycentric coordinates (l1, l2; l3 = 1 - l1 - l2) and
/// weights summing to 1 (multiply by the triangle's area). `degree` 2: the 3-point rule (exact
/// for quadratics, Strang & Fix 1973); above 2: the 7-point degree-5 rule (Radon 1948;
/// Zienkiewicz & Taylor, The Finite Element Method, table 5.3).
pub fn triangle_rule(degree: usize) -> Vec<([f64; 2], f64)> {
    if degree <= 2 {
        let (a, b) = (1.0 / 6.0, 2.0 / 3.0);
        return vec![
            ([a, a], 1.0 / 3.0),
            ([b, a], 1.0 / 3.0),
            ([a, b], 1.0 / 3.0),
        ];
    }
    let s15 = 15f64.sqrt();
    let (a1, a2) = ((6.0 - s15) / 21.0, (6.0 + s15) / 21.0);
    let (w1, w2) = ((155.0 - s15) / 1200.0, (155.0 + s15) / 1200.0);
    let (b1, b2) = (1.0 - 2.0 * a1, 1.0 - 2.0 * a2);
    vec![
        ([1.0 / 3.0, 1.0 / 3.0], 0.225),
        ([a1, a1], w1),
        ([b1, a1], w1),
        ([a1, b1], w1),
        ([a2, a2], w2),
        ([b2, a2], w2),
        ([a2, b2], w2),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_integrate_polynomials_exactly() {
        for n in 1..=5 {
            let (x, w) = gauss_1d(n);
            for p in 0..2 * n {
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(p as i32)).sum();
                let exact = if p % 2 == 1 {
                    0.0
                } else {
                    2.0 / (p as f64 + 1.0)
                };
                assert!((q - exact).abs() < 1e-14, "n={n} p={p}");
            }
        }
        let r = subquad_rule(4, 2);
        assert_eq!(r.len(), 64);
        let area: f64 = r.iter().map(|p| p.w).sum();
        assert!((area - 4.0).abs() < 1e-14);
        let m: f64 = r.iter().map(|p| p.w * p.xi.powi(2) * p.eta.powi(2)).sum();
        assert!((m - 4.0 / 9.0).abs() < 1e-14);
    }

    #[test]
    fn triangle_rules_integrate_polynomials_exactly() {
        // int over the unit triangle of x^p y^q = p! q! / (p + q + 2)!
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        for (deg, rule) in [(2, triangle_rule(2)), (5, triangle_rule(5))] {
            for p in 0..=deg {
                for q in 0..=deg - p {
                    let v: f64 = rule
                        .iter()
                        .map(|(l, w)| 0.5 * w * l[0].powi(p as i32) * l[1].powi(q as i32))
                        .sum();
                    let exact = fact(p) * fact(q) / fact(p + q + 2);
                    assert!((v - exact).abs() < 1e-15, "deg {deg}: x^{p} y^{q}");
                }
            }
        }
    }
}
