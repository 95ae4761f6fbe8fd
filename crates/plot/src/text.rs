//! Text for SVG: escaping and fitting a label into a width (an estimate: no font metrics).

use std::borrow::Cow;

/// Average glyph width of the sans-serif font, as a fraction of the font size.
const GLYPH: f64 = 0.6;

/// `s` with the XML special characters escaped (borrowed when it has none, as labels and
/// tick values mostly do).
pub fn esc(s: &str) -> Cow<'_, str> {
    if !s.contains(['&', '<', '>', '"']) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 16);
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// `s` shortened with a middle ellipsis so that it fits `width` pixels at `font` size.
pub fn fit(s: &str, width: f64, font: f64) -> String {
    let max = (width / (GLYPH * font)).floor().max(3.0) as usize;
    let n = s.chars().count();
    if n <= max {
        return s.to_string();
    }
    let head = (max - 1) / 2;
    let tail = max - 1 - head;
    let start: String = s.chars().take(head).collect();
    let end: String = s.chars().skip(n - tail).collect();
    format!("{start}…{end}")
}

/// `s` on one line if it fits `width` pixels at `font` size, else on two, split after the comma
/// that balances them best; a second line still too long is shortened by [`fit`]. A text
/// without a comma is shortened onto one line.
pub fn wrap_two(s: &str, width: f64, font: f64) -> Vec<String> {
    let max = (width / (GLYPH * font)).floor().max(3.0) as usize;
    let n = s.chars().count();
    if n <= max {
        return vec![s.to_string()];
    }
    // Split after ", " (the separator of the panel titles' element lists).
    let best = s
        .match_indices(", ")
        .map(|(at, _)| at)
        .filter(|&at| s[..at + 1].chars().count() <= max)
        .min_by_key(|&at| {
            // Both lines fitting first, then the most even split.
            let head = s[..at + 1].chars().count();
            let tail = n - head - 1;
            (tail > max, head.abs_diff(tail))
        });
    match best {
        Some(at) => vec![s[..at + 1].to_string(), fit(&s[at + 2..], width, font)],
        None => vec![fit(s, width, font)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_labels_are_shortened() {
        assert_eq!(fit("abc", 100.0, 10.0), "abc");
        let s = fit("crank_pin.ground.F.x-and-much-more", 60.0, 10.0);
        assert_eq!(s.chars().count(), 10);
        assert!(s.starts_with("cran") && s.ends_with("more"));
        assert_eq!(esc("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn long_lists_wrap_at_a_comma() {
        assert_eq!(wrap_two("a, b", 100.0, 10.0), ["a, b"]);
        assert_eq!(
            wrap_two("aaaa, bbbb, cccc", 72.0, 10.0),
            ["aaaa,", "bbbb, cccc"]
        );
        assert_eq!(
            wrap_two("aaaa, bbbbbbbbbb", 72.0, 10.0),
            ["aaaa,", "bbbbbbbbbb"]
        );
        // No comma: one shortened line; a long tail is shortened too.
        assert_eq!(wrap_two("abcdefghijklmnop", 60.0, 10.0).len(), 1);
        let two = wrap_two("aa, bbbbbbbbbbbbbbbbbbbbbbbbbbb", 60.0, 10.0);
        assert_eq!(two[0], "aa,");
        assert!(two[1].contains('…') && two[1].chars().count() == 10);
    }
}
