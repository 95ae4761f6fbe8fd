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
}
