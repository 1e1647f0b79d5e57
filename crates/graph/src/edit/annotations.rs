//! Edits of what the network editor draws besides nodes: sticky notes,
//! network boxes and node colours, all kept in the network file.

use crate::document::{Document, NetworkBox, NodeDoc, StickyNote};
use serde_json::json;

use crate::edit::{refuse, EditError, UI_KEY};

/// `#rrggbb`, or the refusal naming what was given.
pub fn check_color(path: &str, color: &str) -> Result<(), EditError> {
    let ok = color.len() == 7
        && color.starts_with('#')
        && color[1..].chars().all(|c| c.is_ascii_hexdigit());
    if ok {
        Ok(())
    } else {
        Err(refuse(
            path,
            format!("a colour is written #rrggbb, found `{color}`"),
        ))
    }
}

/// Sets (or with None removes) a node's colour, kept in its `ui` object.
pub fn set_node_color(
    node: &mut NodeDoc,
    path: &str,
    color: Option<&str>,
) -> Result<(), EditError> {
    if let Some(c) = color {
        check_color(path, c)?;
    }
    let ui = node
        .extra
        .entry(UI_KEY.to_owned())
        .or_insert_with(|| json!({}));
    if !ui.is_object() {
        *ui = json!({});
    }
    let map = ui.as_object_mut().expect("an object");
    match color {
        Some(c) => {
            map.insert("color".into(), json!(c));
        }
        None => {
            map.remove("color");
        }
    }
    if map.is_empty() {
        node.extra.remove(UI_KEY);
    }
    Ok(())
}

/// Sets (or with None removes) sticky note `id` of the network at `parent`.
pub fn set_note(
    d: &mut Document,
    parent: &str,
    id: &str,
    note: Option<&StickyNote>,
) -> Result<(), EditError> {
    let net = crate::edit::network_mut(d, parent)?;
    match note {
        Some(n) => {
            if let Some(c) = &n.color {
                check_color(parent, c)?;
            }
            let finite = n.pos.iter().chain(&n.size).all(|v| v.is_finite());
            if !finite || n.size[0] <= 0.0 || n.size[1] <= 0.0 {
                return Err(refuse(
                    parent,
                    "a note needs a finite position and a positive size",
                ));
            }
            net.notes.insert(id.to_owned(), n.clone());
        }
        None => {
            net.notes
                .remove(id)
                .ok_or_else(|| refuse(parent, format!("no note `{id}`")))?;
        }
    }
    Ok(())
}

/// Sets (or with None removes) network box `id` of the network at `parent`;
/// it may hold only nodes of that network.
pub fn set_box(
    d: &mut Document,
    parent: &str,
    id: &str,
    nbox: Option<&NetworkBox>,
) -> Result<(), EditError> {
    let net = crate::edit::network_mut(d, parent)?;
    match nbox {
        Some(b) => {
            if let Some(c) = &b.color {
                check_color(parent, c)?;
            }
            if let Some(n) = b.nodes.iter().find(|n| !net.nodes.contains_key(*n)) {
                return Err(refuse(
                    parent,
                    format!("a box holds nodes of its network; `{n}` is not one"),
                ));
            }
            net.boxes.insert(id.to_owned(), b.clone());
        }
        None => {
            net.boxes
                .remove(id)
                .ok_or_else(|| refuse(parent, format!("no box `{id}`")))?;
        }
    }
    Ok(())
}

/// Keeps boxes true to a renamed (`Some(new)`) or removed (`None`) node.
pub fn node_renamed(net: &mut crate::document::NetworkDoc, old: &str, new: Option<&str>) {
    for b in net.boxes.values_mut() {
        match new {
            Some(n) => b
                .nodes
                .iter_mut()
                .filter(|x| *x == old)
                .for_each(|x| *x = n.to_owned()),
            None => b.nodes.retain(|x| x != old),
        }
    }
}
