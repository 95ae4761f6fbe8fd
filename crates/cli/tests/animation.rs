//! `animation.glb` and `index.html` of `cardan run` (issue 23): the glb read back with the
//! `gltf` crate matches the poses of `bodies.csv` written in the same run (kinematic, inverse
//! and dynamic), declared geometry reaches the file, and bad geometry input is refused before
//! the analysis with the body and the line.

mod common;

use common::{cardan, edited, run_text, scratch, BASE};
use std::path::Path;

/// `bodies.csv` as (header, rows).
fn bodies_csv(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("bodies.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|s| s.trim_matches('"').to_string())
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

/// Per animated node: (name, times, translations, rotations as [x, y, z, w]).
type Track = (String, Vec<f32>, Vec<[f32; 3]>, Vec<[f32; 4]>);

fn tracks(glb: &[u8]) -> Vec<Track> {
    let g = gltf::Gltf::from_slice(glb).expect("a valid glb");
    let blob = g.blob.clone().expect("a BIN chunk");
    let mut out: Vec<Track> = Vec::new();
    for anim in g.animations() {
        for ch in anim.channels() {
            let name = ch.target().node().name().unwrap().to_string();
            let reader = ch.reader(|_| Some(&blob));
            let times: Vec<f32> = reader.read_inputs().unwrap().collect();
            let k = match out.iter().position(|t| t.0 == name) {
                Some(k) => k,
                None => {
                    out.push((name, times.clone(), vec![], vec![]));
                    out.len() - 1
                }
            };
            assert_eq!(out[k].1, times, "one time accessor for all channels");
            match reader.read_outputs().unwrap() {
                gltf::animation::util::ReadOutputs::Translations(v) => out[k].2 = v.collect(),
                gltf::animation::util::ReadOutputs::Rotations(r) => {
                    out[k].3 = r.into_f32().collect()
                }
                _ => panic!("only translation and rotation channels"),
            }
        }
    }
    out
}

/// |a − b| ≤ 1e-6 max(1, |b|) (glTF stores single precision).
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs().max(1.0)
}

/// Every node's keyframes equal the CSV poses: times, r, and p as [e1, e2, e3, e0].
fn assert_keyframes_match_csv(dir: &Path) {
    let (header, rows) = bodies_csv(dir);
    let glb = std::fs::read(dir.join("animation.glb")).unwrap();
    let tracks = tracks(&glb);
    let names: Vec<&str> = header[1..]
        .iter()
        .filter_map(|h| h.strip_suffix(".r.x [m]"))
        .collect();
    assert!(!names.is_empty());
    assert_eq!(
        tracks.len(),
        names.len(),
        "one animated node per moving body"
    );
    let mut compared = 0;
    for name in names {
        let (_, times, tr, rot) = tracks.iter().find(|t| t.0 == name).expect(name);
        assert_eq!(
            (times.len(), tr.len(), rot.len()),
            (rows.len(), rows.len(), rows.len())
        );
        let col = |suffix: &str| {
            header
                .iter()
                .position(|h| h == &format!("{name}.{suffix}"))
                .unwrap()
        };
        let r = ["r.x [m]", "r.y [m]", "r.z [m]"].map(col);
        let p = ["p.e0 [-]", "p.e1 [-]", "p.e2 [-]", "p.e3 [-]"].map(col);
        for (k, row) in rows.iter().enumerate() {
            assert!(close(f64::from(times[k]), row[0]), "{name} t {k}");
            for c in 0..3 {
                assert!(
                    close(f64::from(tr[k][c]), row[r[c]]),
                    "{name} r{c} at row {k}"
                );
            }
            let q = [row[p[1]], row[p[2]], row[p[3]], row[p[0]]];
            for c in 0..4 {
                assert!(
                    close(f64::from(rot[k][c]), q[c]),
                    "{name} rotation {c} at row {k}: {} vs {}",
                    rot[k][c],
                    q[c]
                );
                compared += 1;
            }
        }
    }
    assert!(compared > 100);
}

fn run_example(name: &str) -> std::path::PathBuf {
    let dir = scratch("anim");
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let o = cardan(
        &["run", model.to_str().unwrap(), "-o", "out", "--quiet"],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    dir.join("out")
}

/// Runs a bundled example with `bodies.csv` listing every body (the file's
/// `[analysis.outputs] bodies` replaced), so every animated node has its CSV poses.
fn run_with_all_bodies(name: &str) -> std::path::PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let mut doc: toml::Table = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let names: Vec<toml::Value> = doc["body"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["name"].clone())
        .collect();
    let analysis = doc.get_mut("analysis").unwrap().as_table_mut().unwrap();
    let outputs = analysis
        .entry("outputs")
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    outputs
        .as_table_mut()
        .unwrap()
        .insert("bodies".into(), toml::Value::Array(names));
    let dir = scratch("anim-all");
    let o = run_in(&dir, &toml::to_string(&doc).unwrap());
    assert_eq!(o.code, 0, "{}", o.stderr);
    dir.join("out")
}

#[test]
fn keyframes_equal_the_csv_poses_kinematic() {
    assert_keyframes_match_csv(&run_with_all_bodies("slider_crank.toml"));
}

#[test]
fn keyframes_equal_the_csv_poses_inverse_dynamics() {
    assert_keyframes_match_csv(&run_with_all_bodies("slider_crank_inverse.toml"));
}

#[test]
fn keyframes_equal_the_csv_poses_dynamic() {
    assert_keyframes_match_csv(&run_with_all_bodies("a05_flyball.toml"));
}

#[test]
fn the_report_embeds_the_glb_the_plots_and_the_summary() {
    let out = run_example("slider_crank.toml");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let files: Vec<&str> = run["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(
        files.contains(&"animation.glb") && files.contains(&"index.html"),
        "{files:?}"
    );
    assert!(
        html.contains("window.THREE={"),
        "three.js as a classic script"
    );
    assert_eq!(
        html.matches("<svg").count(),
        files.iter().filter(|f| f.ends_with(".svg")).count()
    );
    assert!(html.contains("<th>largest residual</th>"));
    // The embedded glb is the file, byte for byte.
    let start = html.find("type=\"application/octet-stream\">").unwrap() + 32;
    let end = start + html[start..].find("</script>").unwrap();
    let b64 = &html[start..end];
    let glb = std::fs::read(out.join("animation.glb")).unwrap();
    assert_eq!(decode_base64(b64), glb);
    // No network: nothing is loaded from elsewhere.
    for needle in [
        "src=\"http",
        "href=\"http",
        "import(",
        "<script type=\"module\"",
    ] {
        assert!(!html.contains(needle), "{needle}");
    }
}

fn decode_base64(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let bytes: Vec<u8> = s.bytes().filter(|&c| c != b'=').collect();
    let mut out = Vec::new();
    for chunk in bytes.chunks(4) {
        let mut n = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            n |= u32::from(val(c)) << (18 - 6 * i);
        }
        for i in 0..chunk.len() - 1 {
            out.push((n >> (16 - 8 * i)) as u8);
        }
    }
    out
}

/// A binary STL of one tetrahedron (4 triangles), or a header claiming `count` triangles.
fn binary_stl(count: Option<u32>) -> Vec<u8> {
    let tris: [[[f32; 3]; 3]; 4] = [
        [[0., 0., 0.], [0., 10., 0.], [10., 0., 0.]],
        [[0., 0., 0.], [10., 0., 0.], [0., 0., 10.]],
        [[0., 0., 0.], [0., 0., 10.], [0., 10., 0.]],
        [[10., 0., 0.], [0., 10., 0.], [0., 0., 10.]],
    ];
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&count.unwrap_or(4).to_le_bytes());
    for t in tris {
        b.extend_from_slice(&[0u8; 12]);
        for v in t {
            for x in v {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]);
    }
    b
}

const OBJ_QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

/// BASE with `geometry` on the crank.
fn with_geometry(items: &str) -> String {
    edited(
        "vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\n\n[[joint]]",
        &format!("vectors = {{ z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }}\ngeometry = [{items}]\n\n[[joint]]"),
    )
}

fn run_in(dir: &Path, model: &str) -> common::Outcome {
    std::fs::write(dir.join("model.toml"), model).unwrap();
    cardan(&["run", "model.toml", "-o", "out", "--quiet"], dir)
}

#[test]
fn declared_geometry_and_mesh_files_reach_the_glb() {
    let dir = scratch("anim-geo");
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(dir.join("parts/tet.stl"), binary_stl(None)).unwrap();
    std::fs::write(
        dir.join("parts/tri.stl"),
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
    )
    .unwrap();
    std::fs::write(dir.join("parts/quad.obj"), OBJ_QUAD).unwrap();
    let model = with_geometry(
        r#"{ shape = "box", size = [1.0, 0.1, 0.05] },
  { shape = "cylinder", radius = 0.02, length = 0.2, axis = [1.0, 0.0, 0.0], position = [-0.5, 0.0, 0.0] },
  { shape = "sphere", radius = 0.05, position = [0.5, 0.0, 0.0], orientation = { axis = [0.0, 0.0, 1.0], angle = 0.3 } },
  { shape = "mesh", file = "parts/tet.stl", scale = 0.001 },
  { shape = "mesh", file = "parts/tri.stl" },
  { shape = "mesh", file = "parts/quad.obj" }"#,
    );
    let o = run_in(&dir, &model);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let (doc, blob) = load(&dir.join("out/animation.glb"));
    let crank = doc.nodes().find(|n| n.name() == Some("crank")).unwrap();
    let items: Vec<_> = crank.children().collect();
    assert_eq!(items.len(), 6, "declared items only, no derived rods");
    let triangles: Vec<usize> = items
        .iter()
        .map(|n| {
            let p = n.mesh().unwrap().primitives().next().unwrap();
            p.reader(|_| Some(&blob[..]))
                .read_indices()
                .unwrap()
                .into_u32()
                .count()
                / 3
        })
        .collect();
    assert_eq!(triangles[0], 12, "a box");
    assert_eq!(
        &triangles[3..],
        &[4, 1, 2],
        "tetrahedron, one facet, a quad as 2 triangles"
    );
    // The STL in millimetres became metres.
    let p = items[3].mesh().unwrap().primitives().next().unwrap();
    let bb = p.bounding_box();
    assert!((bb.max[0] - 0.01).abs() < 1e-7, "{:?}", bb.max);
    // The cylinder's axis along body x: its node rotation takes z to x.
    let (_, q, _) = items[1].transform().decomposed();
    let z_to = rotate(q, [0.0, 0.0, 1.0]);
    assert!((z_to[0].abs() - 1.0).abs() < 1e-6, "{z_to:?}");
}

/// The document and binary chunk of a .glb file.
fn load(path: &Path) -> (gltf::Document, Vec<u8>) {
    let g = gltf::Gltf::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let blob = g.blob.clone().unwrap();
    (g.document, blob)
}

/// q (x, y, z, w) applied to v.
fn rotate(q: [f32; 4], v: [f32; 3]) -> [f32; 3] {
    let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
    let t = [
        2.0 * (y * v[2] - z * v[1]),
        2.0 * (z * v[0] - x * v[2]),
        2.0 * (x * v[1] - y * v[0]),
    ];
    [
        v[0] + w * t[0] + (y * t[2] - z * t[1]),
        v[1] + w * t[1] + (z * t[0] - x * t[2]),
        v[2] + w * t[2] + (x * t[1] - y * t[0]),
    ]
}

/// The error names the body, the geometry item and the model file's line, and no output was
/// written (refused before the analysis).
fn assert_refused(dir: &Path, model: &str, needles: &[&str]) {
    let o = run_in(dir, model);
    assert_eq!(o.code, 1, "{}", o.stderr);
    let line = model
        .lines()
        .position(|l| l.contains("geometry = ["))
        .unwrap()
        + 1;
    assert!(
        o.stderr.contains("body \"crank\": geometry item"),
        "{}",
        o.stderr
    );
    for n in needles {
        assert!(o.stderr.contains(n), "{n} in {}", o.stderr);
    }
    let at = format!("model.toml:{line}:");
    assert!(o.stderr.contains(&at), "{at} in {}", o.stderr);
    assert!(!dir.join("out").exists());
}

#[test]
fn a_missing_mesh_file_is_refused_with_body_and_line() {
    let dir = scratch("anim-missing");
    let m = with_geometry(r#"{ shape = "mesh", file = "nowhere.stl" }"#);
    assert_refused(&dir, &m, &["nowhere.stl", "cannot open"]);
    // `cardan check` refuses it too.
    let o = cardan(&["check", "model.toml"], &dir);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(o.stderr.contains("nowhere.stl"), "{}", o.stderr);
}

/// Preparing a model reads no mesh file: the geometry is read when first asked for (a run
/// that writes no report never reads it). The mesh is written only after the model is
/// prepared, and the geometry then reads it.
#[test]
fn mesh_files_are_read_when_the_geometry_is_asked_for_not_when_the_model_is_prepared() {
    let dir = scratch("anim-lazy");
    let m = with_geometry(r#"{ shape = "mesh", file = "late.obj" }"#);
    std::fs::write(dir.join("model.toml"), m).unwrap();
    let p = cardan_model::prepare::prepare(&dir.join("model.toml")).expect("prepared");
    std::fs::write(dir.join("late.obj"), OBJ_QUAD).unwrap();
    let declared = p
        .geometry
        .declared()
        .expect("read after the mesh was written");
    assert_eq!(declared.bodies["crank"].len(), 1);
}

#[test]
fn a_mesh_of_ten_million_triangles_is_refused_before_it_is_read() {
    let dir = scratch("anim-huge");
    // A binary STL whose length and header say 10⁷ triangles (sparse: nothing is stored).
    let f = std::fs::File::create(dir.join("huge.stl")).unwrap();
    let mut head = vec![0u8; 80];
    head.extend_from_slice(&10_000_000u32.to_le_bytes());
    std::io::Write::write_all(&mut &f, &head).unwrap();
    f.set_len(84 + 50 * 10_000_000).unwrap();
    let m = with_geometry(r#"{ shape = "mesh", file = "huge.stl" }"#);
    assert_refused(&dir, &m, &["10000000 triangles", "at most 2000000"]);
    std::fs::remove_file(dir.join("huge.stl")).unwrap();
}

#[test]
fn non_finite_vertices_are_refused() {
    let dir = scratch("anim-nan");
    std::fs::write(
        dir.join("nan.obj"),
        "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let m = with_geometry(r#"{ shape = "mesh", file = "nan.obj" }"#);
    assert_refused(&dir, &m, &["nan.obj", "not finite"]);
    let mut stl = binary_stl(None);
    stl[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(dir.join("nan.stl"), stl).unwrap();
    let m = with_geometry(r#"{ shape = "mesh", file = "nan.stl" }"#);
    assert_refused(&dir, &m, &["nan.stl", "not finite"]);
}

#[test]
fn malformed_meshes_and_shapes_are_refused() {
    let dir = scratch("anim-bad");
    std::fs::write(dir.join("junk.stl"), "this is not an STL file at all").unwrap();
    let m = with_geometry(r#"{ shape = "mesh", file = "junk.stl" }"#);
    assert_refused(&dir, &m, &["junk.stl", "not a readable STL"]);
    let m = with_geometry(r#"{ shape = "cube", size = [1.0, 1.0, 1.0] }"#);
    assert_refused(&dir, &m, &["unknown shape \"cube\""]);
    let m = with_geometry(r#"{ shape = "sphere", radius = -1.0 }"#);
    assert_refused(&dir, &m, &["radius = -1 must be positive"]);
    let m = with_geometry(r#"{ shape = "sphere", radius = 1.0, size = [1.0, 1.0, 1.0] }"#);
    assert_refused(&dir, &m, &["a sphere takes no size"]);
}

#[test]
fn a_model_without_geometry_gets_a_derived_picture() {
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let (doc, _) = load(&o.dir.join("out/animation.glb"));
    let crank = doc.nodes().find(|n| n.name() == Some("crank")).unwrap();
    // A sphere at the origin, rods to O and tip, the revolute joint's cylinder.
    assert_eq!(crank.children().count(), 4);
    let ground = doc.nodes().find(|n| n.name() == Some("ground")).unwrap();
    assert_eq!(
        ground.children().count(),
        1,
        "a marker at the ground point O"
    );
    assert_eq!(doc.materials().count(), 2, "one material per body");
}
