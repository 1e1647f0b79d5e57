//! The node catalogue as the studio reads it: every node type's ports and parameter declarations (the same declarations that drive the cook, the docs and the CLI).

use geode_op::{ParamDefault, ParamSpec, ParamType, Registry};
use serde_json::{json, Value as Json};

fn default_json(d: ParamDefault) -> Json {
    match d {
        ParamDefault::Float(x) => json!(x),
        ParamDefault::Int(x) => json!(x),
        ParamDefault::Toggle(b) => json!(b),
        ParamDefault::Vec2(v) => json!(v),
        ParamDefault::Vec3(v) => json!(v),
        ParamDefault::Vec4(v) => json!(v),
        ParamDefault::Str(s) => json!(s),
        ParamDefault::EmptyList => json!([]),
    }
}

fn type_json(t: ParamType) -> Json {
    match t {
        ParamType::Float => json!("float"),
        ParamType::Int => json!("int"),
        ParamType::Toggle => json!("toggle"),
        ParamType::Vec2 => json!("vec2"),
        ParamType::Vec3 => json!("vec3"),
        ParamType::Vec4 => json!("vec4"),
        ParamType::String => json!("string"),
        ParamType::File => json!("file"),
        ParamType::Menu(_) => json!("menu"),
        ParamType::List(_) => json!("list"),
    }
}

pub fn param_json(p: &ParamSpec) -> Json {
    let mut j = json!({
        "name": p.name,
        "label": p.label,
        "type": type_json(p.ty),
        "default": default_json(p.default),
        "min": p.min,
        "max": p.max,
        "animatable": p.animatable,
        "help": p.help,
        "affects": p.affects,
    });
    if p.code {
        j["code"] = json!(true);
    }
    match p.ty {
        ParamType::Menu(items) => j["items"] = json!(items),
        ParamType::List(l) => {
            j["fields"] = Json::Array(l.fields.iter().map(param_json).collect());
        }
        _ => {}
    }
    j
}

/// Every node type, sorted by category then name.
pub fn catalogue(registry: &Registry) -> Json {
    let mut nodes: Vec<Json> = registry
        .iter()
        .map(|op| {
            let s = op.spec();
            json!({
                "name": s.name,
                "label": s.label,
                "category": s.category,
                "summary": s.summary(),
                "help": s.help,
                "inputs": s.inputs.iter().map(|i| json!({
                    "name": i.name, "type": i.ty.to_string(), "required": i.required,
                })).collect::<Vec<_>>(),
                "variadic": s.variadic,
                "output": s.output.to_string(),
                "params": s.params.iter().map(param_json).collect::<Vec<_>>(),
                "timeDependent": s.time_dependent,
                "spare": s.spare,
            })
        })
        .collect();
    for kind in geode_graph::BlockKind::ALL {
        nodes.push(json!({
            "name": kind.name(),
            "label": kind.label(),
            "category": "Flow",
            "summary": kind.help().split(", ").next().unwrap_or(""),
            "help": kind.help(),
            "inputs": [
                {"name": "input 1", "type": "geometry", "required": true},
                {"name": "input 2", "type": "geometry", "required": false},
                {"name": "input 3", "type": "geometry", "required": false},
                {"name": "input 4", "type": "geometry", "required": false},
            ],
            "variadic": false,
            "output": "geometry",
            "params": kind.params().iter().map(param_json).collect::<Vec<_>>(),
            "timeDependent": kind == geode_graph::BlockKind::Solver,
            "network": true,
            "spare": true,
        }));
    }
    nodes.push(json!({
        "name": "subnet",
        "label": "Subnetwork",
        "category": "Flow",
        "summary": "A network inside a node: its inputs are @0, @1... inside; promoted parameters drive inner nodes.",
        "help": "A network inside a node: inner nodes read the subnet's inputs as @0, @1...; its output is the inner network's output or display node.",
        "inputs": [
            {"name": "input 1", "type": "geometry", "required": false},
            {"name": "input 2", "type": "geometry", "required": false},
            {"name": "input 3", "type": "geometry", "required": false},
            {"name": "input 4", "type": "geometry", "required": false},
        ],
        "variadic": false,
        "output": "geometry",
        "params": [],
        "timeDependent": false,
        "network": true,
        "spare": true,
    }));
    nodes.sort_by(|a, b| {
        (a["category"].as_str(), a["name"].as_str())
            .cmp(&(b["category"].as_str(), b["name"].as_str()))
    });
    json!({"nodes": nodes})
}
