//! Graded tensor grids: grid lines with a fine uniform spacing in a refinement interval and
//! element sizes growing geometrically (ratio `grading`) away from it, capped at a coarse size.
//! Crack tips need small elements; the far field does not (the singular field decays as r^-1/2),
//! so a graded grid reaches the uniform grid's K_I with far fewer unknowns (benches/RESULTS.md).

/// Grid lines on [0, len]: spacing about `h` in [lo, hi] (clipped to [0, len]; `h` is rounded so
/// the interval holds a whole number of elements), outside it sizes h g, h g^2, ... capped at
/// `coarse`, each run scaled down so the lines end exactly at 0 and `len` (neighbouring sizes
/// differ by at most the ratio `grading`, except where a sliver at an end is merged).
pub fn graded_lines(len: f64, lo: f64, hi: f64, h: f64, grading: f64, coarse: f64) -> Vec<f64> {
    let (lo, hi) = (lo.clamp(0.0, len), hi.clamp(0.0, len));
    let coarse = coarse.max(h);
    let n_in = (((hi - lo) / h).round() as usize).max(usize::from(hi > lo));
    let h_in = if n_in > 0 { (hi - lo) / n_in as f64 } else { h };
    // sizes of the run from the interval outwards over a length `rest`
    let run = |rest: f64| -> Vec<f64> {
        if rest <= 0.0 {
            return Vec::new();
        }
        let mut sizes = Vec::new();
        let (mut s, mut sum) = (h_in, 0.0);
        while sum < rest * (1.0 - 1e-12) {
            s = (s * grading).min(coarse);
            sizes.push(s);
            sum += s;
        }
        // scale the run down to end exactly at the edge (ratios stay <= grading)
        sizes.iter().map(|x| x * rest / sum).collect()
    };
    let mut xs = Vec::new();
    let mut x = lo;
    let left = run(lo);
    for s in &left {
        xs.push(x);
        x -= s;
    }
    xs.push(0.0);
    xs.reverse();
    xs.pop();
    for k in 0..=n_in {
        xs.push(if k == n_in { hi } else { lo + h_in * k as f64 });
    }
    let mut x = hi;
    let right = run(len - hi);
    for (k, s) in right.iter().enumerate() {
        x += s;
        xs.push(if k + 1 == right.len() { len } else { x });
    }
    xs.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * len);
    if let Some(first) = xs.first_mut() {
        *first = 0.0;
    }
    // a sliver at either end (a run scaled far down) merges into its neighbour
    let n = xs.len();
    if n > 2 && xs[n - 1] - xs[n - 2] < 0.5 * h_in {
        xs.remove(n - 2);
    }
    if xs.len() > 2 && xs[1] - xs[0] < 0.5 * h_in {
        xs.remove(1);
    }
    xs
}

/// The number of elements [`graded_lines`] makes for these arguments, in closed form (within
/// two per run, from the sliver merges), without building a line: a size check made before the
/// lines are built (a tiny `h` asks for more lines than memory holds). Saturates at
/// `f64::INFINITY` as a float.
pub fn graded_count(len: f64, lo: f64, hi: f64, h: f64, grading: f64, coarse: f64) -> f64 {
    let (lo, hi) = (lo.clamp(0.0, len), hi.clamp(0.0, len));
    let coarse = coarse.max(h);
    let n_in = ((hi - lo) / h).round().max(f64::from(u8::from(hi > lo)));
    let h_in = if n_in > 0.0 { (hi - lo) / n_in } else { h };
    // elements of a run over `rest`: sizes h_in g^k (k = 1, 2, ...) up to `coarse`, then
    // `coarse`; the geometric sum S_j = h_in g (g^j - 1) / (g - 1)
    let run = |rest: f64| -> f64 {
        if rest <= 0.0 {
            return 0.0;
        }
        if grading <= 1.0 || h_in * grading >= coarse {
            let s = (h_in * grading).min(coarse);
            return (rest / s).ceil();
        }
        let lg = grading.ln();
        // geometric terms below the cap
        let k = ((coarse / h_in).ln() / lg).floor().max(0.0);
        let sum = |j: f64| h_in * grading * (grading.powf(j) - 1.0) / (grading - 1.0);
        if rest <= sum(k) {
            ((1.0 + rest * (grading - 1.0) / (h_in * grading)).ln() / lg).ceil()
        } else {
            k + ((rest - sum(k)) / coarse).ceil()
        }
    };
    n_in + run(lo) + run(len - hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form count against the lines built, over sizes, gradings and boxes.
    #[test]
    fn graded_count_matches_the_lines_built() {
        for &(len, lo, hi, h, g, coarse) in &[
            (11.0, 0.5, 2.5, 0.05, 1.2, 0.25),
            (4.0, 0.0, 1.0, 0.1, 1.5, 1.0),
            (21.0, 9.0, 12.0, 0.01, 1.05, 0.5),
            (21.0, 9.0, 12.0, 0.01, 1.0, 0.5),
            (10.0, 3.0, 3.5, 0.001, 2.0, 1.0),
            (10.0, 0.0, 10.0, 0.3, 1.2, 1.0),
            (100.0, 40.0, 41.0, 0.002, 1.01, 2.0),
        ] {
            let built = (graded_lines(len, lo, hi, h, g, coarse).len() - 1) as f64;
            let n = graded_count(len, lo, hi, h, g, coarse);
            assert!(
                (n - built).abs() <= 4.0,
                "{n} vs {built} for {len} {lo} {hi} {h} {g}"
            );
        }
        // a size no memory holds, counted without building a line
        assert!(graded_count(11.0, 0.5, 2.5, 1e-30, 1.0, 0.25) > 1e29);
        assert!(graded_count(11.0, 0.5, 2.5, 1e-8, 1.0, 0.25) > 1e8);
    }

    #[test]
    fn graded_lines_span_the_plate_and_grade() {
        let xs = graded_lines(11.0, 0.5, 2.5, 0.05, 1.2, 0.25);
        assert_eq!(xs[0], 0.0);
        assert_eq!(*xs.last().unwrap(), 11.0);
        let h: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(h.iter().all(|&d| d > 0.0));
        // fine in the box, at most the coarse size (+ the end scaling) outside, ratio <= 1.2 + eps
        for (w, d) in xs.windows(2).zip(&h) {
            if w[0] >= 0.5 - 1e-12 && w[1] <= 2.5 + 1e-12 {
                assert!((d - 0.05).abs() < 1e-9);
            }
            assert!(*d <= 0.25 * 1.3);
        }
        for p in h.windows(2) {
            let r = p[1] / p[0];
            assert!((1.0 / 1.2 - 1e-9..=1.2 + 1e-9).contains(&r), "ratio {r}");
        }
        // the box at an edge
        let ys = graded_lines(4.0, 0.0, 1.0, 0.1, 1.5, 1.0);
        assert_eq!(ys[0], 0.0);
        assert!((ys[10] - 1.0).abs() < 1e-12);
        assert_eq!(*ys.last().unwrap(), 4.0);
    }
}
