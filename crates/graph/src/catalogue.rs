//! The node catalogue as hosts read it (the studio's page, Python's `node_type`): every node type's ports and parameter declarations as JSON, from the same declarations that drive the cook, the docs and the CLI.

use geode_geo::{RampKey, RampKind};
use geode_op::{NodeSpec, ParamDefault, ParamSpec, ParamType, Registry};
use serde_json::{json, Value as Json};

/// A ramp's keys as the document writes them: `{pos, value, interp}` each.
pub fn ramp_keys_json(kind: RampKind, keys: &[RampKey]) -> Json {
    Json::Array(
        keys.iter()
            .map(|k| {
                let value = match kind {
                    RampKind::Float => json!(k.value[0]),
                    RampKind::Color => json!(k.value),
                };
                json!({"pos": k.pos, "value": value, "interp": k.basis.name()})
            })
            .collect(),
    )
}

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
        ParamDefault::Ramp(kind, keys) => ramp_keys_json(kind, keys),
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
        ParamType::Ramp(RampKind::Float) => json!("ramp"),
        ParamType::Ramp(RampKind::Color) => json!("colorramp"),
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
        ParamType::Ramp(_) => {
            let l = p.ty.ramp_rows().expect("a ramp has key rows");
            j["fields"] = Json::Array(l.fields.iter().map(param_json).collect());
        }
        _ => {}
    }
    j
}

/// One node type as the page reads it; `network` marks the types that hold
/// a network (subnet, loop, solver: the page dives into those).
pub fn spec_json(s: &NodeSpec) -> Json {
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
        "network": crate::holds_network(s.name),
        "meta": crate::has_meta(s.name),
        "spare": s.spare,
    })
}

/// Every node type (the engine's own included), sorted by category then name.
pub fn catalogue(registry: &Registry) -> Json {
    let mut specs = crate::node_specs(registry);
    specs.sort_by_key(|s| (s.category, s.name));
    json!({"nodes": specs.into_iter().map(spec_json).collect::<Vec<_>>()})
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_engine_s_own_types_are_served_from_their_declarations() {
        // The engine's own types are there whatever the library registers.
        let cat = catalogue(&Registry::new());
        let nodes = cat["nodes"].as_array().unwrap();
        for ty in ["subnet", "loop", "solver", "for_each"] {
            let spec = crate::container_spec(ty).unwrap();
            let node = nodes.iter().find(|n| n["name"] == ty).expect(ty);
            assert_eq!(node["network"], true, "{ty}");
            assert_eq!(node["spare"], true, "{ty}");
            assert_eq!(node["label"], spec.label);
            assert_eq!(node["summary"], spec.summary());
            let names: Vec<&str> = node["params"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| p["name"].as_str().unwrap())
                .collect();
            let declared: Vec<&str> = spec.params.iter().map(|p| p.name).collect();
            assert_eq!(names, declared, "{ty}");
            assert_eq!(node["inputs"].as_array().unwrap().len(), spec.inputs.len());
        }
        let lp = nodes.iter().find(|n| n["name"] == "loop").unwrap();
        assert_eq!(lp["params"][0]["name"], "iterations");
        assert_eq!(lp["params"][0]["default"], 1);
        assert_eq!(lp["inputs"][0]["required"], true);
        // Nothing else holds a network.
        let holders = nodes.iter().filter(|n| n["network"] == true).count();
        assert_eq!(holders, 4);
    }
}
