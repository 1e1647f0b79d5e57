//! The network document: versioned JSON, nodes by name (paths are their nesting), unknown fields kept.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use serde_json::Value as Json;

/// The document version this geode writes and understands.
pub const VERSION: u64 = 1;

/// A network file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Document {
    /// Marks the file as a geode network (always "network").
    pub geode: String,
    pub version: u64,
    #[serde(flatten)]
    pub network: NetworkDoc,
    /// Fields of newer versions, kept so saving never drops them.
    #[serde(flatten)]
    pub extra: BTreeMap<String, Json>,
}

/// Nodes by name, and the node whose output is the network's result.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct NetworkDoc {
    pub nodes: BTreeMap<String, NodeDoc>,
    /// The output node's name; else the node with the display flag; else none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<String>,
    /// Sticky notes by id: what the author wrote beside the nodes (UI data
    /// the file keeps, as Houdini's .hip keeps its notes).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub notes: BTreeMap<String, StickyNote>,
    /// Network boxes by id: named, coloured groups of nodes.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub boxes: BTreeMap<String, NetworkBox>,
}

/// A sticky note of the network editor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StickyNote {
    pub text: String,
    /// Top-left corner and size in the editor's units.
    pub pos: [f64; 2],
    pub size: [f64; 2],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<String>,
}

/// A network box: a labelled frame around nodes of one network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NetworkBox {
    pub label: String,
    /// Names of the nodes it holds (its frame is drawn around them).
    pub nodes: Vec<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<String>,
}

/// One node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NodeDoc {
    #[serde(rename = "type")]
    pub ty: String,
    /// Parameter values: constants, or channels (`{"keys": [...]}`) per component.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, Json>,
    /// Sibling node names (or `@N` for a subnetwork's N-th input), null for an
    /// unconnected optional input.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inputs: Vec<Option<String>>,
    #[serde(default, skip_serializing_if = "is_false")]
    pub bypass: bool,
    #[serde(default, skip_serializing_if = "is_false")]
    pub display: bool,
    /// Houdini's template flag: the viewport draws this node's result as a
    /// ghost beside what is viewed.
    #[serde(default, skip_serializing_if = "is_false")]
    pub template: bool,
    /// For `type: "subnet"`: the inner network.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub network: Option<Box<NetworkDoc>>,
    /// Spare parameters the network declares on the node, name -> type
    /// (float, int, toggle, vector2, vector, vector4, string); their values
    /// go in `params` like any other.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub spare: BTreeMap<String, String>,
    /// For subnets: promoted parameters, name -> "inner_node/parameter".
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub promote: BTreeMap<String, String>,
    #[serde(flatten)]
    pub extra: BTreeMap<String, Json>,
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A document that could not even be parsed as JSON of the right shape:
/// where, in the text and (when the place is inside a node's entry) in the
/// network.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}, column {column}: {}{message}", self.within())]
pub struct SyntaxError {
    pub line: usize,
    pub column: usize,
    pub message: String,
    /// The node whose entry holds the error (`/a/b` inside subnet `a`).
    pub node: Option<String>,
    /// The parameter of `node` whose value holds it.
    pub param: Option<String>,
}

impl SyntaxError {
    /// `node /a, parameter `size`: ` where known.
    fn within(&self) -> String {
        match (&self.node, &self.param) {
            (Some(n), Some(p)) => format!("node {n}, parameter `{p}`: "),
            (Some(n), None) => format!("node {n}: "),
            _ => String::new(),
        }
    }
}

/// Paths of the nodes with the template flag, subnets' contents included.
pub fn templated(net: &NetworkDoc, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (name, node) in &net.nodes {
        let path = format!("{prefix}/{name}");
        if node.template {
            out.push(path.clone());
        }
        if let Some(inner) = &node.network {
            out.extend(templated(inner, &path));
        }
    }
    out
}

impl Document {
    pub fn new() -> Document {
        Document {
            geode: "network".into(),
            version: VERSION,
            network: NetworkDoc::default(),
            extra: BTreeMap::new(),
        }
    }

    pub fn from_json(text: &str) -> Result<Document, SyntaxError> {
        refuse_duplicate_keys(text)
            .and_then(|()| serde_json::from_str(text))
            .map_err(|e| {
                let (node, param) = crate::json_path::node_and_param_at(text, e.line(), e.column());
                SyntaxError {
                    line: e.line(),
                    column: e.column(),
                    message: e
                        .to_string()
                        .split(" at line")
                        .next()
                        .unwrap_or_default()
                        .to_owned(),
                    node,
                    param,
                }
            })
    }

    /// Pretty JSON with keys in a stable order.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("documents always serialise") + "\n"
    }
}

/// Refuses a name given twice in any object of `text` (serde would keep
/// the last silently: two nodes or parameters named alike are a mistake to
/// report, never one to drop), at the line and column of the second.
/// A pass of its own: the typed parse buffers flattened fields and loses
/// positions.
fn refuse_duplicate_keys(text: &str) -> Result<(), serde_json::Error> {
    use serde::de::{DeserializeSeed, Error, MapAccess, SeqAccess, Visitor};
    struct Scan;
    impl<'de> DeserializeSeed<'de> for Scan {
        type Value = ();
        fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
            d.deserialize_any(self)
        }
    }
    impl<'de> Visitor<'de> for Scan {
        type Value = ();
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("JSON")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
            let mut seen = std::collections::HashSet::new();
            while let Some(name) = map.next_key::<String>()? {
                if !seen.insert(name.clone()) {
                    return Err(A::Error::custom(format!(
                        "`{name}` is named twice in one object (names must be unique)"
                    )));
                }
                map.next_value_seed(Scan)?;
            }
            Ok(())
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
            while seq.next_element_seed(Scan)?.is_some() {}
            Ok(())
        }
        fn visit_bool<E>(self, _: bool) -> Result<(), E> {
            Ok(())
        }
        fn visit_i64<E>(self, _: i64) -> Result<(), E> {
            Ok(())
        }
        fn visit_u64<E>(self, _: u64) -> Result<(), E> {
            Ok(())
        }
        fn visit_f64<E>(self, _: f64) -> Result<(), E> {
            Ok(())
        }
        fn visit_str<E>(self, _: &str) -> Result<(), E> {
            Ok(())
        }
        fn visit_unit<E>(self) -> Result<(), E> {
            Ok(())
        }
    }
    let mut de = serde_json::Deserializer::from_str(text);
    Scan.deserialize(&mut de)
}

impl Default for Document {
    fn default() -> Self {
        Document::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_node_or_parameter_named_twice_is_refused() {
        let twice = r#"{"geode": "network", "version": 1, "nodes": {
            "a": {"type": "box"},
            "a": {"type": "sphere"}}}"#;
        let e = Document::from_json(twice).unwrap_err();
        assert!(e.message.contains("`a` is named twice"), "{e}");
        // At the second name, not where the object ends.
        assert_eq!(e.line, 3, "{e}");
        let twice = r#"{"geode": "network", "version": 1, "nodes": {
            "a": {"type": "box", "params": {"size": 1, "size": 2}}}}"#;
        let e = Document::from_json(twice).unwrap_err();
        assert!(e.message.contains("`size` is named twice"), "{e}");
        // Inside a subnetwork too.
        let twice = r#"{"geode": "network", "version": 1, "nodes": {
            "s": {"type": "subnet", "network": {"nodes": {"b": {"type": "box"}, "b": {"type": "box"}}}}}}"#;
        assert!(Document::from_json(twice).is_err());
    }

    #[test]
    fn unknown_fields_survive_a_round_trip() {
        let text = r#"{"geode": "network", "version": 1, "future": {"x": 1},
            "nodes": {"a": {"type": "box", "colour": "red", "params": {"size": [1, 2, 3]}}}}"#;
        let d = Document::from_json(text).unwrap();
        let again = Document::from_json(&d.to_json()).unwrap();
        assert_eq!(again, d);
        assert_eq!(again.extra["future"]["x"], 1);
        assert_eq!(again.network.nodes["a"].extra["colour"], "red");
    }

    #[test]
    fn syntax_errors_have_positions() {
        let e = Document::from_json("{\n \"geode\": \"network\",\n \"version\": }").unwrap_err();
        assert_eq!((e.line, e.column), (3, 13));
        assert_eq!((e.node, e.param), (None, None));
    }

    /// A number JSON cannot hold (1e999, NaN) names its node and parameter,
    /// subnets' contents included.
    #[test]
    fn a_bad_number_names_its_node_and_parameter() {
        let text = r#"{"geode": "network", "version": 1, "nodes": {"box1": {"type": "box", "params": {"size": [1, 1e999, 1]}}}}"#;
        let e = Document::from_json(text).unwrap_err();
        assert_eq!(e.node.as_deref(), Some("/box1"), "{e}");
        assert_eq!(e.param.as_deref(), Some("size"), "{e}");
        assert!(
            e.to_string()
                .contains("node /box1, parameter `size`: number out of range"),
            "{e}"
        );
        let text = r#"{"geode": "network", "version": 1, "nodes": {"s": {"type": "subnet",
            "network": {"nodes": {"t": {"type": "transform", "params": {"scale": NaN}}}}}}}"#;
        let e = Document::from_json(text).unwrap_err();
        assert_eq!(
            (e.node.as_deref(), e.param.as_deref()),
            (Some("/s/t"), Some("scale")),
            "{e}"
        );
    }
}
