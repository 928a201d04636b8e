//! Numbers in messages: a derived value (0.7 x a width, a computed length) printed with at most
//! ten significant digits, so a message says `7.7`, not `7.699999999999999`. Values the user
//! wrote print as written without it (Rust's shortest round-trip form).

/// `x` with at most 10 significant digits, trailing zeros dropped: `short(0.7 * 11.0)` is
/// `"7.7"`, `short(1e-12)` is `"1e-12"`, `short(f64::NAN)` is `"NaN"`.
pub fn short(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    // round to 10 significant digits through the exponent form, then print shortest
    let rounded: f64 = format!("{x:.9e}").parse().unwrap_or(x);
    format!("{rounded}")
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn derived_values_print_short() {
        assert_eq!(short(0.7 * 11.0), "7.7");
        assert_eq!(format!("{}", 0.7 * 11.0), "7.699999999999999"); // what it replaces
        assert_eq!(short(0.1 + 0.2), "0.3");
        assert_eq!(short(10.5), "10.5");
        assert_eq!(short(-2.5e-7), "-0.00000025");
        assert_eq!(short(1.0 / 3.0), "0.3333333333");
        assert_eq!(short(f64::NAN), "NaN");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(123456789012.0), "123456789000");
    }
}
