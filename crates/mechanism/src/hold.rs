//! A stop held as a bilateral constraint, for the analyses that take the active set as given:
//! a static equilibrium resting on a stop (a pendulum held against it by gravity) and the modal
//! analysis about it (the stop then acts as a joint, Haug 1989 §11.6 for the active-set
//! view). [`MechanismBuilder::holding_stop`] returns the builder with the stop's coordinate
//! held at its bound by a constant driver named `<limit>.<lower|upper>` (a rotation driver for
//! an angle, a translation driver for a slide), whose effort is the stop's reaction. The stop
//! rests on the equilibrium when that reaction pushes into the range (positive effort along the
//! coordinate at a lower stop, negative at an upper one); else the equilibrium leaves it.

use crate::builder::{DriverSpec, MechanismBuilder};
use crate::error::ModelError;
use cardan_constraints::joints::Measure;
use cardan_constraints::{Bound, TimeFunction};

impl MechanismBuilder {
    /// The builder with the `bound` of limit `limit` held by a constant driver (module docs).
    ///
    /// # Errors
    /// [`ModelError::BadLimit`] for an unknown limit, a bound it does not have, or a
    /// coordinate no driver can hold (only a joint's rotation angle or its slide).
    pub fn holding_stop(&self, limit: &str, bound: Bound) -> Result<MechanismBuilder, ModelError> {
        let bad = |key: &str, reason: String| ModelError::BadLimit {
            limit: limit.into(),
            joint: String::new(),
            key: key.into(),
            reason,
        };
        let spec = self
            .limits
            .iter()
            .find(|l| l.name == limit)
            .ok_or_else(|| bad("name", "no such limit".into()))?;
        let value = match bound {
            Bound::Lower => spec.lower,
            Bound::Upper => spec.upper,
        }
        .ok_or_else(|| {
            bad(
                bound.name(),
                format!("the limit has no {} bound", bound.name()),
            )
        })?;
        let joint = self
            .joints
            .iter()
            .find(|j| j.name == spec.joint)
            .ok_or_else(|| bad("joint", format!("unknown joint \"{}\"", spec.joint)))?;
        let info = joint.kind.info();
        let coordinate = (info.coordinate(spec.coordinate.as_deref()))
            .ok_or_else(|| bad("coordinate", "no such coordinate".into()))?;
        let name = format!("{limit}.{}", bound.name());
        let f = TimeFunction::Constant(value);
        let driver = match coordinate.measure {
            Measure::Angle if info.rotation == Some(coordinate.name) => {
                DriverSpec::rotation(name, &spec.joint, f)
            }
            Measure::Slide if info.translation == Some(coordinate.name) => {
                DriverSpec::translation(name, &spec.joint, f)
            }
            _ => {
                return Err(bad(
                    "coordinate",
                    format!(
                        "the {} of a {} joint cannot be held by a driver (only a joint's driven \
                         angle or slide)",
                        coordinate.name, info.name
                    ),
                ))
            }
        };
        let mut b = self.clone();
        b.driver(driver);
        Ok(b)
    }
}
