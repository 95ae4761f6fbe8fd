//! Arbitrary structured input → `MechanismBuilder` calls → build → assemble → DOF → a short
//! kinematic run. Must never panic; an assembled or computed state is never NaN.
#![no_main]

use arbitrary::Arbitrary;
use cardan_constraints::{TimeFunction, KINDS};
use cardan_mechanism::{
    AssemblyOptions, Axis, Body, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder,
    Orientation, GROUND,
};
use libfuzzer_sys::fuzz_target;
use nalgebra::Vector3;

/// A number: mostly moderate, sometimes extreme.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Num {
    Small(i8),
    Mid(i16),
    Raw(f64),
    Zero,
}

impl Num {
    fn get(self) -> f64 {
        match self {
            Num::Small(k) => k as f64 / 16.0,
            Num::Mid(k) => k as f64 / 256.0,
            Num::Raw(v) => v,
            Num::Zero => 0.0,
        }
    }
}

#[derive(Arbitrary, Debug)]
struct V3(Num, Num, Num);
impl V3 {
    fn get(&self) -> Vector3<f64> {
        Vector3::new(self.0.get(), self.1.get(), self.2.get())
    }
}

#[derive(Arbitrary, Debug)]
enum Orient {
    Identity,
    Params(Num, Num, Num, Num),
    AxisAngle(V3, Num),
    E313(Num, Num, Num),
    E123(Num, Num, Num),
    Axes(V3, Option<V3>),
}

#[derive(Arbitrary, Debug)]
struct BodyIn {
    mass: Option<Num>,
    inertia: Option<(Num, Num, Num)>,
    position: V3,
    orientation: Orient,
}

#[derive(Arbitrary, Debug)]
struct FeatureIn {
    body: u8,
    name: u8,
    value: V3,
    vector: bool,
}

#[derive(Arbitrary, Debug)]
struct JointIn {
    kind: u8,
    bi: u8,
    pi: u8,
    bj: u8,
    pj: u8,
    axes: Option<(u8, u8)>,
    x_axes: Option<(u8, u8)>,
    length: Option<Num>,
}

#[derive(Arbitrary, Debug)]
enum Func {
    Constant(Num),
    Poly(Vec<Num>),
    Harmonic(Num, Num, Num, Num),
    Ramp(Num, Num, Num, Num),
    Spline(Vec<(Num, Num)>),
}

#[derive(Arbitrary, Debug)]
enum Target {
    Rotation(u8),
    Translation(u8),
    Distance(u8, u8, u8, u8),
    Coordinate(u8, u8, u8),
}

#[derive(Arbitrary, Debug)]
struct DriverIn {
    target: Target,
    function: Func,
}

#[derive(Arbitrary, Debug)]
struct Input {
    bodies: Vec<BodyIn>,
    features: Vec<FeatureIn>,
    joints: Vec<JointIn>,
    drivers: Vec<DriverIn>,
    t_end: Num,
    steps: u8,
}


fn body_name(k: u8, n: usize) -> String {
    // One index past the bodies names a body that does not exist.
    let k = k as usize % (n + 2);
    if k == 0 {
        GROUND.into()
    } else {
        format!("b{}", k - 1)
    }
}

fn feat(k: u8) -> String {
    format!("f{}", k % 4)
}

fn function(f: &Func) -> TimeFunction {
    match f {
        Func::Constant(c) => TimeFunction::Constant(c.get()),
        Func::Poly(c) => TimeFunction::Polynomial(c.iter().take(8).map(|c| c.get()).collect()),
        Func::Harmonic(a, w, p, b) => TimeFunction::Harmonic {
            amplitude: a.get(),
            frequency: w.get(),
            phase: p.get(),
            offset: b.get(),
        },
        Func::Ramp(t0, t1, f0, f1) => TimeFunction::Ramp {
            t0: t0.get(),
            t1: t1.get(),
            f0: f0.get(),
            f1: f1.get(),
        },
        Func::Spline(k) => {
            let t: Vec<f64> = k.iter().take(16).map(|k| k.0.get()).collect();
            let f: Vec<f64> = k.iter().take(16).map(|k| k.1.get()).collect();
            TimeFunction::spline(t, f).unwrap_or(TimeFunction::Constant(0.0))
        }
    }
}

fuzz_target!(|input: Input| {
    let n = input.bodies.len().min(6);
    let mut b = MechanismBuilder::new();
    for (k, body) in input.bodies.iter().take(n).enumerate() {
        let mut bd = Body::new(format!("b{k}")).position(body.position.get());
        if let Some(m) = body.mass {
            bd = bd.mass(m.get());
        }
        if let Some((a, c, d)) = body.inertia {
            bd = bd.inertia_diagonal(a.get(), c.get(), d.get());
        }
        bd = bd.orientation(match &body.orientation {
            Orient::Identity => Orientation::Identity,
            Orient::Params(a, c, d, e) => {
                Orientation::EulerParams([a.get(), c.get(), d.get(), e.get()])
            }
            Orient::AxisAngle(a, t) => Orientation::AxisAngle {
                axis: a.get(),
                angle: t.get(),
            },
            Orient::E313(a, c, d) => Orientation::Euler313([a.get(), c.get(), d.get()]),
            Orient::E123(a, c, d) => Orientation::Euler123([a.get(), c.get(), d.get()]),
            Orient::Axes(z, x) => Orientation::Axes {
                z: z.get(),
                x: x.as_ref().map(V3::get),
            },
        });
        b.body(bd);
    }
    for f in input.features.iter().take(40) {
        let body = body_name(f.body, n);
        if f.vector {
            b.vector(&body, &feat(f.name), f.value.get());
        } else {
            b.point(&body, &feat(f.name), f.value.get());
        }
    }
    for (k, j) in input.joints.iter().take(10).enumerate() {
        let (bi, bj) = (body_name(j.bi, n), body_name(j.bj, n));
        let (pi, pj) = (feat(j.pi), feat(j.pj));
        let mut js = JointSpec::new(
            format!("j{k}"),
            KINDS[j.kind as usize % KINDS.len()].kind,
            (&bi, &pi),
            (&bj, &pj),
        );
        if let Some((a, c)) = j.axes {
            js = js.axes(&feat(a), &feat(c));
        }
        if let Some((a, c)) = j.x_axes {
            js = js.x_axes(&feat(a), &feat(c));
        }
        if let Some(l) = j.length {
            js = js.length(l.get());
        }
        b.joint(js);
    }
    for (k, d) in input.drivers.iter().take(6).enumerate() {
        let name = format!("d{k}");
        let f = function(&d.function);
        let spec = match &d.target {
            Target::Rotation(j) => DriverSpec::rotation(name, &format!("j{}", j % 11), f),
            Target::Translation(j) => DriverSpec::translation(name, &format!("j{}", j % 11), f),
            Target::Distance(a, c, e, g) => {
                let (bi, bj) = (body_name(*a, n), body_name(*e, n));
                DriverSpec::distance(name, (&bi, &feat(*c)), (&bj, &feat(*g)), f)
            }
            Target::Coordinate(a, c, ax) => {
                let body = body_name(*a, n);
                let axis = [Axis::X, Axis::Y, Axis::Z][*ax as usize % 3];
                DriverSpec::coordinate(name, (&body, &feat(*c)), axis, f)
            }
        };
        b.driver(spec);
    }
    let Ok(model) = b.build() else { return };
    let mut ws = model.workspace();
    let opts = AssemblyOptions {
        include_drivers: false,
        ..AssemblyOptions::at(0.0)
    };
    if model.assemble(&mut ws, &opts).is_err() {
        return;
    }
    assert!(
        ws.state().iter().all(|x| x.is_finite()),
        "assembled state not finite"
    );
    let _ = model.dof(&ws);
    let t_end = input.t_end.get();
    let steps = (input.steps % 8) as usize;
    let results = match model.run_kinematics(&KinematicOptions::new(0.0, t_end, steps)) {
        Ok(r) => r,
        Err(e) => match e.into_partial_results() {
            Some(r) => r,
            None => return,
        },
    };
    for body in &results.bodies {
        for k in 0..body.r.len() {
            assert!(
                body.r[k].iter().all(|v| v.is_finite()),
                "r not finite at {k}"
            );
            assert!(
                body.p[k].iter().all(|v| v.is_finite()),
                "p not finite at {k}"
            );
        }
    }
});
