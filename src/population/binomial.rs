//! Fractions of a population and their binomial standard errors.
//!
//! Each of n particles has an outcome (deposition, release in a generation) independently with
//! probability p, so the count k is binomial and the fraction f = k/n estimates p with
//! standard error $\sqrt{f(1 − f)/n}$ (the normal approximation, good where nf and n(1 − f)
//! are more than a few; the studies report counts beside it).

/// f = k/n, 0 if n = 0.
pub fn fraction(k: u64, n: u64) -> f64 {
    if n == 0 { 0.0 } else { k as f64 / n as f64 }
}

/// The binomial standard error $\sqrt{f(1 − f)/n}$ of f = k/n, 0 if n = 0.
pub fn stderr(k: u64, n: u64) -> f64 {
    if n == 0 {
        0.0
    } else {
        let f = fraction(k, n);
        (f * (1.0 - f) / n as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 30 of 120: f = 1/4 and √(3/16/120) = 0.0395…; none of none is 0 with error 0.
    #[test]
    fn fraction_and_error() {
        assert_eq!(fraction(30, 120), 0.25);
        assert!((stderr(30, 120) - (0.25f64 * 0.75 / 120.0).sqrt()).abs() < 1e-17);
        assert_eq!((fraction(0, 0), stderr(0, 0)), (0.0, 0.0));
        assert_eq!(stderr(120, 120), 0.0);
    }
}
