//! URDF text → [`Robot`], with roxmltree.
//!
//! The XML parser refuses a document type declaration, so no entity can be declared and the
//! "billion laughs" expansion cannot start, and it stops at [`MAX_NODES`] nodes, so memory
//! stays bounded by the file size. Every value is checked where it is read: a number that is not
//! one, NaN or ∞, a negative mass, a missing attribute, an unknown joint type are errors at the
//! element's line naming the link or joint. Elements URDF tools add (`<gazebo>`,
//! `<transmission>`, `<material>`, `<dynamics>`, `<safety_controller>`, `<calibration>`) are
//! not part of the mechanism; `<dynamics>` damping or friction is reported, in one warning
//! listing the joints.

use crate::error::{Result, UrdfError};
use crate::pose::Pose;
use crate::robot::{
    Dynamics, Geometry, Inertial, Joint, JointType, Limit, Link, Mimic, Robot, Visual,
};
use nalgebra::{Matrix3, Vector3};
use roxmltree::{Document, Node, ParsingOptions};

/// The most XML nodes a file may hold (elements, attributes' text, comments): about 10⁵ links.
pub const MAX_NODES: u32 = 4_000_000;

/// Reads a URDF document.
///
/// # Errors
/// The first problem, at its line.
pub fn read(text: &str) -> Result<Robot> {
    let options = ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_NODES,
        ..ParsingOptions::default()
    };
    let doc = Document::parse_with_options(text, options).map_err(|e| xml_error(text, e))?;
    let root = doc.root_element();
    // Line starts, for a node's line by binary search (roxmltree's `text_pos_at` scans the text
    // from its start: quadratic over a large file).
    let starts: Vec<usize> = std::iter::once(0)
        .chain(text.match_indices('\n').map(|(k, _)| k + 1))
        .collect();
    let at = |n: Node| starts.partition_point(|&s| s <= n.range().start);
    if root.tag_name().name() != "robot" {
        return Err(UrdfError::new(
            at(root),
            format!(
                "the document's root element is <{}>; a URDF file is one <robot> element",
                root.tag_name().name()
            ),
        ));
    }
    let reader = Reader { at: &at };
    let mut robot = Robot {
        name: root.attribute("name").unwrap_or("robot").to_string(),
        links: Vec::new(),
        joints: Vec::new(),
    };
    for node in root.children().filter(Node::is_element) {
        match node.tag_name().name() {
            "link" => robot.links.push(reader.link(node)?),
            "joint" => robot.joints.push(reader.joint(node)?),
            _ => {}
        }
    }
    if robot.links.is_empty() {
        return Err(UrdfError::new(
            at(root),
            format!("robot \"{}\" has no <link>", robot.name),
        ));
    }
    Ok(robot)
}

/// An XML syntax error at its line; a DTD or too many nodes said in words.
fn xml_error(text: &str, e: roxmltree::Error) -> UrdfError {
    let mut line = e.pos().row as usize;
    if matches!(e, roxmltree::Error::DtdDetected) {
        if let Some(k) = text.find("<!DOCTYPE") {
            line = 1 + text[..k].matches('\n').count();
        }
    }
    let message = match e {
        roxmltree::Error::DtdDetected => {
            "the file has a document type declaration (<!DOCTYPE …>); URDF needs none and entity \
             declarations are not accepted (they can expand without bound): remove it"
                .to_string()
        }
        roxmltree::Error::NodesLimitReached => format!(
            "the file has more than {MAX_NODES} XML nodes; a robot of that size is not accepted"
        ),
        e => format!("not well-formed XML: {e}"),
    };
    UrdfError::new(line, message)
}

struct Reader<'a> {
    at: &'a dyn Fn(Node) -> usize,
}

/// The element children of `node` named `tag`.
fn children<'a, 'i>(node: Node<'a, 'i>, tag: &'a str) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children()
        .filter(move |n| n.is_element() && n.tag_name().name() == tag)
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &'a str) -> Option<Node<'a, 'i>> {
    children(node, tag).next()
}

impl Reader<'_> {
    fn err(&self, node: Node, message: String) -> UrdfError {
        UrdfError::new((self.at)(node), message)
    }

    /// A required attribute.
    fn attr<'a>(&self, node: Node<'a, '_>, key: &str, owner: &str) -> Result<&'a str> {
        node.attribute(key).ok_or_else(|| {
            self.err(
                node,
                format!(
                    "{owner}: <{}> needs the attribute {key}",
                    node.tag_name().name()
                ),
            )
        })
    }

    /// `n` finite numbers separated by spaces.
    fn numbers(
        &self,
        node: Node,
        key: &str,
        text: &str,
        n: usize,
        owner: &str,
    ) -> Result<Vec<f64>> {
        let values: Vec<&str> = text.split_whitespace().collect();
        let bad = |why: &str| {
            self.err(
                node,
                format!(
                    "{owner}: <{} {key}=\"{}\"> {why}",
                    node.tag_name().name(),
                    clip(text)
                ),
            )
        };
        if values.len() != n {
            return Err(bad(&format!("needs {n} numbers")));
        }
        values
            .iter()
            .map(|v| match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(bad("is not finite")),
                Err(_) => Err(bad(&format!("is not a number: \"{}\"", clip(v)))),
            })
            .collect()
    }

    fn number(&self, node: Node, key: &str, owner: &str) -> Result<Option<f64>> {
        match node.attribute(key) {
            None => Ok(None),
            Some(text) => Ok(Some(self.numbers(node, key, text, 1, owner)?[0])),
        }
    }

    fn vector(
        &self,
        node: Node,
        key: &str,
        default: Vector3<f64>,
        owner: &str,
    ) -> Result<Vector3<f64>> {
        match node.attribute(key) {
            None => Ok(default),
            Some(text) => Ok(Vector3::from_column_slice(
                &self.numbers(node, key, text, 3, owner)?,
            )),
        }
    }

    /// `<origin xyz rpy>` under `node` (identity when absent).
    fn origin(&self, node: Node, owner: &str) -> Result<Pose> {
        let Some(o) = child(node, "origin") else {
            return Ok(Pose::IDENTITY);
        };
        Ok(Pose::from_xyz_rpy(
            self.vector(o, "xyz", Vector3::zeros(), owner)?,
            self.vector(o, "rpy", Vector3::zeros(), owner)?,
        ))
    }

    fn link(&self, node: Node) -> Result<Link> {
        let name = self.attr(node, "name", "a link")?.to_string();
        let owner = format!("link \"{name}\"");
        let inertial = child(node, "inertial")
            .map(|n| self.inertial(n, &owner))
            .transpose()?;
        let visuals = children(node, "visual")
            .map(|n| self.visual(n, &owner))
            .collect::<Result<Vec<_>>>()?;
        let collisions = children(node, "collision")
            .map(|n| self.visual(n, &owner))
            .collect::<Result<Vec<_>>>()?;
        Ok(Link {
            name,
            line: (self.at)(node),
            inertial,
            visuals,
            collisions,
        })
    }

    fn inertial(&self, node: Node, owner: &str) -> Result<Inertial> {
        let origin = self.origin(node, owner)?;
        let mass_node = child(node, "mass")
            .ok_or_else(|| self.err(node, format!("{owner}: <inertial> needs <mass value=…>")))?;
        let mass = self.numbers(
            mass_node,
            "value",
            self.attr(mass_node, "value", owner)?,
            1,
            owner,
        )?[0];
        if mass < 0.0 {
            return Err(self.err(mass_node, format!("{owner}: mass {mass} is negative")));
        }
        let inertia = match child(node, "inertia") {
            None if mass == 0.0 => Matrix3::zeros(),
            None => {
                return Err(self.err(
                    node,
                    format!("{owner}: <inertial> has a mass but no <inertia ixx=… ixy=… ixz=… iyy=… iyz=… izz=…>"),
                ))
            }
            Some(n) => {
                let mut k = [0.0; 6];
                for (value, key) in k.iter_mut().zip(["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]) {
                    *value = self.number(n, key, owner)?.unwrap_or(0.0);
                }
                let [xx, xy, xz, yy, yz, zz] = k;
                Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
            }
        };
        let line = (self.at)(node);
        Ok(Inertial {
            origin,
            mass,
            inertia,
            line,
        })
    }

    fn visual(&self, node: Node, owner: &str) -> Result<Visual> {
        let origin = self.origin(node, owner)?;
        let g = child(node, "geometry")
            .and_then(|g| g.children().find(Node::is_element))
            .ok_or_else(|| {
                self.err(
                    node,
                    format!(
                        "{owner}: <{}> needs a <geometry> with a shape",
                        node.tag_name().name()
                    ),
                )
            })?;
        let positive = |key: &str| -> Result<f64> {
            let x = self.numbers(g, key, self.attr(g, key, owner)?, 1, owner)?[0];
            if x > 0.0 {
                Ok(x)
            } else {
                Err(self.err(
                    g,
                    format!(
                        "{owner}: <{} {key}> must be positive, not {x}",
                        g.tag_name().name()
                    ),
                ))
            }
        };
        let geometry = match g.tag_name().name() {
            "box" => {
                let size = Vector3::from_column_slice(&self.numbers(g, "size", self.attr(g, "size", owner)?, 3, owner)?);
                if size.iter().any(|&s| s <= 0.0) {
                    return Err(self.err(g, format!("{owner}: <box size> must be positive")));
                }
                Geometry::Box(size)
            }
            "cylinder" => Geometry::Cylinder {
                radius: positive("radius")?,
                length: positive("length")?,
            },
            "capsule" => Geometry::Capsule {
                radius: positive("radius")?,
                length: positive("length")?,
            },
            "sphere" => Geometry::Sphere(positive("radius")?),
            "mesh" => Geometry::Mesh {
                filename: self.attr(g, "filename", owner)?.to_string(),
                scale: self.vector(g, "scale", Vector3::repeat(1.0), owner)?,
            },
            other => {
                return Err(self.err(
                    g,
                    format!("{owner}: unknown geometry <{other}>; URDF's are box, cylinder, sphere and mesh"),
                ))
            }
        };
        Ok(Visual {
            origin,
            geometry,
            line: (self.at)(node),
        })
    }

    fn joint(&self, node: Node) -> Result<Joint> {
        let name = self.attr(node, "name", "a joint")?.to_string();
        let owner = format!("joint \"{name}\"");
        let type_name = self.attr(node, "type", &owner)?;
        let kind = JointType::parse(type_name).ok_or_else(|| {
            let known: Vec<&str> = JointType::TABLE.iter().map(|(n, _)| *n).collect();
            self.err(
                node,
                format!(
                    "{owner}: unknown joint type \"{}\"; URDF's are {}",
                    clip(type_name),
                    known.join(", ")
                ),
            )
        })?;
        let link_of = |tag: &str| -> Result<String> {
            let n = child(node, tag)
                .ok_or_else(|| self.err(node, format!("{owner}: needs <{tag} link=…>")))?;
            Ok(self.attr(n, "link", &owner)?.to_string())
        };
        let (parent, child_link) = (link_of("parent")?, link_of("child")?);
        let axis = match child(node, "axis") {
            None => Vector3::x(),
            Some(a) => {
                let v = self.vector(a, "xyz", Vector3::x(), &owner)?;
                let n = v.norm();
                if n < 1e-9
                    && matches!(
                        kind,
                        JointType::Revolute
                            | JointType::Continuous
                            | JointType::Prismatic
                            | JointType::Planar
                    )
                {
                    return Err(self.err(
                        a,
                        format!("{owner}: <axis xyz> is zero; give the joint's direction"),
                    ));
                }
                if n < 1e-9 {
                    Vector3::x()
                } else {
                    v / n
                }
            }
        };
        let limit = match child(node, "limit") {
            None => None,
            Some(l) => {
                // A bound beyond 10⁶ (rad or m) means none (files write ±1e16 for "unbounded").
                let bound = |key, none: f64| -> Result<f64> {
                    Ok(self.number(l, key, &owner)?.map_or(0.0, |v| {
                        if v.abs() >= 1e6 {
                            none
                        } else {
                            v
                        }
                    }))
                };
                let limit = Limit {
                    lower: bound("lower", f64::NEG_INFINITY)?,
                    upper: bound("upper", f64::INFINITY)?,
                    effort: self.number(l, "effort", &owner)?,
                    velocity: self.number(l, "velocity", &owner)?,
                    line: (self.at)(l),
                };
                if limit.lower > limit.upper {
                    return Err(self.err(l, format!("{owner}: <limit lower={} upper={}>: the lower bound is above the upper", limit.lower, limit.upper)));
                }
                Some(limit)
            }
        };
        let mimic = match child(node, "mimic") {
            None => None,
            Some(m) => Some(Mimic {
                joint: self.attr(m, "joint", &owner)?.to_string(),
                multiplier: self.number(m, "multiplier", &owner)?.unwrap_or(1.0),
                offset: self.number(m, "offset", &owner)?.unwrap_or(0.0),
                line: (self.at)(m),
            }),
        };
        let dynamics = match child(node, "dynamics") {
            None => None,
            Some(d) => {
                let value = |key| -> Result<f64> {
                    let v = self.number(d, key, &owner)?.unwrap_or(0.0);
                    if v < 0.0 {
                        return Err(UrdfError::new(
                            (self.at)(d),
                            format!("{owner}: <dynamics> {key} = {v} is negative; a damping or friction is at least 0"),
                        ));
                    }
                    Ok(v)
                };
                Some(Dynamics {
                    damping: value("damping")?,
                    friction: value("friction")?,
                    line: (self.at)(d),
                })
            }
        };
        Ok(Joint {
            name,
            line: (self.at)(node),
            kind,
            parent,
            child: child_link,
            origin: self.origin(node, &owner)?,
            axis,
            limit,
            mimic,
            dynamics,
        })
    }
}

/// A value as quoted in a message: at most 40 characters.
fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        format!("{}…", s.chars().take(40).collect::<String>())
    }
}
