//! `index.html`: one self-contained page that works offline from `file://`.
//!
//! Its scripts, in order: the error recorder (`window.onerror`, `unhandledrejection` and a
//! `console.error` wrapper write into `#errors`), three.js 0.160.1 as a classic script
//! ([`classic_three`]), the data (the `.glb` in base64 and a small JSON of what the `.glb` does
//! not hold: named points, joint axes, the view's centre and size), then the viewer
//! (`viewer.js`): it reads the `.glb` itself (nodes, meshes with POSITION, NORMAL and indices,
//! materials, the animation's channels), so the page shows exactly the file. Below the view:
//! the plots (the SVGs inline) and the run summary (run.json as a table).
//!
//! `?t=<seconds>` sets the time and pauses; the body gets `data-ready="1"` after the first
//! frame is drawn (for screenshot tests). In a browser without WebGL the viewer shows one
//! sentence (`#no-webgl`: "3D view needs WebGL; the plots below work without it") instead of
//! the 3D view and three.js's errors, and the timeline, plots and summary work as before.
//!
//! A run with end stops ([`Page::stops`], `stops.rs`) adds their data to the JSON, their
//! style (`stops.css`) and their script (`stops.js`: the rings, the list of stops, the ticks
//! of the impacts on the timeline) before the viewer, which calls it from the lines of
//! `viewer.js` tagged `// [stops]`. A page without stops leaves all of that out, those lines
//! too, so its text is exactly that of a page written before stops were drawn.

use crate::base64::encode_into;
use crate::modes::{modes_json, validate_modes, ModeShape, MAX_ANIMATED_MODES};
use crate::rotate::rotate;
use crate::scene::Scene;
use crate::stops::{stops_json, validate_stops, StopEvent, StopMarker};
use std::fmt::Write as _;
use std::sync::OnceLock;

/// three.js 0.160.1, `build/three.module.min.js` of the npm package (vendor/three-0.160.1), as
/// a classic script (converted by `build.rs`).
const THREE_CLASSIC: &str = include_str!(concat!(env!("OUT_DIR"), "/three.classic.js"));
/// The page's own script.
const VIEWER: &str = include_str!("viewer.js");
/// The page's style.
const STYLE: &str = include_str!("viewer.css");
/// The end stops' script and style (only in a page with stops).
const STOPS_SCRIPT: &str = include_str!("stops.js");
const STOPS_STYLE: &str = include_str!("stops.css");
/// The tag of the lines of `viewer.js` that call `stops.js`.
const STOPS_TAG: &str = "// [stops]";

/// `viewer.js` for a page with stops (as written) or without (the lines tagged
/// [`STOPS_TAG`] left out, once).
fn viewer(with_stops: bool) -> &'static str {
    static PLAIN: OnceLock<String> = OnceLock::new();
    if with_stops {
        return VIEWER;
    }
    PLAIN.get_or_init(|| {
        VIEWER
            .split_inclusive('\n')
            .filter(|line| !line.trim_end().ends_with(STOPS_TAG))
            .collect()
    })
}

/// What the page shows besides the scene.
#[derive(Debug, Clone, Default)]
pub struct Page {
    /// Plots: (name, SVG text), shown in this order.
    pub plots: Vec<(String, String)>,
    /// The run summary (run.json), shown as a table.
    pub summary: Option<serde_json::Value>,
    /// The direction drawn upwards (e.g. against gravity); +z if zero.
    pub up: [f64; 3],
    /// A modal run's modes: the page animates them about the scene's first pose (a mode
    /// selector and an amplitude slider replace the time slider). Empty for other runs.
    pub modes: Vec<ModeShape>,
    /// A run's end stops: a marker at each stop's joint in the frames it is active in
    /// (`stops.rs`). Empty for a model without limits (the page is then as without them).
    pub stops: Vec<StopMarker>,
    /// The impacts and releases of the stops, ticks on the timeline.
    pub stop_events: Vec<StopEvent>,
}

/// three.js as a classic script (`src/classic.rs` applied to the vendored module), made
/// once when the crate is built (`build.rs`, which fails if the module is not of the expected
/// form): converting the 700 kB module took a quarter of a small model's whole `cardan run`.
pub fn classic_three() -> &'static str {
    THREE_CLASSIC
}

/// The text of a page in three parts, three.js (a constant of 0.67 MB) in the middle: written
/// to its file part by part, the page is never copied into one string (the copy and the fresh
/// memory for it cost a small model's run a few percent).
#[derive(Debug, Clone, Default)]
pub struct Html {
    head: String,
    three: &'static str,
    tail: String,
}

impl Html {
    /// The parts, in order.
    pub fn parts(&self) -> [&str; 3] {
        [&self.head, self.three, &self.tail]
    }

    /// Its length in bytes.
    pub fn len(&self) -> usize {
        self.parts().iter().map(|p| p.len()).sum()
    }

    /// Whether it is empty (the default).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl std::fmt::Display for Html {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.parts().iter().try_for_each(|p| f.write_str(p))
    }
}

/// The page for `scene` whose animation is `glb`.
///
/// # Errors
/// [`crate::Error::Scene`] if the modes do not fit the scene ([`validate_modes`]).
pub fn write_html(scene: &Scene, glb: &[u8], page: &Page) -> Result<Html, crate::Error> {
    validate_modes(scene, &page.modes)?;
    validate_stops(scene, &page.stops, &page.stop_events)?;
    let with_stops = !page.stops.is_empty();
    let stops_style = if with_stops { STOPS_STYLE } else { "" };
    let mut html =
        String::with_capacity(page.plots.iter().map(|p| p.1.len()).sum::<usize>() + 20_000);
    let title = escape(&scene.name);
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>{title} — cardan</title><style>{STYLE}{stops_style}</style>\n\
         <script>{RECORDER}</script>\n</head><body>\n\
         <header><h1>{title}</h1><ul id=\"errors\" hidden></ul></header>\n"
    );
    let (controls, end) = CONTROLS.rsplit_once("</section>").unwrap_or((CONTROLS, ""));
    html.push_str(controls);
    if !page.modes.is_empty() {
        mode_controls(&page.modes, &mut html);
    }
    html.push_str("</section>");
    html.push_str(end);
    html.push_str("<section id=\"plots\">");
    plots_html(&page.plots, &mut html);
    html.push_str("</section>\n<section id=\"summary\">");
    summary_html(page.summary.as_ref(), &mut html);
    html.push_str("</section>\n<script>");
    let head = std::mem::replace(&mut html, String::with_capacity(glb.len() * 4 / 3 + 50_000));
    html.push_str("</script>\n<script id=\"glb\" type=\"application/octet-stream\">");
    encode_into(glb, &mut html);
    html.push_str("</script>\n<script id=\"meta\" type=\"application/json\">");
    html.push_str(&script_safe(&page_meta(scene, page).to_string()));
    html.push_str("</script>\n<script>");
    if with_stops {
        html.push_str(STOPS_SCRIPT);
        html.push_str("</script>\n<script>");
    }
    html.push_str(viewer(with_stops));
    html.push_str("</script>\n</body></html>\n");
    Ok(Html {
        head,
        three: classic_three(),
        tail: html,
    })
}

/// The data of a new solve for a page already open (the live preview, `cardan watch`): a JSON
/// object with the `.glb` in base64 (`glb`), the viewer's data (`meta`) and the inner HTML of
/// the plots and summary sections (`plots`, `summary`), which the viewer's `replace` shows in
/// place of the old model without loading a page. `meta.replaceable` is false for a modal run
/// or a run with end stops (their controls are part of the page; the host loads the new page).
///
/// # Errors
/// As [`write_html`].
pub fn write_update(scene: &Scene, glb: &[u8], page: &Page) -> Result<String, crate::Error> {
    validate_modes(scene, &page.modes)?;
    validate_stops(scene, &page.stops, &page.stop_events)?;
    let mut glb64 = String::with_capacity(glb.len() * 4 / 3 + 4);
    encode_into(glb, &mut glb64);
    let (mut plots, mut summary) = (String::new(), String::new());
    plots_html(&page.plots, &mut plots);
    summary_html(page.summary.as_ref(), &mut summary);
    let update = serde_json::json!({
        "glb": glb64,
        "meta": page_meta(scene, page),
        "plots": plots,
        "summary": summary,
    });
    Ok(update.to_string())
}

/// The page's JSON data: [`meta`], the modes and the stops, and whether the viewer can show a
/// new solve in place (`replaceable`).
fn page_meta(scene: &Scene, page: &Page) -> serde_json::Value {
    let mut meta = meta(scene, page.up);
    if !page.modes.is_empty() {
        meta["modes"] = modes_json(scene, &page.modes);
    }
    if !page.stops.is_empty() {
        meta["stops"] = stops_json(&page.stops, &page.stop_events);
    }
    meta["replaceable"] = serde_json::Value::Bool(page.modes.is_empty() && page.stops.is_empty());
    meta
}

/// The plots section's content: its heading and a figure per plot (the SVG inline).
fn plots_html(plots: &[(String, String)], html: &mut String) {
    html.push_str("<h2>Plots</h2>\n");
    for (name, svg) in plots {
        let svg = svg.trim_start();
        let svg = match svg.strip_prefix("<?xml") {
            Some(rest) => rest.split_once("?>").map_or(rest, |(_, s)| s),
            None => svg,
        };
        let _ = writeln!(
            html,
            "<figure><figcaption>{}</figcaption>{svg}</figure>",
            escape(name)
        );
    }
}

/// The summary section's content: its heading and the run summary as a table.
fn summary_html(summary: Option<&serde_json::Value>, html: &mut String) {
    html.push_str("<h2>Run summary</h2>\n");
    if let Some(s) = summary {
        summary_table(s, html);
    }
}

/// Records errors into `#errors` from the very start (before three.js runs).
const RECORDER: &str = r#"(function(){
var list=[],shown=0;window.__cardanErrors=list;
function show(){var e=document.getElementById('errors');if(!e)return;
for(;shown<list.length;shown++){var li=document.createElement('li');li.textContent=list[shown];e.appendChild(li);e.hidden=false;}}
function add(m){list.push(String(m));show();}
window.__cardanError=add;
window.onerror=function(msg,src,line,col){add('error: '+msg+' ('+src+':'+line+':'+col+')');};
window.addEventListener('unhandledrejection',function(ev){add('unhandled rejection: '+ev.reason);});
var ce=console.error;console.error=function(){add('console.error: '+Array.prototype.join.call(arguments,' '));return ce.apply(console,arguments);};
document.addEventListener('DOMContentLoaded',show);
})();"#;

/// The 3D view and its controls.
const CONTROLS: &str = r#"<section id="viewer">
<div id="view"><canvas id="canvas"></canvas></div>
<div id="controls">
<button id="play" type="button">pause</button>
<input id="scrub" type="range" min="0" max="1" step="any" value="0" aria-label="time">
<span id="time">t = 0 s</span>
<label>speed <select id="speed"><option>0.1</option><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option><option>4</option></select></label>
<label><input id="frames" type="checkbox"> body frames</label>
<label><input id="axes" type="checkbox"> joint axes</label>
</div>
<details id="trails-box"><summary>trails of points</summary><div id="trails"></div></details>
<p class="hint">drag: rotate · wheel: zoom · right-drag or shift-drag: pan</p>
</section>
"#;

/// A modal run's controls: the mode list (number, frequency, damping ratio; "rigid"), the
/// amplitude slider (a factor on the default amplitude), a note when not every mode is
/// animated, and `#mode-poses` (filled for scripts when the page is opened at a phase, `?tau=`).
fn mode_controls(modes: &[ModeShape], html: &mut String) {
    html.push_str(
        "<div id=\"mode-controls\">\n<label>mode <select id=\"mode\" aria-label=\"mode\">",
    );
    for (i, m) in modes.iter().take(MAX_ANIMATED_MODES).enumerate() {
        let _ = write!(
            html,
            "<option value=\"{i}\">{}</option>",
            escape(&m.label())
        );
    }
    html.push_str(
        "</select></label>\n<label>amplitude <input id=\"amplitude\" type=\"range\" \
         min=\"0\" max=\"5\" step=\"0.05\" value=\"1\" aria-label=\"amplitude\"></label>\n\
         <span id=\"amplitude-value\"></span>\n",
    );
    if modes.len() > MAX_ANIMATED_MODES {
        let _ = writeln!(
            html,
            "<span class=\"hint\">the lowest {MAX_ANIMATED_MODES} of {} modes are animated; \
             mode_shapes.csv holds all</span>",
            modes.len()
        );
    }
    html.push_str("<output id=\"mode-poses\" hidden></output>\n</div>\n");
}

/// What the viewer needs beyond the `.glb`: points and axes per body, the view's centre,
/// size and up direction.
fn meta(scene: &Scene, up: [f64; 3]) -> serde_json::Value {
    let (centre, size) = bounds(scene);
    let up = if up.iter().all(|x| *x == 0.0) {
        [0.0, 0.0, 1.0]
    } else {
        up
    };
    serde_json::json!({
        "name": scene.name,
        "centre": centre,
        "size": size.max(scene.extent).max(1e-9),
        "extent": scene.extent,
        "up": up,
        "bodies": scene.bodies.iter().map(|b| serde_json::json!({
            "name": b.name,
            "points": b.points.iter().map(|p| serde_json::json!({"name": p.name, "local": p.local})).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "axes": scene.axes.iter().map(|a| serde_json::json!({
            "name": a.name, "body": a.body, "point": a.point, "direction": a.direction,
        })).collect::<Vec<_>>(),
    })
}

/// Centre and diagonal of the box around every body origin and named point over the run
/// (a fixed body: its points).
fn bounds(scene: &Scene) -> ([f64; 3], f64) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut add = |p: [f64; 3]| {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    };
    for b in &scene.bodies {
        if !b.moves() {
            b.points.iter().for_each(|p| add(p.local));
            continue;
        }
        for (r, q) in b.positions.iter().zip(&b.rotations) {
            add(*r);
            for p in &b.points {
                add(rotate(q, p.local, r));
            }
        }
    }
    if lo[0] > hi[0] {
        return ([0.0; 3], 1.0);
    }
    let centre = [0, 1, 2].map(|c| (lo[c] + hi[c]) / 2.0);
    let size = (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt();
    (centre, size)
}

/// The run summary as a two-column table (nested values as compact JSON).
fn summary_table(v: &serde_json::Value, html: &mut String) {
    html.push_str("<table>");
    if let Some(map) = v.as_object() {
        for (k, val) in map {
            let shown = match val {
                serde_json::Value::String(s) => s.clone(),
                serde_json::Value::Array(a) if a.iter().all(|x| x.is_string()) => a
                    .iter()
                    .filter_map(|x| x.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                serde_json::Value::Null => "—".into(),
                other => other.to_string(),
            };
            let _ = write!(
                html,
                "<tr><th>{}</th><td>{}</td></tr>",
                escape(&k.replace('_', " ")),
                escape(&shown)
            );
        }
    }
    html.push_str("</table>\n");
}

/// Text for HTML content and attributes.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// JSON safe inside a script element (`<` as its JSON escape).
fn script_safe(json: &str) -> String {
    json.replace('<', "\\u003c")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_becomes_a_classic_script_exporting_its_names() {
        let c = classic_three();
        assert!(c.starts_with("(function(){\"use strict\";"));
        assert!(c.contains("window.THREE={"));
        for name in [
            "WebGLRenderer:",
            "PerspectiveCamera:",
            "Quaternion:",
            "BufferGeometry:",
        ] {
            assert!(c.contains(name), "{name}");
        }
        assert!(!c.contains("export{"));
        assert!(!c.to_ascii_lowercase().contains("</script"));
    }

    #[test]
    fn a_page_without_stops_has_the_viewer_without_its_stop_lines() {
        let tagged = VIEWER.lines().filter(|l| l.ends_with(STOPS_TAG)).count();
        assert_eq!(tagged, 3);
        let plain = viewer(false);
        assert_eq!(plain.lines().count(), VIEWER.lines().count() - tagged);
        assert!(!plain.contains("stops") && !plain.contains("cardanStops"));
        assert!(viewer(true).contains("window.cardanStops"));
        let scene = Scene {
            times: vec![0.0],
            ..Scene::default()
        };
        let page = write_html(&scene, &[], &Page::default())
            .unwrap()
            .to_string();
        assert!(!page.contains("cardanStops") && !page.contains("stop-ticks"));
        assert!(page.contains(viewer(false)));
    }

    #[test]
    fn modules_of_another_form_are_refused() {
        assert_eq!(crate::classic::to_classic("const a=1;"), None);
        assert_eq!(
            crate::classic::to_classic("export{a as A};const b=2;export{b as B};"),
            None
        );
        assert_eq!(
            crate::classic::to_classic("const a=\"</script>\";export{a as A};"),
            None
        );
        assert_eq!(
            crate::classic::to_classic("const a=1;export{a as A,a};").as_deref(),
            Some("(function(){\"use strict\";\nconst a=1;\nwindow.THREE={A:a,a:a};\n})();")
        );
    }
}
