//! Tokens of an expression, each with its byte span in the text.
//!
//! Numbers are `digits [. digits] [(e|E) [+|-] digits]` (also `.5`); a name is a letter or `_`
//! followed by letters, digits and `_`. Whitespace separates tokens and is otherwise ignored.
//! Other number syntaxes (e.g. the Smalltalk `1.0d-3` of ASMT files) belong in [`number`].

use super::ParseError;
use std::ops::Range;

/// One token.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Tok {
    Num(f64),
    Name(String),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    LBracket,
    RBracket,
    Comma,
    End,
}

impl Tok {
    /// How the token reads in a message.
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Num(x) => format!("the number {x}"),
            Tok::Name(n) => format!("\"{n}\""),
            Tok::End => "the end of the expression".into(),
            Tok::Plus => "\"+\"".into(),
            Tok::Minus => "\"-\"".into(),
            Tok::Star => "\"*\"".into(),
            Tok::Slash => "\"/\"".into(),
            Tok::Caret => "\"^\"".into(),
            Tok::LParen => "\"(\"".into(),
            Tok::RParen => "\")\"".into(),
            Tok::LBracket => "\"[\"".into(),
            Tok::RBracket => "\"]\"".into(),
            Tok::Comma => "\",\"".into(),
        }
    }
}

/// The tokens of `text`, ending with [`Tok::End`] (spanning the end of the text).
pub(crate) fn tokens(text: &str) -> Result<Vec<(Tok, Range<usize>)>, ParseError> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let c = b[k];
        let start = k;
        let single = match c {
            b'+' => Some(Tok::Plus),
            b'-' => Some(Tok::Minus),
            b'*' => Some(Tok::Star),
            b'/' => Some(Tok::Slash),
            b'^' => Some(Tok::Caret),
            b'(' => Some(Tok::LParen),
            b')' => Some(Tok::RParen),
            b'[' => Some(Tok::LBracket),
            b']' => Some(Tok::RBracket),
            b',' => Some(Tok::Comma),
            _ => None,
        };
        if let Some(t) = single {
            out.push((t, start..start + 1));
            k += 1;
        } else if c.is_ascii_whitespace() {
            k += 1;
        } else if c.is_ascii_digit() || c == b'.' {
            let (x, end) = number(text, start)?;
            out.push((Tok::Num(x), start..end));
            k = end;
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while k < b.len() && (b[k].is_ascii_alphanumeric() || b[k] == b'_') {
                k += 1;
            }
            out.push((Tok::Name(text[start..k].to_string()), start..k));
        } else {
            let ch = text[start..].chars().next().unwrap_or('?');
            let end = start + ch.len_utf8();
            let hint = if ch == '*' || ch == '×' || ch == '·' {
                "; write * for a product"
            } else {
                ""
            };
            return Err(ParseError::new(
                start..end,
                format!("unexpected character \"{ch}\"{hint}"),
            ));
        }
    }
    out.push((Tok::End, b.len()..b.len()));
    Ok(out)
}

/// A number starting at byte `start`; returns its value and end.
fn number(text: &str, start: usize) -> Result<(f64, usize), ParseError> {
    let b = text.as_bytes();
    let digits = |mut k: usize| {
        while k < b.len() && b[k].is_ascii_digit() {
            k += 1;
        }
        k
    };
    let mut k = digits(start);
    let int_digits = k - start;
    let mut frac_digits = 0;
    if k < b.len() && b[k] == b'.' {
        let f = digits(k + 1);
        frac_digits = f - k - 1;
        k = f;
    }
    if int_digits + frac_digits == 0 {
        return Err(ParseError::new(
            start..start + 1,
            "a number needs digits (\".\" alone is not a number)",
        ));
    }
    if k < b.len() && (b[k] == b'e' || b[k] == b'E') {
        let mut e = k + 1;
        if e < b.len() && (b[e] == b'+' || b[e] == b'-') {
            e += 1;
        }
        let end = digits(e);
        if end == e {
            // "2e" or "2ex": read "2" and let the parser reject what follows ("e" is Euler's
            // number, so "2e" is a missing operator, not a malformed exponent).
            if e == k + 1 {
                return Ok((parse_f64(text, start, k)?, k));
            }
            return Err(ParseError::new(
                start..e,
                "the exponent of this number has no digits",
            ));
        }
        k = end;
    }
    Ok((parse_f64(text, start, k)?, k))
}

fn parse_f64(text: &str, start: usize, end: usize) -> Result<f64, ParseError> {
    let x: f64 = text[start..end]
        .parse()
        .map_err(|_| ParseError::new(start..end, "not a number"))?;
    if !x.is_finite() {
        return Err(ParseError::new(
            start..end,
            format!(
                "the number {} is beyond the range of f64",
                &text[start..end]
            ),
        ));
    }
    Ok(x)
}
