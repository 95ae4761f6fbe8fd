//! # cardan-urdf: robot descriptions (URDF) for cardan
//!
//! URDF (the Unified Robot Description Format of ROS) describes a robot as a tree of links
//! joined by joints. This crate reads it ([`read()`]: XML with the line of every element, typed
//! [`Robot`]), checks the tree ([`tree()`]), groups links joined by fixed joints into rigid bodies
//! at the zero configuration ([`bodies`]), maps the rest to cardan's elements ([`import()`]) and
//! writes them as a cardan model file ([`toml_out`]), which the model library validates and runs
//! like any other.
//!
//! ```
//! let urdf = r#"<robot name="pendulum">
//!   <link name="world"/>
//!   <link name="rod">
//!     <inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
//!       <inertia ixx="0.0834" iyy="0.0834" izz="0.0001"/></inertial>
//!   </link>
//!   <joint name="hinge" type="continuous">
//!     <parent link="world"/><child link="rod"/><axis xyz="0 1 0"/>
//!   </joint>
//! </robot>"#;
//! let import = cardan_urdf::import(urdf, cardan_urdf::Options::default())?;
//! let toml = cardan_urdf::toml_out::to_toml(&import, "pendulum.urdf");
//! assert!(toml.contains("type = \"revolute\""));
//! # Ok::<(), cardan_urdf::UrdfError>(())
//! ```
//!
//! ## Conventions (pinned by the tests)
//! - A joint's `<origin>` places the joint frame in the parent link's frame; the joint's motion
//!   comes after it, about (along) `<axis>` in the joint frame; at q = 0 the child link's frame
//!   is the joint frame.
//! - `rpy` is R = R_z(yaw) R_y(pitch) R_x(roll) ([`pose`]).
//! - `<inertia>` is about the centre of mass `<inertial><origin xyz>`, in the axes of
//!   `<inertial><origin rpy>`.
//! - `continuous` joints are unbounded; `revolute` and `prismatic` limits become `[[limit]]`
//!   stops (unless lower = upper, read as no limit, with a warning).
//! - `fixed` joints merge the child link into the parent's body (its origin stays a named point).
//!
//! Bad input never panics: every problem is a [`UrdfError`] with the file line and the element.

pub mod bodies;
pub mod collisions;
pub mod error;
pub mod import;
pub mod names;
mod numbers;
pub mod pose;
pub mod read;
pub mod robot;
pub mod toml_out;
pub mod tree;
pub mod visuals;

pub use bodies::Base;
pub use error::{UrdfError, Warning};
pub use import::{import, Import, MimicMode, Options};
pub use read::read;
pub use robot::{Joint, JointType, Link, Robot};
pub use tree::tree;
