//! Scalars as OndselSolver reads them, and the clipped text that messages quote: the leaf that
//! the document reader (`document.rs`) and the `TimeSeries` reader (`series.rs`) share.
//!
//! A number field is a decimal with an optional exponent written `e` or, in the Smalltalk
//! tradition of the format, `d` (`1.0d-3`, `2.0d`); it must be finite.

use crate::error::{AsmtError, Result};

/// At most 60 characters of `s`, for messages.
pub(crate) fn clip(s: &str) -> String {
    if s.chars().count() <= 60 {
        s.to_string()
    } else {
        format!("{}…", s.chars().take(60).collect::<String>())
    }
}

/// A scalar as OndselSolver reads it, also with the Smalltalk `d` exponent (`1.0d-3`); must be
/// finite.
pub(crate) fn number(text: &str, line: usize, what: &str) -> Result<f64> {
    let t = text.trim();
    let fixed: String;
    let t = match t.find(['d', 'D']) {
        Some(k)
            if t[..k]
                .chars()
                .all(|c| c.is_ascii_digit() || "+-.".contains(c)) =>
        {
            fixed = if k + 1 == t.len() {
                t[..k].to_string()
            } else {
                format!("{}e{}", &t[..k], &t[k + 1..])
            };
            fixed.as_str()
        }
        _ => t,
    };
    let v: f64 = t.parse().map_err(|_| {
        AsmtError::new(
            line,
            format!("{what}: \"{}\" is not a number", clip(text.trim())),
        )
    })?;
    if !v.is_finite() {
        return Err(AsmtError::new(
            line,
            format!("{what}: \"{}\" is not a finite number", clip(text.trim())),
        ));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smalltalk_numbers() {
        assert_eq!(number("1.0d-3", 1, "x").unwrap(), 1e-3);
        assert_eq!(number("2.0d", 1, "x").unwrap(), 2.0);
        assert_eq!(number("1.0e-9", 1, "x").unwrap(), 1e-9);
        assert_eq!(number("0.0 ", 1, "x").unwrap(), 0.0);
        assert!(number("NaN", 3, "x")
            .unwrap_err()
            .message
            .contains("finite"));
        assert!(number("inf", 3, "x").is_err());
        assert!(number("1.2.3", 3, "x").is_err());
    }
}
