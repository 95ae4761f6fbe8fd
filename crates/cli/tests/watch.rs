//! `cardan watch` in a real browser (issue 52): headless Chromium, driven through the DevTools
//! protocol, opens the preview; the test edits the model file and sees the report (scene and
//! plots) change, measuring the save-to-updated-page time; moves a slider and sees a new
//! solution with the `--set` arguments that reproduce it; writes a broken file and sees the
//! error with its line; fixes it, deletes it, replaces it by a directory and restores it, the
//! preview following each time; then Ctrl-C ends the command. The server refuses other hosts
//! and origins and listens on the loopback interface only. A saved edit is shown in place by
//! the report's viewer (the bodies' poses at a paused time change, no page load). A second
//! preview drags a hinged rod with the mouse (Ctrl held): it turns about its hinge toward the
//! pointer and stops at its end stop.

mod common;
use common::{chromium, scratch};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use tungstenite::Message;

/// Kills the child processes when the test ends, passing or failing.
struct Kill(Vec<Child>);

impl Drop for Kill {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// A DevTools session on one page.
struct Page {
    socket: tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<TcpStream>>,
    session: String,
    id: u64,
}

impl Page {
    fn call(
        &mut self,
        method: &str,
        params: serde_json::Value,
        session: bool,
    ) -> serde_json::Value {
        self.id += 1;
        let mut msg = serde_json::json!({"id": self.id, "method": method, "params": params});
        if session {
            msg["sessionId"] = self.session.clone().into();
        }
        self.socket
            .send(Message::Text(msg.to_string().into()))
            .unwrap();
        loop {
            if let Message::Text(t) = self.socket.read().unwrap() {
                let v: serde_json::Value = serde_json::from_str(&t).unwrap();
                if v["id"] == self.id {
                    assert!(v.get("error").is_none(), "{method}: {v}");
                    return v["result"].clone();
                }
            }
        }
    }

    /// The value of a JavaScript expression in the page.
    fn eval(&mut self, js: &str) -> serde_json::Value {
        let r = self.call(
            "Runtime.evaluate",
            serde_json::json!({"expression": js, "returnByValue": true}),
            true,
        );
        r["result"]["value"].clone()
    }

    /// Waits (at most 20 s) until `js` is true; returns the time it took.
    fn wait(&mut self, js: &str, what: &str) -> Duration {
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(20) {
            if self.eval(js) == serde_json::Value::Bool(true) {
                return start.elapsed();
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let state = self.eval("document.body.dataset.version + ' ' + document.body.dataset.loaded + ' ' + document.getElementById('error').textContent + ' ' + document.getElementById('drag').textContent");
        panic!("timed out waiting for {what} ({js}); page: {state}");
    }
}

/// The report's digest: its body's length and a hash of it (plots are inline SVG).
const DIGEST: &str = "(() => { const d = document.getElementById('report').contentDocument; \
    if (!d || !d.body) return ''; const s = d.body.innerHTML; let h = 0; \
    for (let i = 0; i < s.length; i++) h = (h * 31 + s.charCodeAt(i)) | 0; return s.length + ':' + h; })()";

/// The report's viewer paused at t = 0.25 s.
const PAUSE: &str = "(() => { const d = document.getElementById('report').contentDocument; \
    const s = d.getElementById('scrub'); s.value = 0.25; s.dispatchEvent(new Event('input')); \
    return true; })()";

/// The poses of the bodies as the viewer draws them.
const POSES: &str =
    "(() => { const v = document.getElementById('report').contentWindow.cardanReport; \
    return JSON.stringify(v.bodies().map((_, i) => v.pose(i))); })()";

/// How many solves the viewer showed in place, its time and the errors it recorded.
const VIEWER_STATE: &str = "(() => { const w = document.getElementById('report').contentWindow; \
    return [w.cardanReport.replaced, w.cardanReport.time(), JSON.stringify(w.__cardanErrors)]; })()";

fn loaded_at(v: u64) -> String {
    format!("document.body.dataset.loaded === '{v}'")
}

fn version(page: &mut Page) -> u64 {
    page.eval("Number(document.body.dataset.version || 0)")
        .as_u64()
        .unwrap()
}

/// An HTTP request's status line.
fn status(port: u16, host: &str, origin: Option<&str>) -> String {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    let origin = origin
        .map(|o| format!("Origin: {o}\r\n"))
        .unwrap_or_default();
    write!(
        s,
        "GET / HTTP/1.1\r\nHost: {host}\r\n{origin}Connection: close\r\n\r\n"
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    out.lines().next().unwrap_or("").to_string()
}

/// A preview of a copy of an example, open in headless Chromium.
struct Preview {
    page: Page,
    children: Kill,
    /// The model file watched.
    model: PathBuf,
    /// The example's text.
    original: String,
}

/// Starts `cardan watch` on a copy of `example` in a scratch directory `name` and opens its
/// page in headless Chromium (None without Chromium). The server's host and origin checks and
/// its loopback-only listening are tested on the way.
fn open(example: &str, name: &str) -> Option<Preview> {
    let chromium = chromium()?;
    let (model, port, mut children) = serve(example, name);
    let original = std::fs::read_to_string(&model).unwrap();
    let dir = model.parent().unwrap().to_path_buf();
    let url = format!("http://127.0.0.1:{port}/");

    // Only this server's host and origin are answered.
    assert!(status(port, &format!("127.0.0.1:{port}"), None).contains("200"));
    assert!(status(port, "evil.example", None).contains("403"));
    assert!(status(
        port,
        &format!("127.0.0.1:{port}"),
        Some("http://evil.example")
    )
    .contains("403"));
    // Not on another interface.
    let other = std::net::UdpSocket::bind("0.0.0.0:0")
        .and_then(|u| u.connect("10.255.255.255:9").and_then(|()| u.local_addr()));
    if let Ok(addr) = other {
        if !addr.ip().is_loopback() && !addr.ip().is_unspecified() {
            let to = std::net::SocketAddr::new(addr.ip(), port);
            assert!(
                TcpStream::connect_timeout(&to, Duration::from_secs(1)).is_err(),
                "{to} answered"
            );
        }
    }

    let profile = dir.join("profile");
    let mut browser = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--remote-debugging-port=0",
            "--window-size=1000,700",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(&url)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = BufReader::new(browser.stderr.take().unwrap());
    children.0.push(browser);
    let ws = stderr
        .lines()
        .map_while(Result::ok)
        .find_map(|l| {
            l.split_once("DevTools listening on ")
                .map(|(_, u)| u.trim().to_string())
        })
        .expect("Chromium prints its DevTools address");
    let (socket, _) = tungstenite::connect(ws.as_str()).unwrap();
    let mut page = Page {
        socket,
        session: String::new(),
        id: 0,
    };
    let targets = page.call("Target.getTargets", serde_json::json!({}), false);
    let target = targets["targetInfos"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["type"] == "page" && t["url"].as_str().unwrap_or("").starts_with(&url))
        .expect("the preview's page")["targetId"]
        .clone();
    let attached = page.call(
        "Target.attachToTarget",
        serde_json::json!({"targetId": target, "flatten": true}),
        false,
    );
    page.session = attached["sessionId"].as_str().unwrap().to_string();
    Some(Preview {
        page,
        children,
        model,
        original,
    })
}

#[test]
fn the_preview_follows_the_file_and_the_sliders() {
    let Some(Preview {
        mut page,
        mut children,
        model,
        original,
    }) = open("slider_crank_parametric.toml", "watch")
    else {
        return;
    };

    // The first solve: the report is shown, with sliders for the independent parameters.
    page.wait(
        "Number(document.body.dataset.loaded || 0) >= 1",
        "the first report",
    );
    let v1 = version(&mut page);
    page.wait(&loaded_at(v1), "the first report loaded");
    assert_eq!(page.eval("!!document.getElementById('slider-crank')"), true);
    page.eval(PAUSE);
    let before = page.eval(DIGEST);
    let poses = page.eval(POSES);

    // Save a shorter crank: the scene and plots change.
    let saved = Instant::now();
    std::fs::write(
        &model,
        original.replace("crank = \"80 mm\"", "crank = \"60 mm\""),
    )
    .unwrap();
    page.wait(
        &format!("Number(document.body.dataset.loaded || 0) > {v1}"),
        "the edited model's report",
    );
    let latency = saved.elapsed();
    let v2 = version(&mut page);
    page.wait(&loaded_at(v2), "the edited model loaded");
    assert_ne!(page.eval(DIGEST), before, "the plots did not change");
    assert_ne!(page.eval(POSES), poses, "the scene did not change");
    // In place: the viewer replaced its model (no page load), kept its time and recorded no
    // error.
    assert_eq!(page.eval(VIEWER_STATE), serde_json::json!([1, 0.25, "[]"]));
    let load = page.eval("document.body.dataset.loadMs");
    eprintln!(
        "save-to-updated-page latency: {:.0} ms (the page showing the new solve: {} ms)",
        latency.as_secs_f64() * 1e3,
        load.as_str().unwrap_or("?")
    );

    // Move a slider: a new solution, and the arguments that reproduce it.
    let before = page.eval(DIGEST);
    page.eval(
        "(() => { const i = document.getElementById('slider-speed'); i.value = i.max; \
               i.dispatchEvent(new Event('input')); return true; })()",
    );
    // Wait for the slider's own solve (its command line), not for any newer version: the
    // watcher may solve the saved file once more (a second change event of the same save), and
    // that version shows the same solution (this test failed so, once in several runs).
    page.wait(
        "document.getElementById('command').textContent.startsWith('--set speed=')",
        "the slider's solution",
    );
    let v3 = version(&mut page);
    page.wait(&loaded_at(v3), "the slider's report loaded");
    assert_ne!(page.eval(DIGEST), before, "the slider changed nothing");
    let command = page.eval("document.getElementById('command').textContent");
    assert!(
        command.as_str().unwrap().starts_with("--set speed=9.42"),
        "{command}"
    );

    // A broken file: the error with its line; fixed: the model again.
    let mass_line = original.lines().position(|l| l == "mass = 0.12").unwrap() + 1;
    std::fs::write(&model, original.replace("mass = 0.12", "mass = \"heavy\"")).unwrap();
    page.wait("document.body.dataset.error === '1'", "the error");
    let error = page.eval("document.getElementById('error').textContent");
    assert!(
        error
            .as_str()
            .unwrap()
            .contains(&format!("model.toml:{mass_line}:")),
        "{error}"
    );
    let v4 = version(&mut page);
    std::fs::write(&model, &original).unwrap();
    page.wait(&format!("document.body.dataset.error === '0' && Number(document.body.dataset.loaded || 0) > {v4}"), "the fixed model");

    // Deleted, then a directory in its place, then restored: an error each time, no crash.
    std::fs::remove_file(&model).unwrap();
    page.wait(
        "document.getElementById('error').textContent.includes('cannot read')",
        "the deleted file's error",
    );
    std::fs::create_dir(&model).unwrap();
    page.wait(
        "document.getElementById('error').textContent.includes('directory')",
        "the directory's error",
    );
    std::fs::remove_dir(&model).unwrap();
    let v5 = version(&mut page);
    std::fs::write(&model, &original).unwrap();
    page.wait(&format!("document.body.dataset.error === '0' && Number(document.body.dataset.loaded || 0) > {v5}"), "the restored model");

    // Ctrl-C ends the preview cleanly.
    let pid = children.0[0].id().to_string();
    assert!(Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap()
        .success());
    let start = Instant::now();
    let code = loop {
        if let Some(s) = children.0[0].try_wait().unwrap() {
            break s.code();
        }
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "cardan watch did not end on Ctrl-C"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(code, Some(0));
}

/// Presses, moves and releases the mouse with Ctrl held at page coordinates (the report's
/// frame offset added to the viewer's client coordinates).
fn ctrl_drag(page: &mut Page, path: &[(f64, f64)]) {
    let offset = page.eval(
        "(() => { const r = document.getElementById('report').getBoundingClientRect(); \
         return [r.left, r.top]; })()",
    );
    let (dx, dy) = (offset[0].as_f64().unwrap(), offset[1].as_f64().unwrap());
    let mouse = |page: &mut Page, kind: &str, (x, y): (f64, f64), buttons: u8| {
        page.call(
            "Input.dispatchMouseEvent",
            serde_json::json!({"type": kind, "x": x + dx, "y": y + dy, "modifiers": 2,
                "button": "left", "buttons": buttons, "clickCount": 1}),
            true,
        );
    };
    mouse(page, "mousePressed", path[0], 1);
    for &p in &path[1..] {
        mouse(page, "mouseMoved", p, 1);
    }
    mouse(page, "mouseReleased", *path.last().unwrap(), 0);
}

/// Where the viewer draws a point given in the frame of body `index` (client pixels), and
/// whether that is on its canvas.
fn screen(page: &mut Page, index: usize, local: [f64; 3]) -> (f64, f64) {
    let p = page.eval(&format!(
        "(() => {{ const w = document.getElementById('report').contentWindow; \
         const p = w.cardanReport.project({index}, {local:?}); \
         const r = w.document.getElementById('canvas').getBoundingClientRect(); \
         return [p.x, p.y, p.x > r.left && p.x < r.right && p.y > r.top && p.y < r.bottom]; }})()"
    ));
    assert_eq!(
        p[2], true,
        "{local:?} of body {index} is drawn outside the view: {p}"
    );
    (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
}

/// The rod's angle about z (deg) as the viewer draws it.
fn rod_angle(page: &mut Page) -> f64 {
    let q = page.eval("document.getElementById('report').contentWindow.cardanReport.pose(0)");
    let (e0, e3) = (q[3].as_f64().unwrap(), q[6].as_f64().unwrap());
    2.0 * e3.atan2(e0).to_degrees()
}

#[test]
fn a_body_dragged_with_the_mouse_follows_it_and_stops_at_its_end_stop() {
    let Some(Preview {
        mut page,
        children: _processes,
        ..
    }) = open("pendulum_stop.toml", "watch-drag")
    else {
        return;
    };
    page.wait(&loaded_at(1), "the report");
    page.wait(
        "document.getElementById('report').contentDocument.body.dataset.ready === '1'",
        "the viewer",
    );
    // At t = 0 the rod lies along x from the hinge; its body index 0, the ground's 1.
    let names = page.eval("document.getElementById('report').contentWindow.cardanReport.bodies()");
    assert_eq!(names, serde_json::json!(["rod", "ground"]));
    page.eval(
        "(() => { const d = document.getElementById('report').contentDocument; \
         const s = d.getElementById('scrub'); s.value = 0; s.dispatchEvent(new Event('input')); \
         return true; })()",
    );
    assert!(rod_angle(&mut page).abs() < 1e-6);

    // Up: the rod turns toward the pointer, about the hinge.
    let from = screen(&mut page, 0, [0.0, 0.0, 0.0]);
    let to = screen(&mut page, 1, [0.45, 0.1, 0.0]);
    let path: Vec<(f64, f64)> = (0..=8)
        .map(|k| {
            let s = f64::from(k) / 8.0;
            (from.0 + s * (to.0 - from.0), from.1 + s * (to.1 - from.1))
        })
        .collect();
    ctrl_drag(&mut page, &path);
    page.wait(
        "Number(document.body.dataset.dragSteps || 0) >= 1 && document.body.dataset.dragError === '0'",
        "a drag step",
    );
    page.wait(
        "document.getElementById('drag').textContent.startsWith('dragging rod:')",
        "the drag's report",
    );
    std::thread::sleep(Duration::from_millis(300));
    let up = rod_angle(&mut page);
    assert!(up > 4.0 && up < 20.0, "the rod turned to {up}°");
    // The hinge held: the rod's end O stays at the ground's O.
    let hinge = page.eval(
        "(() => { const v = document.getElementById('report').contentWindow.cardanReport; \
         const q = v.pose(0); return q; })()",
    );
    let (x, y) = (hinge[0].as_f64().unwrap(), hinge[1].as_f64().unwrap());
    let a = up.to_radians();
    assert!(
        (x - 0.5 * a.cos()).abs() < 1e-6 && (y - 0.5 * a.sin()).abs() < 1e-6,
        "the rod's centre ({x}, {y}) is not 0.5 m from the hinge at {up}°"
    );

    // Far down, grabbed nearer the hinge: the rod stops at its end stop, −60°.
    let from = screen(&mut page, 0, [-0.3, 0.0, 0.0]);
    let to = screen(&mut page, 1, [0.1, -0.8, 0.0]);
    ctrl_drag(&mut page, &[from, to]);
    page.wait("document.body.dataset.dragStop === 'stop'", "the end stop");
    let down = rod_angle(&mut page);
    assert!((down + 60.0).abs() < 1e-6, "the rod went to {down}°");
    let said = page.eval("document.getElementById('drag').textContent");
    assert!(
        said.as_str()
            .unwrap()
            .contains("stopped by the end stop \"stop\""),
        "{said}"
    );
}

/// An HTTP POST to the preview: its status code and body.
fn post(port: u16, path: &str, body: &str) -> (u16, String) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(
        s,
        "POST {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let code = out.split_whitespace().nth(1).unwrap().parse().unwrap();
    let body = out
        .split_once("\r\n\r\n")
        .map_or("", |(_, b)| b)
        .to_string();
    (code, body)
}

/// Starts `cardan watch` on a copy of `example` without a browser: its model path and port.
fn serve(example: &str, name: &str) -> (PathBuf, u16, Kill) {
    let dir = scratch(name);
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples")
            .join(example),
    )
    .unwrap();
    let model = dir.join("model.toml");
    std::fs::write(&model, text).unwrap();
    // CARDAN_BIN: the release command, for the latency reported in docs/performance.md.
    let bin = std::env::var_os("CARDAN_BIN").unwrap_or_else(|| env!("CARGO_BIN_EXE_cardan").into());
    let mut watch = Command::new(bin)
        .args(["watch", "model.toml"])
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(watch.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let port = line
        .split_whitespace()
        .find_map(|w| w.strip_prefix("http://127.0.0.1:"))
        .and_then(|w| w.trim_end_matches('/').parse().ok())
        .unwrap();
    (model, port, Kill(vec![watch]))
}

/// Waits for the preview's solve after `version`; returns its version.
fn solved_after(port: u16, version: u64) -> u64 {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(
        s,
        "GET /state?after={version} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let body = out.split_once("\r\n\r\n").unwrap().1;
    let v: serde_json::Value = serde_json::from_str(body).unwrap();
    v["version"].as_u64().unwrap()
}

#[test]
fn drag_requests_that_cannot_be_followed_are_refused_with_the_reason() {
    let (model, port, _watch) = serve("pendulum_stop.toml", "watch-drag-refused");
    let v1 = solved_after(port, 0);
    for (body, reason) in [
        ("not json", "not JSON"),
        (
            r#"{"phase": "jump"}"#,
            "\"phase\" must be start, move or end",
        ),
        (
            r#"{"phase": "move", "target": [0, 0, 0]}"#,
            "no drag in progress",
        ),
        (
            r#"{"phase": "start", "body": "ground", "point": [0, 0, 0], "t": 0}"#,
            "the ground cannot be dragged",
        ),
        (
            r#"{"phase": "start", "body": "arm", "point": [0, 0, 0], "t": 0}"#,
            "no body \"arm\"",
        ),
        (
            r#"{"phase": "start", "body": "rod", "point": [0, 0], "t": 0}"#,
            "\"point\" must be three numbers",
        ),
        (
            r#"{"phase": "start", "body": "rod", "point": [0, 0, 0]}"#,
            "\"t\" must be a time",
        ),
    ] {
        let (code, said) = post(port, "/drag", body);
        assert_eq!(code, 400, "{body}: {said}");
        assert!(said.contains(reason), "{body}: {said}");
    }
    // A drag step, then the file saved again: the next step is refused, not applied to a
    // model that is no longer shown.
    let start = r#"{"phase": "start", "body": "rod", "point": [1, 0, 0], "t": 0}"#;
    assert_eq!(post(port, "/drag", start).0, 200);
    let (code, said) = post(
        port,
        "/drag",
        r#"{"phase": "move", "target": [0.9, 0.3, 0]}"#,
    );
    assert_eq!(code, 200, "{said}");
    let step: serde_json::Value = serde_json::from_str(&said).unwrap();
    assert_eq!(step["stop"], serde_json::Value::Null);
    let tip = step["poses"][0].as_array().unwrap();
    let (x, y) = (tip[0].as_f64().unwrap(), tip[1].as_f64().unwrap());
    assert!(((x * x + y * y).sqrt() - 0.5).abs() < 1e-9, "({x}, {y})");
    let text = std::fs::read_to_string(&model).unwrap();
    std::fs::write(&model, text.replace("t_end = 3.0", "t_end = 2.0")).unwrap();
    solved_after(port, v1);
    let (code, said) = post(
        port,
        "/drag",
        r#"{"phase": "move", "target": [0.9, 0.4, 0]}"#,
    );
    assert_eq!(code, 400, "{said}");
    assert!(said.contains("solved again"), "{said}");
}

#[test]
fn a_save_without_an_edit_is_not_solved_again() {
    // The stamp changes (a save, or one of the two change events of an in-place write) but the
    // text does not: no new version. An edit after it is solved.
    let (model, port, _watch) = serve("pendulum_stop.toml", "watch-same-text");
    let v1 = solved_after(port, 0);
    let text = std::fs::read_to_string(&model).unwrap();
    for _ in 0..3 {
        std::thread::sleep(std::time::Duration::from_millis(120));
        std::fs::write(&model, &text).unwrap();
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert_eq!(solved_after(port, 0), v1, "the same text was solved again");
    std::fs::write(&model, text.replace("t_end = 3.0", "t_end = 2.0")).unwrap();
    assert!(solved_after(port, v1) > v1);
}
