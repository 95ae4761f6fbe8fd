//! A dynamic or static run's contacts between collision shapes: `contacts.csv` (one row per
//! contact point and output time: the two shapes and their bodies, the point, the normal, the
//! penetration and its rate, the normal and friction forces, the slip velocity, in the model's
//! units) and the warnings about doubtful contacts (a penetration deep against the shapes, the
//! sign of a step too long for the contact stiffness or of a contact the law cannot hold).

use crate::prepare::Prepared;
use crate::table::csv_field;
use cardan_dynamics::collision::ContactPoint;

pub use cardan_dynamics::collision::DEEP_PENETRATION;

/// `contacts.csv` (module docs); `None` for a model without shapes.
pub fn contacts_csv(p: &Prepared, rows: &[(f64, ContactPoint)]) -> Option<(String, String)> {
    let shapes = p.model.shapes();
    if shapes.is_empty() {
        return None;
    }
    let (lu, lf) = p.units.unit("m");
    let (vu, vf) = p.units.unit("m/s");
    let (fu, ff) = p.units.unit("N");
    let mut s = format!(
        "t [s],shape_1,body_1,shape_2,body_2,point.x [{lu}],point.y [{lu}],point.z [{lu}],\
         normal.x [-],normal.y [-],normal.z [-],penetration [{lu}],penetration_rate [{vu}],\
         normal_force [{fu}],friction.x [{fu}],friction.y [{fu}],friction.z [{fu}],\
         slip.x [{vu}],slip.y [{vu}],slip.z [{vu}]\n"
    );
    let mut b = ryu::Buffer::new();
    for (t, c) in rows {
        let [a, z] = c.shapes;
        let mut fields = vec![b.format(*t).to_string()];
        for k in [a, z] {
            fields.push(csv_field(&shapes[k].name).into_owned());
            fields.push(csv_field(p.model.body_name(shapes[k].body)).into_owned());
        }
        let mut num = |v: f64| fields.push(b.format(v).to_string());
        for v in c.point.iter() {
            num(v * lf);
        }
        for v in c.normal.iter() {
            num(*v);
        }
        num(c.penetration * lf);
        num(c.penetration_rate * vf);
        num(c.normal_force * ff);
        for v in c.friction_force.iter() {
            num(v * ff);
        }
        for v in c.slip_velocity.iter() {
            num(v * vf);
        }
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    Some(("contacts.csv".into(), s))
}

/// The deepest penetration relative to the shapes' size over `rows`: (ratio, time, point).
pub fn deepest(p: &Prepared, rows: &[(f64, ContactPoint)]) -> Option<(f64, f64, ContactPoint)> {
    rows.iter()
        .map(|(t, c)| (cardan_dynamics::collision::depth_ratio(&p.model, c), *t, *c))
        .filter(|(r, _, _)| r.is_finite())
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

/// The warning about a penetration deeper than [`DEEP_PENETRATION`] of the shapes' size, if any.
pub fn penetration_warning(p: &Prepared, rows: &[(f64, ContactPoint)]) -> Option<String> {
    let (ratio, t, c) = deepest(p, rows)?;
    if ratio <= DEEP_PENETRATION {
        return None;
    }
    let shapes = p.model.shapes();
    let (lu, lf) = p.units.unit("m");
    Some(format!(
        "shapes \"{}\" and \"{}\" penetrate {} {lu} at t = {} s, {:.0} % of the smaller shape's \
         size: the contact is too soft for the load (raise the material's stiffness) or a \
         fast impact went deep; results there are doubtful",
        shapes[c.shapes[0]].name,
        shapes[c.shapes[1]].name,
        crate::number::num(c.penetration * lf),
        crate::number::num(t),
        100.0 * ratio
    ))
}

/// The warning about fixed steps long enough for a shape to move more than a quarter of its
/// thickness in one (`IntegrationStats::contact_step_ratio` above 1), if any.
pub fn step_warning(stats: &cardan_dynamics::IntegrationStats) -> Option<String> {
    let (ratio, t) = stats.contact_step_ratio;
    (ratio > 1.0).then(|| {
        format!(
            "at t = {} s a collision shape moved {ratio:.1} times a quarter of its thickness in \
             one step: thin shapes could pass through each other unseen and impacts are \
             resolved by too few steps; use a smaller dt (or DOPRI5, which caps its steps)",
            crate::number::num(t)
        )
    })
}
