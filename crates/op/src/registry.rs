//! The set of node types a network may use, by name.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::{CookFn, ExprLanguage, FnOperator, NodeSpec, Operator};

/// Node types by name. The engine only ever sees this, never a concrete node.
#[derive(Clone, Default)]
pub struct Registry {
    ops: BTreeMap<&'static str, Arc<dyn Operator>>,
    expressions: Option<Arc<dyn ExprLanguage>>,
}

impl Registry {
    pub fn new() -> Registry {
        Registry::default()
    }

    /// Adds a node type. A name given twice is a bug in the library that
    /// builds the registry (one declaration would silently shadow the
    /// other), found the first time the registry is built.
    pub fn add(&mut self, op: impl Operator + 'static) {
        let name = op.spec().name;
        let earlier = self.ops.insert(name, Arc::new(op));
        assert!(earlier.is_none(), "node type `{name}` is registered twice");
    }

    /// Adds a node type given by its declaration and cook function.
    pub fn node(&mut self, spec: &'static NodeSpec, cook: CookFn) {
        self.add(FnOperator {
            spec,
            cook,
            key_extra: None,
        });
    }

    /// Sets the language of parameter expressions.
    pub fn set_expressions(&mut self, language: Arc<dyn ExprLanguage>) {
        self.expressions = Some(language);
    }

    /// The language of parameter expressions, if one is plugged in.
    pub fn expressions(&self) -> Option<&dyn ExprLanguage> {
        self.expressions.as_deref()
    }

    pub fn get(&self, name: &str) -> Option<&Arc<dyn Operator>> {
        self.ops.get(name)
    }

    /// Node types in name order.
    pub fn iter(&self) -> impl Iterator<Item = &Arc<dyn Operator>> {
        self.ops.values()
    }

    /// Up to three known names closest to `name` (edit distance), for "did
    /// you mean": only those as close as the closest (a near name is not
    /// joined by far ones: `sphear` suggests `sphere`, not also `peak`).
    pub fn closest(&self, name: &str) -> Vec<&'static str> {
        let mut scored: Vec<(usize, &'static str)> = self
            .ops
            .keys()
            .map(|k| (edit_distance(name, k), *k))
            .filter(|(d, k)| *d <= (k.len().max(name.len()) / 2).max(2))
            .collect();
        scored.sort();
        let best = scored.first().map_or(0, |s| s.0);
        scored
            .into_iter()
            .take_while(|(d, _)| *d == best)
            .take(3)
            .map(|(_, k)| k)
            .collect()
    }
}

/// Levenshtein distance over characters.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::edit_distance;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("sphere", "sphere"), 0);
        assert_eq!(edit_distance("shpere", "sphere"), 2);
        assert_eq!(edit_distance("", "box"), 3);
    }
}
