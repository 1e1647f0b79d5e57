//! Toy operators for the engine's tests: the engine must work with node types it has never heard of.
#![allow(dead_code)]

use std::sync::atomic::{AtomicUsize, Ordering};

use geode_geo::glam::Vec3;
use geode_geo::Geometry;
use geode_op::{
    CheckContext, CookContext, CookError, InputSpec, NodeSpec, Operator, ParamDefault, ParamSpec,
    ParamType, Params, PortType, Registry, Value,
};

/// `points`: `count` points along X, spaced by `step`.
struct Points;
/// `offset`: moves every point by `by`.
struct Offset;
/// `clamp`: clamps X to at most `max` (so different inputs can give equal outputs).
struct Clamp;
/// `join`: merges any number of inputs.
struct Join;
/// `pack`: a bundle of its inputs named a, b, c...
struct Pack;
/// `slow`: spins until cancelled.
struct Slow;

static POINTS: NodeSpec = NodeSpec::new(
    "points",
    "Points",
    "test",
    "",
    &[],
    &[
        ParamSpec::new("count", "Count", ParamType::Int, ParamDefault::Int(3), "")
            .range(0.0, 1000.0),
        ParamSpec::new(
            "step",
            "Step",
            ParamType::Float,
            ParamDefault::Float(1.0),
            "",
        ),
    ],
);
static OFFSET: NodeSpec = NodeSpec::new(
    "offset",
    "Offset",
    "test",
    "",
    &[InputSpec {
        name: "geometry",
        ty: PortType::Geometry,
        required: true,
    }],
    &[ParamSpec::new(
        "by",
        "By",
        ParamType::Vec3,
        ParamDefault::Vec3([0.0; 3]),
        "",
    )],
);
static CLAMP: NodeSpec = NodeSpec::new(
    "clamp",
    "Clamp",
    "test",
    "",
    &[InputSpec {
        name: "geometry",
        ty: PortType::Geometry,
        required: true,
    }],
    &[ParamSpec::new(
        "max",
        "Max",
        ParamType::Float,
        ParamDefault::Float(1.0),
        "",
    )],
);
/// Any number of optional geometry inputs (with `variadic`).
const OPTIONAL_GEOMETRY: [InputSpec; 1] = [InputSpec {
    name: "geometry",
    ty: PortType::Geometry,
    required: false,
}];
static JOIN: NodeSpec =
    NodeSpec::new("join", "Join", "test", "", &OPTIONAL_GEOMETRY, &[]).variadic();
static PACK: NodeSpec = NodeSpec::new("pack", "Pack", "test", "", &OPTIONAL_GEOMETRY, &[])
    .variadic()
    .output(PortType::Bundle);
static SLOW: NodeSpec = NodeSpec::new("slow", "Slow", "test", "", &[], &[]);
static SPIN: NodeSpec =
    NodeSpec::new("spin", "Spin", "test", "", &OPTIONAL_GEOMETRY, &[]).variadic();

pub static COOKS: AtomicUsize = AtomicUsize::new(0);

pub fn geo(v: &Value) -> &Geometry {
    v.as_geometry().unwrap()
}

impl Operator for Points {
    fn spec(&self) -> &'static NodeSpec {
        &POINTS
    }
    fn cook(&self, _: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
        COOKS.fetch_add(1, Ordering::Relaxed);
        let mut g = Geometry::new();
        let step = p.float(&POINTS.params[1])? as f32;
        let pts: Vec<Vec3> = (0..p.int(&POINTS.params[0])?)
            .map(|i| Vec3::X * i as f32 * step)
            .collect();
        g.add_points(&pts);
        Ok(Value::geometry(g))
    }
}

impl Operator for Offset {
    fn spec(&self) -> &'static NodeSpec {
        &OFFSET
    }
    fn cook(
        &self,
        _: &CookContext,
        inputs: &[Option<Value>],
        p: &Params,
    ) -> Result<Value, CookError> {
        let mut g = geo(inputs[0].as_ref().unwrap()).clone();
        let by = p.vector::<3>(&OFFSET.params[0])?;
        for q in g.positions_mut() {
            *q += Vec3::new(by[0] as f32, by[1] as f32, by[2] as f32);
        }
        Ok(Value::geometry(g))
    }
}

impl Operator for Clamp {
    fn spec(&self) -> &'static NodeSpec {
        &CLAMP
    }
    fn cook(
        &self,
        _: &CookContext,
        inputs: &[Option<Value>],
        p: &Params,
    ) -> Result<Value, CookError> {
        let mut g = geo(inputs[0].as_ref().unwrap()).clone();
        let max = p.float(&CLAMP.params[0])? as f32;
        for q in g.positions_mut() {
            q.x = q.x.min(max);
        }
        Ok(Value::geometry(g))
    }
    /// Refuses a negative `max` without cooking (`Network::check`).
    fn check(&self, ctx: &CheckContext, p: &Params) -> Result<(), CookError> {
        let max = p.float(&CLAMP.params[0])?;
        if max < 0.0 {
            return Err(CookError::param(
                ctx.path,
                "max",
                format!(
                    "{max} at frame {} is negative (input wired: {})",
                    ctx.frame, ctx.wired[0]
                ),
            ));
        }
        Ok(())
    }
}

impl Operator for Join {
    fn spec(&self) -> &'static NodeSpec {
        &JOIN
    }
    fn cook(
        &self,
        _: &CookContext,
        inputs: &[Option<Value>],
        _: &Params,
    ) -> Result<Value, CookError> {
        let gs: Vec<&Geometry> = inputs.iter().flatten().map(geo).collect();
        Ok(Value::geometry(geode_geo::ops::merge(&gs).unwrap()))
    }
}

impl Operator for Pack {
    fn spec(&self) -> &'static NodeSpec {
        &PACK
    }
    fn cook(
        &self,
        _: &CookContext,
        inputs: &[Option<Value>],
        _: &Params,
    ) -> Result<Value, CookError> {
        let mut b = geode_op::Bundle::default();
        for (i, v) in inputs.iter().enumerate() {
            if let Some(v) = v {
                b.entries.insert(
                    ((b'a' + i as u8) as char).to_string(),
                    v.as_geometry().unwrap().clone(),
                );
            }
        }
        Ok(Value::Bundle(std::sync::Arc::new(b)))
    }
}

impl Operator for Slow {
    fn spec(&self) -> &'static NodeSpec {
        &SLOW
    }
    fn cook(&self, ctx: &CookContext, _: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
        loop {
            ctx.check()?;
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }
}

/// Passes its first input through after parallel work with short waits
/// (a kernel that joins on rayon, during which its worker steals jobs).
struct Spin;

impl Operator for Spin {
    fn spec(&self) -> &'static NodeSpec {
        &SPIN
    }
    fn cook(
        &self,
        _: &CookContext,
        inputs: &[Option<Value>],
        _: &Params,
    ) -> Result<Value, CookError> {
        use rayon::prelude::*;
        let spun: u64 = (0..32u64)
            .into_par_iter()
            .map(|k| {
                std::thread::sleep(std::time::Duration::from_micros(200));
                k
            })
            .sum();
        assert_eq!(spun, 496);
        Ok(inputs
            .iter()
            .flatten()
            .next()
            .cloned()
            .unwrap_or_else(|| Value::geometry(Geometry::new())))
    }
}

pub fn registry() -> Registry {
    let mut r = Registry::new();
    r.add(Points);
    r.add(Offset);
    r.add(Clamp);
    r.add(Join);
    r.add(Pack);
    r.add(Slow);
    r.add(Spin);
    r
}
