//! Loading the oracle reference files and comparing the Rust implementation with them.
//!
//! Tolerance: |got − want| ≤ 1e-12 · S for every entry, where S is the largest magnitude of that
//! quantity in the case (relative comparison), floored by the magnitude of the terms that make it
//! up (so that an entry that is zero up to cancellation, e.g. Φ at a solution, is compared at the
//! round-off level of its terms rather than at 1e-12 of itself).

use crate::registry::{build, Element};
use cardan_constraints::{BodyPair, BodyState, Constraint, MAX_EXTRA};
use nalgebra::{Vector3, Vector4};
use serde_json::Value;
use std::fmt;
use std::path::{Path, PathBuf};

/// The relative tolerance of the gate.
pub const RTOL: f64 = 1e-12;

/// The folder of the committed reference data.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../oracle/data")
}

/// One entry where Rust and the oracle disagree.
#[derive(Debug, Clone)]
pub struct Disagreement {
    /// Element name.
    pub element: String,
    /// Case label.
    pub case: String,
    /// Quantity ("phi", "phi_q", "phi_v", "nu", "gamma_q", "gamma_v").
    pub quantity: &'static str,
    /// Row.
    pub row: usize,
    /// Column (Jacobians).
    pub col: Option<usize>,
    /// Rust value.
    pub got: f64,
    /// Oracle value.
    pub want: f64,
    /// The tolerance that was applied.
    pub tol: f64,
}

impl fmt::Display for Disagreement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} [case {}] {} row {}",
            self.element, self.case, self.quantity, self.row
        )?;
        if let Some(c) = self.col {
            let (body, local) = if c < 7 || (self.quantity == "phi_v" && c < 6) {
                ("i", c)
            } else if self.quantity == "phi_v" {
                ("j", c - 6)
            } else {
                ("j", c - 7)
            };
            let names: &[&str] = if self.quantity == "phi_v" {
                &["ṙx", "ṙy", "ṙz", "ω'x", "ω'y", "ω'z"]
            } else {
                &["rx", "ry", "rz", "e0", "e1", "e2", "e3"]
            };
            write!(f, " col {c} (body {body}, {})", names[local])?;
        }
        write!(
            f,
            ": got {:.17e}, want {:.17e} (|diff| {:.2e} > tol {:.2e})",
            self.got,
            self.want,
            (self.got - self.want).abs(),
            self.tol
        )
    }
}

/// A loaded oracle file.
pub struct OracleFile {
    /// Element name.
    pub element: String,
    /// Row count declared by the oracle.
    pub rows: usize,
    /// The cases.
    pub cases: Vec<Value>,
}

/// Reads one oracle file.
pub fn load(path: &Path) -> Result<OracleFile, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let element = v["element"].as_str().ok_or("no `element`")?.to_string();
    let rows = v["rows"].as_u64().ok_or("no `rows`")? as usize;
    let cases = v["cases"].as_array().ok_or("no `cases`")?.clone();
    Ok(OracleFile {
        element,
        rows,
        cases,
    })
}

/// What keeps the oracle data and the Rust vocabulary apart: names the Rust side has without
/// oracle data (`missing`), oracle data naming nothing on the Rust side (`unknown`). The gate
/// requires both to be empty, for elements and for time-function kinds.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Mismatch {
    /// Rust names without oracle data.
    pub missing: Vec<String>,
    /// Oracle names without a Rust counterpart.
    pub unknown: Vec<String>,
}

impl Mismatch {
    /// Compares the Rust names with the oracle's.
    pub fn between<'a>(
        rust: impl IntoIterator<Item = &'a str>,
        oracle: impl IntoIterator<Item = &'a str>,
    ) -> Self {
        let rust: std::collections::BTreeSet<&str> = rust.into_iter().collect();
        let oracle: std::collections::BTreeSet<&str> = oracle.into_iter().collect();
        Self {
            missing: rust.difference(&oracle).map(|s| s.to_string()).collect(),
            unknown: oracle.difference(&rust).map(|s| s.to_string()).collect(),
        }
    }

    /// Whether the two sides agree.
    pub fn is_empty(&self) -> bool {
        self.missing.is_empty() && self.unknown.is_empty()
    }
}

/// The time-function kinds the cases of `files` exercise (`params.function.kind`).
pub fn function_kinds(files: &[OracleFile]) -> Vec<String> {
    let mut kinds: Vec<String> = files
        .iter()
        .flat_map(|f| &f.cases)
        .filter_map(|c| c["params"]["function"]["kind"].as_str())
        .map(str::to_string)
        .collect();
    kinds.sort();
    kinds.dedup();
    kinds
}

fn vec_of(v: &Value, key: &str) -> Result<Vec<f64>, String> {
    v[key]
        .as_array()
        .ok_or_else(|| format!("field `{key}` missing or null"))?
        .iter()
        .map(|x| {
            x.as_f64()
                .ok_or_else(|| format!("field `{key}` holds a non-number"))
        })
        .collect()
}

fn mat_of(v: &Value, key: &str) -> Result<Vec<Vec<f64>>, String> {
    v[key]
        .as_array()
        .ok_or_else(|| format!("field `{key}` missing or null"))?
        .iter()
        .map(|row| {
            row.as_array()
                .ok_or_else(|| format!("field `{key}`: row is not an array"))?
                .iter()
                .map(|x| {
                    x.as_f64()
                        .ok_or_else(|| format!("field `{key}` holds a non-number"))
                })
                .collect()
        })
        .collect()
}

fn body(case: &Value, side: &str, normalized: bool) -> Result<BodyState, String> {
    let q = vec_of(case, &format!("q_{side}"))?;
    let qd = vec_of(case, &format!("qdot_{side}"))?;
    let r = Vector3::new(q[0], q[1], q[2]);
    let p = Vector4::new(q[3], q[4], q[5], q[6]);
    let rd = Vector3::new(qd[0], qd[1], qd[2]);
    let pd = Vector4::new(qd[3], qd[4], qd[5], qd[6]);
    let mut b = BodyState::at(r, p);
    if normalized {
        let v = vec_of(case, &format!("v_{side}"))?;
        b = b.with_v(rd, Vector3::new(v[3], v[4], v[5]));
    }
    // The 7-coordinate quantities use the file's q̇ exactly.
    Ok(b.with_q_dot(rd, pd))
}

struct Cmp<'a> {
    element: &'a str,
    case: &'a str,
    out: &'a mut Vec<Disagreement>,
}

impl Cmp<'_> {
    fn check(
        &mut self,
        quantity: &'static str,
        got: &[f64],
        want: &[f64],
        cols: Option<usize>,
        floor: f64,
    ) {
        let scale = want.iter().chain(got).fold(floor, |m, v| m.max(v.abs()));
        let tol = RTOL * scale.max(1e-300);
        for (k, (g, w)) in got.iter().zip(want).enumerate() {
            let ok = (g - w).abs() <= tol;
            if !ok {
                let (row, col) = match cols {
                    Some(n) => (k / n, Some(k % n)),
                    None => (k, None),
                };
                self.out.push(Disagreement {
                    element: self.element.to_string(),
                    case: self.case.to_string(),
                    quantity,
                    row,
                    col,
                    got: *g,
                    want: *w,
                    tol,
                });
            }
        }
    }
}

/// Compares the Rust element with one oracle case; returns the disagreements.
pub fn compare_case(element_name: &str, case: &Value) -> Result<Vec<Disagreement>, String> {
    let label = case["label"].as_str().unwrap_or("?").to_string();
    let err = |e: String| format!("{element_name} [case {label}]: {e}");
    let el: Element = build(element_name, &case["params"]).map_err(err)?;
    let normalized = case["normalized"]
        .as_bool()
        .ok_or_else(|| err("no `normalized`".into()))?;
    let ground = case["ground"].as_str().unwrap_or("none");
    let t = case["t"].as_f64().ok_or_else(|| err("no `t`".into()))?;
    let i = if ground == "i" {
        BodyState::ground()
    } else {
        body(case, "i", normalized).map_err(err)?
    };
    let j = if ground == "j" {
        BodyState::ground()
    } else {
        body(case, "j", normalized).map_err(err)?
    };
    // The element's extra coordinates (curve parameters) and their rates, when it has any.
    let (u, u_dot) = if el.extra() > 0 {
        (
            vec_of(case, "u").map_err(err)?,
            vec_of(case, "udot").map_err(err)?,
        )
    } else {
        (Vec::new(), Vec::new())
    };
    if u.len() != el.extra() || u_dot.len() != el.extra() {
        return Err(err(format!(
            "oracle has {} extra coordinates, Rust {}",
            u.len(),
            el.extra()
        )));
    }
    let x = BodyPair::with_extra(&i, &j, &u, &u_dot);
    let m = el.rows();
    let mut out = Vec::new();
    let mut c = Cmp {
        element: element_name,
        case: &label,
        out: &mut out,
    };
    let moving = [ground != "i", ground != "j"];

    let want_phi = vec_of(case, "phi").map_err(err)?;
    if want_phi.len() != m {
        return Err(err(format!("oracle has {} rows, Rust {m}", want_phi.len())));
    }
    // Φ_q (all columns of moving bodies).
    let want_q = mat_of(case, "phi_q").map_err(err)?;
    let mut ji = vec![[0.0; 7]; m];
    let mut jj = vec![[0.0; 7]; m];
    el.phi_q(&x, t, &mut ji, &mut jj);
    let (mut got, mut want) = (Vec::new(), Vec::new());
    for r in 0..m {
        for col in 0..14 {
            let (side, lc) = (col / 7, col % 7);
            let g = if side == 0 { ji[r][lc] } else { jj[r][lc] };
            got.push(if moving[side] { g } else { want_q[r][col] });
            want.push(want_q[r][col]);
        }
    }
    let jac_scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    c.check("phi_q", &got, &want, Some(14), 0.0);
    // Φ: floored by T = max over rows of Σ |Φ_q| |q|, the size of the terms that cancel at a
    // solution.
    let q: Vec<f64> = ["q_i", "q_j"]
        .iter()
        .flat_map(|k| vec_of(case, k).unwrap_or_default())
        .collect();
    let term_scale = want_q
        .iter()
        .map(|row| row.iter().zip(&q).map(|(a, b)| (a * b).abs()).sum::<f64>())
        .fold(0.0f64, f64::max);
    let mut phi = vec![0.0; m];
    el.phi(&x, t, &mut phi);
    c.check("phi", &phi, &want_phi, None, term_scale);
    // ν and γ#: floored by the size of their terms. R = max over rows of Σ |Φ_q| |q̇| is the
    // size of Φ_q q̇ (and so of ν); γ# terms are R times the fastest rate of the case
    // (2|ṗ| for rotations, |ṙ|/L for translations at length scale L).
    let qd: Vec<f64> = ["qdot_i", "qdot_j"]
        .iter()
        .flat_map(|k| vec_of(case, k).unwrap_or_default())
        .collect();
    let mut rate_terms = want_q
        .iter()
        .map(|row| row.iter().zip(&qd).map(|(a, b)| (a * b).abs()).sum::<f64>())
        .fold(0.0f64, f64::max);
    if el.extra() > 0 {
        // Φ_u, the same in both forms; its rate terms |Φ_u u̇| join R.
        let want_u = mat_of(case, "phi_u").map_err(err)?;
        let mut ju = vec![[0.0; MAX_EXTRA]; m];
        el.jacobian_extra(&x, t, &mut ju);
        let n = el.extra();
        let got: Vec<f64> = ju.iter().flat_map(|r| r[..n].to_vec()).collect();
        let want: Vec<f64> = want_u.iter().flatten().copied().collect();
        c.check("phi_u", &got, &want, Some(n), jac_scale);
        for row in &want_u {
            let r: f64 = row.iter().zip(&u_dot).map(|(a, b)| (a * b).abs()).sum();
            rate_terms = rate_terms.max(r);
        }
    }
    let length = ["q_i", "q_j"]
        .iter()
        .flat_map(|k| vec_of(case, k).unwrap_or_default()[..3].to_vec())
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let (mut pd_max, mut rd_max) = (0.0f64, 0.0f64);
    for (k, v) in qd.iter().enumerate() {
        if k % 7 < 3 {
            rd_max = rd_max.max(v.abs());
        } else {
            pd_max = pd_max.max(v.abs());
        }
    }
    let rate = (2.0 * pd_max).max(if length > 0.0 { rd_max / length } else { 0.0 });
    let mut nu = vec![0.0; m];
    el.nu(&x, t, &mut nu);
    c.check(
        "nu",
        &nu,
        &vec_of(case, "nu").map_err(err)?,
        None,
        rate_terms,
    );
    let mut gq = vec![0.0; m];
    el.gamma_sharp_q(&x, t, &mut gq);
    let gamma_floor = (rate_terms * rate).max(term_scale * rate * rate);
    c.check(
        "gamma_q",
        &gq,
        &vec_of(case, "gamma_q").map_err(err)?,
        None,
        gamma_floor,
    );
    if normalized {
        let want_v = mat_of(case, "phi_v").map_err(err)?;
        let mut vi = vec![[0.0; 6]; m];
        let mut vj = vec![[0.0; 6]; m];
        el.phi_v(&x, t, &mut vi, &mut vj);
        let (mut got, mut want) = (Vec::new(), Vec::new());
        for r in 0..m {
            for col in 0..12 {
                let (side, lc) = (col / 6, col % 6);
                let g = if side == 0 { vi[r][lc] } else { vj[r][lc] };
                got.push(if moving[side] { g } else { want_v[r][col] });
                want.push(want_v[r][col]);
            }
        }
        // Φ_v's blocks are Φ_r and ½ Φ_p Lᵀ: the same size as Φ_q's.
        c.check("phi_v", &got, &want, Some(12), jac_scale);
        let mut gv = vec![0.0; m];
        el.gamma_sharp_v(&x, t, &mut gv);
        c.check(
            "gamma_v",
            &gv,
            &vec_of(case, "gamma_v").map_err(err)?,
            None,
            gamma_floor,
        );
    }
    Ok(out)
}
