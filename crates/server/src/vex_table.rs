//! `GET /api/vex`: the wrangle language's function table (every form's argument and return types, its display and one-line summary) for the studio's snippet completion, built once from geode-vex's own table.

use std::sync::OnceLock;

use axum::http::header;
use axum::response::{IntoResponse, Response};
use serde_json::{json, Value as Json};

/// The table as JSON: `{"functions": [{name, ret, category, args: [{type, name}], optional, variadic, display, summary}]}`.
pub fn table() -> Json {
    let functions: Vec<Json> = geode_nodes::vex_signatures()
        .iter()
        .map(|s| {
            let args: Vec<Json> = s
                .args
                .iter()
                .map(|(ty, name)| json!({"type": ty, "name": name}))
                .collect();
            json!({
                "name": s.name,
                "ret": s.ret,
                "category": s.category.title(),
                "args": args,
                "optional": s.optional,
                "variadic": s.variadic,
                "display": s.display,
                "summary": s.summary,
            })
        })
        .collect();
    json!({ "functions": functions })
}

/// The route's handler; the text is made on first use and kept.
pub async fn vex_json() -> Response {
    static TEXT: OnceLock<String> = OnceLock::new();
    let text = TEXT.get_or_init(|| table().to_string()).as_str();
    ([(header::CONTENT_TYPE, "application/json")], text).into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_form_is_served_with_its_types_and_summary() {
        let t = table();
        let functions = t["functions"].as_array().unwrap();
        assert_eq!(functions.len(), geode_nodes::vex_signatures().len());
        let noise = functions.iter().find(|f| f["name"] == "noise").unwrap();
        assert_eq!(noise["ret"], "float");
        assert_eq!(
            noise["args"],
            json!([{"type": "<float|vector>", "name": "pos"}])
        );
        assert_eq!(noise["display"], "float noise(<float|vector> pos)");
        assert_eq!(noise["category"], "Random numbers and noise");
        assert!(noise["summary"].as_str().unwrap().contains("noise"));
        let near = functions
            .iter()
            .find(|f| f["name"] == "nearpoints")
            .unwrap();
        assert_eq!(near["ret"], "int[]");
        assert_eq!(near["optional"], 1);
    }
}
