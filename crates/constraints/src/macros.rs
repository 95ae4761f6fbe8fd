//! Internal macros that write the repetitive `Constraint` impls once.

/// `impl Constraint for $ty` by forwarding every method through `$dispatch!(self, c => ...)`,
/// a per-enum macro that matches each variant to `c`.
macro_rules! forward_constraint_by_match {
    ($ty:ty, $dispatch:ident) => {
        impl $crate::constraint::Constraint for $ty {
            fn name(&self) -> &'static str {
                $dispatch!(self, c => c.name())
            }
            fn rows(&self) -> usize {
                $dispatch!(self, c => c.rows())
            }
            fn dimension(&self, row: usize) -> $crate::constraint::Dimension {
                $dispatch!(self, c => c.dimension(row))
            }
            fn footprint(&self) -> $crate::state::Footprint {
                $dispatch!(self, c => c.footprint())
            }
            fn phi(&self, x: &$crate::state::BodyPair, t: f64, out: &mut [f64]) {
                $dispatch!(self, c => c.phi(x, t, out))
            }
            fn jacobian<const N: usize, F: $crate::jet::Form<N>>(
                &self,
                x: &$crate::state::BodyPair,
                t: f64,
                out_i: &mut [[f64; N]],
                out_j: &mut [[f64; N]],
            ) {
                $dispatch!(self, c => c.jacobian::<N, F>(x, t, out_i, out_j))
            }
            fn nu(&self, x: &$crate::state::BodyPair, t: f64, out: &mut [f64]) {
                $dispatch!(self, c => c.nu(x, t, out))
            }
            fn gamma_sharp<const N: usize, F: $crate::jet::Form<N>>(
                &self,
                x: &$crate::state::BodyPair,
                t: f64,
                out: &mut [f64],
            ) {
                $dispatch!(self, c => c.gamma_sharp::<N, F>(x, t, out))
            }
        }
    };
}

/// `impl Constraint for $ty` by forwarding everything but the name to the field `$inner`.
macro_rules! forward_constraint_to_field {
    ($ty:ty, $inner:ident, $name:literal) => {
        impl $crate::constraint::Constraint for $ty {
            fn name(&self) -> &'static str {
                $name
            }
            fn rows(&self) -> usize {
                self.$inner.rows()
            }
            fn dimension(&self, row: usize) -> $crate::constraint::Dimension {
                self.$inner.dimension(row)
            }
            fn footprint(&self) -> $crate::state::Footprint {
                self.$inner.footprint()
            }
            fn phi(&self, x: &$crate::state::BodyPair, t: f64, out: &mut [f64]) {
                self.$inner.phi(x, t, out)
            }
            fn jacobian<const N: usize, F: $crate::jet::Form<N>>(
                &self,
                x: &$crate::state::BodyPair,
                t: f64,
                out_i: &mut [[f64; N]],
                out_j: &mut [[f64; N]],
            ) {
                self.$inner.jacobian::<N, F>(x, t, out_i, out_j)
            }
            fn nu(&self, x: &$crate::state::BodyPair, t: f64, out: &mut [f64]) {
                self.$inner.nu(x, t, out)
            }
            fn gamma_sharp<const N: usize, F: $crate::jet::Form<N>>(
                &self,
                x: &$crate::state::BodyPair,
                t: f64,
                out: &mut [f64],
            ) {
                self.$inner.gamma_sharp::<N, F>(x, t, out)
            }
        }
    };
}
