//! Numbers in the model text: in full (shortest round-trip form), so the text builds the same
//! mechanism as the URDF.

use nalgebra::Vector3;

/// A number in full (shortest round-trip form).
pub(crate) fn num(x: f64) -> String {
    format!("{x:?}")
}

/// `[x, y, z]`.
pub(crate) fn vec3(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}
