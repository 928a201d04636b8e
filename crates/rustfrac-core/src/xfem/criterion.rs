//! The maximum circumferential stress criterion (Erdogan and Sih; paper section 2.1.3): the kink
//! angle of a tip and its equivalent mode I SIF, read by the growth loop ([`super::growth`]) and
//! the direction rules ([`super::kink`]).

/// Kink angle of the maximum circumferential stress criterion (Erdogan and Sih), in the tip frame:
/// theta_c = 2 atan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], written in the cancellation-free
/// form 2 atan[-2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2))]; 0 when K_II = 0. A positive K_II turns
/// the crack clockwise (negative angle).
pub fn kink_angle(k_i: f64, k_ii: f64) -> f64 {
    if k_ii == 0.0 {
        return 0.0;
    }
    // K_II != 0 makes the root exceed |K_I|, so the denominator is positive
    let s = (k_i * k_i + 8.0 * k_ii * k_ii).sqrt();
    2.0 * (-2.0 * k_ii / (k_i + s)).atan()
}

/// Equivalent mode I SIF in the kink direction:
/// K_eq = cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)].
pub fn k_equivalent(k_i: f64, k_ii: f64) -> f64 {
    let t = kink_angle(k_i, k_ii);
    let c = (0.5 * t).cos();
    c * (k_i * c * c - 1.5 * k_ii * t.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn criterion_limits() {
        assert_eq!(kink_angle(1.0, 0.0), 0.0);
        assert!((k_equivalent(2.0, 0.0) - 2.0).abs() < 1e-15);
        // pure mode II: theta = -2 atan(1/sqrt 2) = -70.53 deg
        let t = kink_angle(0.0, 1.0);
        assert!(
            (t.to_degrees() + 70.528_779).abs() < 1e-5,
            "{}",
            t.to_degrees()
        );
        // K_IIc = (sqrt 3 / 2) K_Ic
        assert!((k_equivalent(0.0, 1.0) - 2.0 / 3f64.sqrt()).abs() < 1e-12);
        assert!(kink_angle(1.0, -0.3) > 0.0);
    }
}
