//! Shared test helpers: proptest strategies and independent reference computations.
#![allow(dead_code)] // each test crate uses a different subset

pub mod reference;
pub mod strategies;

/// `x` rounded to `digits` significant digits, as text: stable across machines for snapshots.
pub fn sig(x: f64, digits: i32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let decimals = (digits - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.starts_with("-") && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}
