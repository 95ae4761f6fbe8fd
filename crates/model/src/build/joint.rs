//! `[[joint]]` sections to [`JointSpec`]s: the kind (by name or alias, with the nearest name on
//! a typo), the pairing of the axes the kind takes, and the numbers. Bodies, points and vectors
//! are resolved by the builder, whose errors [`super::Spans::locate`] places at the key.

use super::context::Resolver;
use crate::diag::{did_you_mean, list, Error};
use crate::file::JointSection;
use cardan_constraints::{JointKind, KINDS};
use cardan_mechanism::{JointSpec, Quantity};

/// Every joint type name a model file accepts (names and aliases, from the kind table).
fn joint_types() -> impl Iterator<Item = &'static str> + Clone {
    KINDS
        .iter()
        .flat_map(|k| std::iter::once(k.name).chain(k.aliases.iter().copied()))
}

pub(super) fn load_joint(r: &Resolver, j: &JointSection) -> Result<JointSpec, Error> {
    let cx = r.cx;
    let name = j.name.get_ref();
    let owner = format!("joint \"{name}\"");
    let Some(kind) = JointKind::from_name(j.kind.get_ref()) else {
        let hint = did_you_mean(j.kind.get_ref(), joint_types());
        return Err(cx.err(
            j.kind.span(),
            format!(
                "{owner}: unknown joint type \"{}\"{hint} (types: {})",
                j.kind.get_ref(),
                list(KINDS.iter().map(|k| k.name))
            ),
        ));
    };
    // Bodies, points and vectors are resolved by the builder; its errors are located at the key
    // or the unknown name (`Spans::locate`).
    let (bi, bj) = (j.body_i.get_ref().as_str(), j.body_j.get_ref().as_str());
    let mut spec = JointSpec::new(
        name.clone(),
        kind,
        (bi, j.point_i.get_ref()),
        (bj, j.point_j.get_ref()),
    );
    let info = kind.info();
    // Which of the axes the kind takes is checked by the builder (located by `Spans::locate`);
    // here only the pairing: both sides, or axis_i alone for a kind that uses frame i only.
    let both = info.axes.on_j();
    match (&j.axis_i, &j.axis_j) {
        (Some(ai), Some(aj)) => spec = spec.axes(ai.get_ref(), aj.get_ref()),
        (Some(ai), None) if !both => spec = spec.axis_i(ai.get_ref()),
        (None, None) if !info.axes.required() => {}
        (None, Some(_)) | (Some(_), None) | (None, None) => {
            let keys = if both { "axis_i and axis_j" } else { "axis_i" };
            return Err(cx.err(
                j.name.span(),
                format!(
                    "{owner}: a {} joint needs {keys} (names of vectors on body \"{bi}\"{})",
                    kind.name(),
                    if both {
                        format!(" and body \"{bj}\"")
                    } else {
                        String::new()
                    }
                ),
            ));
        }
    }
    match (&j.x_axis_i, &j.x_axis_j) {
        (Some(xi), Some(xj)) => spec = spec.x_axes(xi.get_ref(), xj.get_ref()),
        (Some(xi), None) if !both => spec = spec.x_axis_i(xi.get_ref()),
        (None, None) => {}
        (Some(x), None) | (None, Some(x)) => {
            return Err(cx.err(
                x.span(),
                format!("{owner}: give both x_axis_i and x_axis_j, or neither"),
            ))
        }
    }
    if let Some(l) = &j.length {
        // Whether the kind takes a length, and its sign: checked by the builder.
        let v = cx.num(l, format_args!("{owner} length"), Quantity::Length)?;
        spec = spec.length(v);
    }
    if let Some(h) = &j.offset {
        spec = spec.offset(cx.num(h, format_args!("{owner} offset"), Quantity::Length)?);
    }
    if let Some(a) = &j.angle {
        spec = spec.angle(cx.num(a, format_args!("{owner} angle"), Quantity::Angle)?);
    }
    Ok(spec)
}
