//! The compliant alternative to impacts: a limit with a [`cardan_mechanism::Compliance`] is a
//! force law on its coordinate instead of a unilateral constraint. With the penetration
//! δ = −g > 0 past the bound and its rate δ̇ = −ġ (Hunt & Crossley 1975):
//!
//! ```text
//! F = max(0, k δⁿ + c δⁿ δ̇)    (0 inside the range),     h += Gᵀ F
//! ```
//!
//! along the stop's row G = ∂g/∂v (F pushes back into the range: N or N m along the
//! coordinate). Its power F ġ is the limit's work channel (the energy stored in the contact
//! counts as work done on the mechanism, so the balance E − E₀ − W closes). No allocation.

use crate::system::Dynamics;
use cardan_mechanism::BodyId;

impl Dynamics<'_> {
    /// Adds the compliant stops' forces to `h` at the synced bodies (time `t`), and their power
    /// to `contacts.compliant_power` (per limit).
    pub(crate) fn add_compliant_stops(&mut self, t: f64) {
        let model = self.model;
        self.contacts.compliant_power.fill(0.0);
        for &s in &self.contacts.compliant {
            self.contacts.compliant_force[s] = 0.0;
        }
        for k in 0..self.contacts.compliant.len() {
            let s = self.contacts.compliant[k];
            let st = &model.stops()[s];
            let law = model.limits()[st.limit]
                .compliance
                .expect("a compliant stop");
            let (g, gdot, _) = self.stop_state(s, t);
            if g >= 0.0 {
                continue;
            }
            let delta = -g;
            let dn = delta.powf(law.exponent);
            let f = (law.stiffness * dn + law.damping * dn * (-gdot)).max(0.0);
            self.eval_stop_row(s, t);
            let (bi, bj) = self.contacts.rows[s];
            for (id, blk) in [(st.body_i, bi), (st.body_j, bj)] {
                if let BodyId::Moving(b) = id {
                    for c in 0..6 {
                        self.h[6 * b + c] += blk[c] * f;
                    }
                }
            }
            self.contacts.compliant_power[st.limit] += f * gdot;
            self.contacts.compliant_force[s] = f * st.row.bound.sign();
        }
    }
}
