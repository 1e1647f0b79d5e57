//! Where in a network document a (line, column) falls: the JSON path to it,
//! read by a tolerant scan of the text before it (the text may be broken
//! right there), and the node and parameter that path names.

/// One step of a JSON path.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

/// An open object (its current key, if one was read) or array (the index
/// of its current element) at the scan's position.
enum Open {
    Object { key: Option<String> },
    Array { index: usize },
}

/// The byte offset of 1-based `line` and `column` (serde_json's position of
/// an error: the column counts bytes), clamped to the text.
fn offset(text: &str, line: usize, column: usize) -> usize {
    let mut start = 0;
    for _ in 1..line {
        match text[start..].find('\n') {
            Some(n) => start += n + 1,
            None => return text.len(),
        }
    }
    (start + column).min(text.len())
}

/// The JSON path to byte `end` of `text`: each open object's key and each
/// open array's index. Iterative, so no nesting can overflow the stack;
/// whatever the text is, it ends.
fn path_to(text: &str, end: usize) -> Vec<Step> {
    let bytes = &text.as_bytes()[..end];
    let mut open: Vec<Open> = Vec::new();
    // An object's key comes after `{` or `,`; its value after `:`.
    let mut want_key = false;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'"' => {
                let start = i + 1;
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                if let (true, Some(Open::Object { key })) = (want_key, open.last_mut()) {
                    let raw = &bytes[start..i.min(bytes.len())];
                    *key = Some(String::from_utf8_lossy(raw).into_owned());
                    want_key = false;
                }
            }
            b'{' => {
                open.push(Open::Object { key: None });
                want_key = true;
            }
            b'[' => {
                open.push(Open::Array { index: 0 });
                want_key = false;
            }
            b'}' | b']' => {
                open.pop();
                want_key = false;
            }
            b',' => match open.last_mut() {
                Some(Open::Object { key }) => {
                    *key = None;
                    want_key = true;
                }
                Some(Open::Array { index }) => *index += 1,
                None => {}
            },
            _ => {}
        }
        i += 1;
    }
    open.into_iter()
        .filter_map(|o| match o {
            Open::Object { key } => key.map(Step::Key),
            Open::Array { index } => Some(Step::Index(index)),
        })
        .collect()
}

/// The node (its path, subnets' contents included) and the parameter a
/// JSON path lies in: `nodes/a/network/nodes/b/params/size` is node `/a/b`,
/// parameter `size`.
fn node_and_param(path: &[Step]) -> (Option<String>, Option<String>) {
    let key = |k: usize| match path.get(k) {
        Some(Step::Key(s)) => Some(s.as_str()),
        _ => None,
    };
    let (mut node, mut at) = (String::new(), 0);
    // At the document's top level, then inside each subnet's `network`.
    while let Some(name) = key(at + 1).filter(|_| key(at) == Some("nodes")) {
        node.push('/');
        node.push_str(name);
        at += 2;
        if key(at) == Some("network") {
            at += 1;
        } else {
            break;
        }
    }
    if node.is_empty() {
        return (None, None);
    }
    let param = key(at + 1).filter(|_| key(at) == Some("params"));
    (Some(node), param.map(str::to_owned))
}

/// The node and parameter whose entry holds `line`, `column` of `text`.
pub(crate) fn node_and_param_at(
    text: &str,
    line: usize,
    column: usize,
) -> (Option<String>, Option<String>) {
    node_and_param(&path_to(text, offset(text, line, column)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_position_names_its_node_and_parameter() {
        let text = r#"{"geode": "network", "nodes": {
  "a": {"type": "box", "params": {"size": [1, 2, 1e999]}},
  "s": {"type": "subnet", "network": {"nodes": {"b": {"params": {"t": "x\"y", "r": NaN}}}}}}}"#;
        let at = |needle: &str| {
            let i = text.find(needle).unwrap() + needle.len();
            node_and_param(&path_to(text, i))
        };
        let some = |n: &str, p: Option<&str>| (Some(n.to_owned()), p.map(str::to_owned));
        assert_eq!(at("1e999"), some("/a", Some("size")));
        assert_eq!(at("\"box\""), some("/a", None));
        assert_eq!(at("NaN"), some("/s/b", Some("r")));
        assert_eq!(at("{\"geode\""), (None, None));
        assert_eq!(
            path_to(text, text.find("1e999").unwrap()),
            ["nodes", "a", "params", "size"]
                .map(|k| Step::Key(k.into()))
                .into_iter()
                .chain([Step::Index(2)])
                .collect::<Vec<_>>()
        );
        // Lines and columns as serde_json counts them.
        assert_eq!(offset(text, 2, 3), text.find("\"a\"").unwrap() + 1);
        assert_eq!(offset(text, 99, 1), text.len());
    }

    #[test]
    fn any_text_scans_without_failing() {
        for text in [
            "",
            "{",
            "\"",
            "[[[[",
            "}}]]",
            "{\"a\":\"\\",
            "{\"nodes\":{\"x\":{\"params\":{\"p\":",
        ] {
            for end in 0..=text.len() {
                let _ = node_and_param(&path_to(text, end));
            }
        }
        let deep = "[".repeat(1 << 20);
        assert_eq!(path_to(&deep, deep.len()).len(), 1 << 20);
    }
}
