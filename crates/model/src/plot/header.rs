//! What a column header says about how to plot it.
//!
//! Headers read `element[.more].quantity[.component] [unit]`: `crank_pin.ground.F.x [N]`
//! (a reaction on body `ground` at joint `crank_pin`), `crank.B.x [m]` (point B of body
//! `crank`), `crank.p.e0 [-]`, `crank_pin.angle [rad]`, `kinetic [J]`.

/// Vector components: the last segment of a header that is one of these is drawn with the dash
/// of its index (x solid, y dashed, z dotted; e0..e3 likewise).
const COMPONENTS: [[&str; 4]; 2] = [["x", "y", "z", ""], ["e0", "e1", "e2", "e3"]];

/// A parsed column header: slices of the header's text (a large model's tables have 10⁵
/// columns, each parsed for the plots).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header<'a> {
    /// The name without the unit, e.g. `crank_pin.ground.F.x`.
    pub label: &'a str,
    /// The unit inside the trailing brackets (empty without brackets), e.g. `N m`.
    pub unit: &'a str,
    /// The first segment: the joint, body or quantity the column belongs to.
    pub element: &'a str,
    /// What keeps one colour across panels: the body of a reaction (the second segment when
    /// there are at least three besides the component), else the element.
    pub colour_key: &'a str,
    /// The dash index of the component (0 without one).
    pub dash: usize,
}

impl<'a> Header<'a> {
    /// Parses a header; any text is accepted.
    pub fn parse(text: &'a str) -> Self {
        let (label, unit) = split_unit(text);
        let mut segs = label.split('.');
        let element = segs.next().unwrap_or_default();
        let second = segs.next();
        let last = label.rsplit('.').next().unwrap_or_default();
        let count = label.matches('.').count() + 1;
        let dash = component(last, count);
        // Segments besides the component.
        let kept = count - usize::from(dash.is_some());
        let colour_key = match second {
            Some(s) if kept >= 3 => s,
            _ => element,
        };
        Self {
            label,
            unit,
            element,
            colour_key,
            dash: dash.unwrap_or(0),
        }
    }
}

/// `name [unit]` split into its name and unit; without brackets the unit is empty.
fn split_unit(text: &str) -> (&str, &str) {
    let t = text.trim();
    if let (Some(open), true) = (t.rfind('['), t.ends_with(']')) {
        return (t[..open].trim_end(), &t[open + 1..t.len() - 1]);
    }
    (t, "")
}

/// The dash index of the last of `count` segments when it is a vector component (and not the
/// only segment).
fn component(last: &str, count: usize) -> Option<usize> {
    if count < 2 || last.is_empty() {
        return None;
    }
    COMPONENTS
        .iter()
        .find_map(|set| set.iter().position(|c| *c == last))
}

/// The y label of a panel of `unit`: the quantity it measures and the unit, e.g. `force [N]`.
pub fn y_label(unit: &str) -> String {
    let quantity = match unit {
        "N" => "force",
        "N m" | "N mm" => "torque",
        "m" | "mm" => "length",
        "rad" => "angle",
        "m/s" | "mm/s" => "velocity",
        "rad/s" => "angular velocity",
        "m/s²" | "mm/s²" => "acceleration",
        "rad/s²" => "angular acceleration",
        "J" | "mJ" => "energy",
        "W" | "mW" => "power",
        "-" => "dimensionless",
        _ => "",
    };
    match (quantity, unit) {
        (_, "") => "value".into(),
        ("", u) => format!("[{u}]"),
        (q, u) => format!("{q} [{u}]"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_name_unit_element_colour_and_dash() {
        let h = Header::parse("crank_pin.ground.T.z [N m]");
        assert_eq!((h.label, h.unit), ("crank_pin.ground.T.z", "N m"));
        assert_eq!(
            (h.element, h.colour_key, h.dash),
            ("crank_pin", "ground", 2)
        );
        // (header, element, colour key, dash). A component needs a segment before it; three
        // segments besides the component name the body as the colour key.
        for (text, element, colour, dash) in [
            ("crank.p.e3 [-]", "crank", "crank", 3),
            ("slide.slide [m]", "slide", "slide", 0),
            ("x", "x", "x", 0),
            ("b.x [m]", "b", "b", 0),
            ("j.b.F [N]", "j", "b", 0),
            ("j.b.y [m]", "j", "j", 1),
            ("a..z [m]", "a", "a", 2),
            ("a.b. [m]", "a", "b", 0),
        ] {
            let h = Header::parse(text);
            assert_eq!(
                (h.element, h.colour_key, h.dash),
                (element, colour, dash),
                "{text}"
            );
        }
        assert_eq!(Header::parse("x").unit, "");
        assert_eq!(Header::parse("").element, "");
        assert_eq!(Header::parse("a.b [").unit, "");
    }

    #[test]
    fn y_labels_carry_the_unit() {
        assert_eq!(y_label("N m"), "torque [N m]");
        // energy.csv's power columns (issue 46: the panel read "[W]").
        assert_eq!(y_label("W"), "power [W]");
        assert_eq!(y_label("mW"), "power [mW]");
        assert_eq!(y_label("kg"), "[kg]");
        assert_eq!(y_label(""), "value");
    }
}
