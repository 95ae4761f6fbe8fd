//! The preview's HTTP side: the page, the latest report, a long poll for the state and the
//! sliders' values. Only requests addressed to this server on the loopback interface are
//! answered: a `Host` other than `127.0.0.1:PORT` or `localhost:PORT` (a DNS-rebinding page)
//! or an `Origin` other than this page's (another site's script) gets 403.

use super::drag::{describe as describe_step, Session};
use super::{stopped, Shared, State};
use cardan_model::analysis::Shown;
use std::io::Read as _;
use std::time::{Duration, Instant};
use tiny_http::{Header, Method, Request, Response};

/// The page: the report in a frame, the error panel, the sliders.
const PAGE: &str = include_str!("page.html");
/// Longest wait of a long poll before it answers with the same version.
const LONG_POLL: Duration = Duration::from_secs(20);
/// Largest body of `POST /set`.
const MAX_BODY: u64 = 64 * 1024;

/// Answers requests until Ctrl-C, each on its own thread (long polls wait).
pub fn serve(server: &tiny_http::Server, port: u16, shared: &Shared) {
    std::thread::scope(|s| {
        while !stopped() {
            match server.recv_timeout(Duration::from_millis(100)) {
                Ok(Some(request)) => {
                    s.spawn(move || handle(request, port, shared));
                }
                Ok(None) => {}
                Err(_) => break,
            }
        }
        shared.update(|_| {});
    });
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header")
}

fn text(status: u16, body: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_string(body)
        .with_status_code(status)
        .with_header(header("Content-Type", "text/plain; charset=utf-8"))
}

/// Whether the request is this page's: its Host is this server and its Origin, if any, too.
fn allowed(request: &Request, port: u16) -> bool {
    let ours = |v: &str, prefix: &str| {
        [
            format!("{prefix}127.0.0.1:{port}"),
            format!("{prefix}localhost:{port}"),
        ]
        .iter()
        .any(|o| o.eq_ignore_ascii_case(v))
    };
    let get = |name: &'static str| {
        (request.headers().iter())
            .find(|h| h.field.equiv(name))
            .map(|h| h.value.as_str().to_string())
    };
    get("Host").is_some_and(|h| ours(&h, "")) && get("Origin").is_none_or(|o| ours(&o, "http://"))
}

fn handle(mut request: Request, port: u16, shared: &Shared) {
    if !allowed(&request, port) {
        let _ = request.respond(text(403, "cardan watch answers its own page only"));
        return;
    }
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((url.as_str(), ""));
    let response = match (request.method(), path) {
        (Method::Get, "/") => Response::from_string(PAGE)
            .with_header(header("Content-Type", "text/html; charset=utf-8")),
        (Method::Get, "/three.js") => {
            let js = Response::from_string(cardan_report::classic_three())
                .with_header(header("Content-Type", "text/javascript; charset=utf-8"))
                .with_header(header("Cache-Control", "max-age=86400"));
            let _ = request.respond(js);
            return;
        }
        (Method::Get, "/report") => shown(shared, "text/html; charset=utf-8", super::solve::page),
        (Method::Get, "/update") => shown(shared, "application/json", |s| s.update()),
        (Method::Post, "/drag") => posted(&mut request, |body| drag(shared, body)),
        (Method::Get, "/state") => {
            let after = (query.split('&'))
                .find_map(|kv| kv.strip_prefix("after="))
                .and_then(|v| v.parse().ok())
                .unwrap_or(0);
            json(&state_after(shared, after))
        }
        (Method::Post, "/set") => posted(&mut request, |body| {
            set(shared, body).map(|()| serde_json::json!({"ok": true}))
        }),
        _ => text(404, "not found"),
    };
    let _ = request.respond(response.with_header(header("Cache-Control", "no-store")));
}

/// The latest solve's page or update (`make` of what it shows, made when asked, outside the
/// state's lock), or 404 before there is one.
fn shown(
    shared: &Shared,
    content_type: &str,
    make: impl FnOnce(&Shown) -> Result<String, cardan_model::diag::Error>,
) -> Response<std::io::Cursor<Vec<u8>>> {
    let shown = shared
        .state
        .lock()
        .ok()
        .and_then(|s| s.solved.shown.clone());
    match shown.as_deref().map(make) {
        Some(Ok(body)) => {
            Response::from_string(body).with_header(header("Content-Type", content_type))
        }
        Some(Err(e)) => text(500, &e.to_string()),
        None => text(404, "no report yet"),
    }
}

/// A POST's answer: `f` of its body (at most [`MAX_BODY`] bytes) as JSON, or its error (400).
fn posted(
    request: &mut Request,
    f: impl FnOnce(&str) -> Result<serde_json::Value, String>,
) -> Response<std::io::Cursor<Vec<u8>>> {
    let mut body = String::new();
    let read = request.as_reader().take(MAX_BODY).read_to_string(&mut body);
    match read.map_err(|e| e.to_string()).and_then(|_| f(&body)) {
        Ok(v) => json(&v),
        Err(e) => text(400, &e),
    }
}

fn json(v: &serde_json::Value) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_string(v.to_string()).with_header(header("Content-Type", "application/json"))
}

/// The state once its version passes `after` (or after [`LONG_POLL`]).
fn state_after(shared: &Shared, after: u64) -> serde_json::Value {
    let deadline = Instant::now() + LONG_POLL;
    let Ok(mut s) = shared.state.lock() else {
        return serde_json::json!({"error": "the preview stopped"});
    };
    while s.version <= after && Instant::now() < deadline && !stopped() {
        s = match shared.changed.wait_timeout(s, Duration::from_millis(200)) {
            Ok((s, _)) => s,
            Err(_) => return serde_json::json!({"error": "the preview stopped"}),
        };
    }
    describe(&s)
}

/// The state as the page reads it.
fn describe(s: &State) -> serde_json::Value {
    let sliders: Vec<serde_json::Value> = (s.solved.sliders.iter())
        .map(|sl| {
            let (lo, hi) = (s.ranges.iter())
                .find(|r| r.0 == sl.name)
                .map_or((sl.value, sl.value), |r| (r.1, r.2));
            serde_json::json!({"name": sl.name, "value": sl.value, "unit": sl.unit, "min": lo, "max": hi})
        })
        .collect();
    let command: Vec<String> = s
        .set
        .iter()
        .map(|(k, v)| format!("--set {k}={v}"))
        .collect();
    serde_json::json!({
        "version": s.version,
        "error": s.solved.error,
        "warnings": s.solved.warnings,
        "report": s.solved.shown.is_some(),
        "seconds": s.seconds,
        "sliders": sliders,
        "command": command.join(" "),
    })
}

/// `POST /set` with `{"name": value, ...}`: the sliders' values, then a solve.
fn set(shared: &Shared, body: &str) -> Result<(), String> {
    let v: serde_json::Value = serde_json::from_str(body).map_err(|e| format!("not JSON: {e}"))?;
    let map = v.as_object().ok_or("a JSON object of name: number")?;
    let mut pairs = Vec::new();
    for (name, value) in map {
        let x = value
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or(format!("{name}: not a number"))?;
        pairs.push((name.clone(), format!("{x:?}")));
    }
    let known = shared.state.lock().map(|s| {
        s.solved
            .sliders
            .iter()
            .map(|sl| sl.name.clone())
            .collect::<Vec<_>>()
    });
    let known = known.map_err(|_| "the preview stopped".to_string())?;
    if let Some((bad, _)) = pairs.iter().find(|(n, _)| !known.contains(n)) {
        return Err(format!("no slider \"{bad}\""));
    }
    shared.update(|s| {
        for (name, value) in pairs {
            match s.set.iter_mut().find(|(n, _)| *n == name) {
                Some(slot) => slot.1 = value,
                None => s.set.push((name, value)),
            }
        }
        s.dirty = true;
    });
    Ok(())
}

/// `POST /drag`: `{"phase": "start", "body": name, "point": [x, y, z], "t": time}` picks a
/// body's point (world coordinates, m) at a time the page shows; `{"phase": "move", "target":
/// [x, y, z]}` is a drag step, answered with every moving body's pose (`poses`: x, y, z, e0,
/// e1, e2, e3) and how far it got; `{"phase": "end"}` ends the drag.
fn drag(shared: &Shared, body: &str) -> Result<serde_json::Value, String> {
    let v: serde_json::Value = serde_json::from_str(body).map_err(|e| format!("not JSON: {e}"))?;
    let triple = |key: &str| -> Result<[f64; 3], String> {
        let a = v[key].as_array().filter(|a| a.len() == 3);
        let a = a.ok_or(format!("drag: \"{key}\" must be three numbers"))?;
        let x: Vec<f64> = a.iter().filter_map(serde_json::Value::as_f64).collect();
        <[f64; 3]>::try_from(x).map_err(|_| format!("drag: \"{key}\" must be three numbers"))
    };
    let mut slot = shared.drag.lock().map_err(|_| "the preview stopped")?;
    let (version, snapshot) = {
        let s = shared.state.lock().map_err(|_| "the preview stopped")?;
        (s.version, s.solved.snapshot.clone())
    };
    match v["phase"].as_str() {
        Some("start") => {
            let snapshot = snapshot.ok_or("drag: no solved model to drag (see the error)")?;
            let name = v["body"]
                .as_str()
                .ok_or("drag: \"body\" must be a body's name")?;
            let t = v["t"].as_f64().ok_or("drag: \"t\" must be a time")?;
            *slot = Some(Session::start(
                snapshot,
                version,
                name,
                triple("point")?,
                t,
            )?);
            Ok(serde_json::json!({"ok": true}))
        }
        Some("move") => {
            let session = slot.as_mut().ok_or("drag: no drag in progress")?;
            if session.version != version {
                *slot = None;
                return Err("drag: the model was solved again; start the drag again".into());
            }
            let stepped = session.step(triple("target")?)?;
            let (unit, per_metre) = session.units().unit("m");
            Ok(serde_json::json!({
                "poses": stepped.poses,
                "reached": stepped.report.reached,
                "stop": match &stepped.report.stop {
                    cardan_mechanism::DragStop::None => None,
                    cardan_mechanism::DragStop::Limit(name) => Some(name.clone()),
                    cardan_mechanism::DragStop::NotConverged => Some("not converged".to_string()),
                },
                "distance": stepped.report.distance,
                "message": describe_step(session.body(), &stepped, per_metre, &unit),
            }))
        }
        Some("end") => {
            *slot = None;
            Ok(serde_json::json!({"ok": true}))
        }
        _ => Err("drag: \"phase\" must be start, move or end".into()),
    }
}
