//! A run's 3D animation and its offline report, from a [`Scene`]: bodies with geometry,
//! colours and named points, joint axes, and each body's pose (position and Euler parameters)
//! at the output times. The crate knows nothing of mechanics; `cardan-cli` builds the scene
//! from a model and its results.
//!
//! - [`write_glb`]: glTF 2.0 binary (`animation.glb`): one node per body with translation and
//!   rotation keyframes, one child node per geometry item, one material per body. Any glTF
//!   viewer (Blender, three.js, Windows 3D Viewer) plays it.
//! - [`write_html`]: `index.html`, one self-contained page that opens from disk: three.js
//!   0.160.1 (vendored, embedded in the binary), the `.glb` embedded and read by a small
//!   JavaScript reader, playback controls, trails of chosen points, body frames and joint
//!   axes, then the plots and the run summary.
//! - [`ModeShape`]: the vibration modes of a modal run, which the page animates about the
//!   scene's one pose (a mode selector, play/pause and an amplitude slider) instead of playing
//!   the `.glb`'s keyframes ([`mode_pose`] is the pose the page draws).
//! - [`StopMarker`], [`StopEvent`]: a run's end stops, which the page marks at their joints
//!   in the frames they are active in, with ticks at the impacts on its timeline (a page
//!   without stops is as it was before them).
//! - [`read_mesh`]: STL (binary or ASCII) and OBJ files as triangle meshes, with a triangle cap
//!   checked before the file is read in full.

mod base64;
/// The conversion `build.rs` runs (compiled here for its unit tests).
#[cfg(test)]
mod classic;
pub mod decimate;
mod glb;
mod html;
mod mesh_file;
mod modes;
mod rotate;
mod scene;
mod stops;
mod tessellate;

pub use glb::write_glb;
pub use html::{classic_three, write_html, write_update, Html, Page};
pub use mesh_file::{flat_mesh, read_mesh, MeshFormat};
pub use modes::{
    amplitude, mode_pose, small_rotation, validate_modes, BodyIncrement, ModeShape,
    MAX_ANIMATED_MODES, MODE_FRACTION,
};
pub use scene::{gltf_rotation, Body, Geometry, JointAxis, Mesh, NamedPoint, Scene, Shape};
pub use stops::{validate_stops, StopEvent, StopEventKind, StopMarker};
pub use tessellate::mesh_of;

/// Colour `k` of the plots' palette (`cardan_plot::PALETTE`) as linear RGB in 0..1, the glTF
/// material colour space; black (the palette's 7th entry) is skipped so no body is invisible
/// on the dark grid.
pub fn palette_colour(k: usize) -> [f32; 3] {
    let usable: Vec<&str> = cardan_plot::PALETTE
        .iter()
        .copied()
        .filter(|c| *c != "#000000")
        .collect();
    let hex = usable[k % usable.len()];
    let channel = |i: usize| {
        let v = u8::from_str_radix(&hex[1 + 2 * i..3 + 2 * i], 16).unwrap_or(0);
        srgb_to_linear(f32::from(v) / 255.0)
    };
    [channel(0), channel(1), channel(2)]
}

/// The sRGB transfer function inverted (IEC 61966-2-1).
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// What can go wrong.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum Error {
    /// The scene is inconsistent (says what and where).
    #[error("{0}")]
    Scene(String),
    /// A mesh file cannot be used (says which file and why).
    #[error("{0}")]
    Mesh(String),
}
