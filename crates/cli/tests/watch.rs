//! `cardan watch` in a real browser (issue 52): headless Chromium, driven through the DevTools
//! protocol, opens the preview; the test edits the model file and sees the report (scene and
//! plots) change, measuring the save-to-updated-page time; moves a slider and sees a new
//! solution with the `--set` arguments that reproduce it; writes a broken file and sees the
//! error with its line; fixes it, deletes it, replaces it by a directory and restores it, the
//! preview following each time; then Ctrl-C ends the command. The server refuses other hosts
//! and origins and listens on the loopback interface only.

mod common;
use common::{chromium, scratch};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
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
        let state = self.eval("document.body.dataset.version + ' ' + document.body.dataset.loaded + ' ' + document.getElementById('error').textContent");
        panic!("timed out waiting for {what} ({js}); page: {state}");
    }
}

/// The report's digest: its body's length and a hash of it (plots are inline SVG).
const DIGEST: &str = "(() => { const d = document.getElementById('report').contentDocument; \
    if (!d || !d.body) return ''; const s = d.body.innerHTML; let h = 0; \
    for (let i = 0; i < s.length; i++) h = (h * 31 + s.charCodeAt(i)) | 0; return s.length + ':' + h; })()";

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

#[test]
fn the_preview_follows_the_file_and_the_sliders() {
    let Some(chromium) = chromium() else { return };
    let dir = scratch("watch");
    let example =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/slider_crank_parametric.toml");
    let original = std::fs::read_to_string(example).unwrap();
    let model = dir.join("model.toml");
    std::fs::write(&model, &original).unwrap();
    // CARDAN_BIN: the release command, for the latency reported in docs/performance.md.
    let bin = std::env::var_os("CARDAN_BIN").unwrap_or_else(|| env!("CARGO_BIN_EXE_cardan").into());
    let mut watch = Command::new(bin)
        .args(["watch", "model.toml"])
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(watch.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://127.0.0.1:"))
        .unwrap()
        .to_string();
    let port: u16 = url
        .trim_end_matches('/')
        .rsplit(':')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let mut children = Kill(vec![watch]);

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

    // The first solve: the report is shown, with sliders for the independent parameters.
    page.wait(
        "Number(document.body.dataset.loaded || 0) >= 1",
        "the first report",
    );
    let v1 = version(&mut page);
    page.wait(&loaded_at(v1), "the first report loaded");
    assert_eq!(page.eval("!!document.getElementById('slider-crank')"), true);
    let before = page.eval(DIGEST);

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
    assert_ne!(page.eval(DIGEST), before, "the report did not change");
    let load = page.eval("document.body.dataset.loadMs");
    eprintln!(
        "save-to-updated-page latency: {:.0} ms (the frame's load of the new report: {} ms)",
        latency.as_secs_f64() * 1e3,
        load.as_str().unwrap_or("?")
    );

    // Move a slider: a new solution, and the arguments that reproduce it.
    let before = page.eval(DIGEST);
    page.eval(
        "(() => { const i = document.getElementById('slider-speed'); i.value = i.max; \
               i.dispatchEvent(new Event('input')); return true; })()",
    );
    page.wait(
        &format!("Number(document.body.dataset.loaded || 0) > {v2}"),
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
