//! Group patterns as the wrangle's functions read them (`expandpointgroup`,
//! `nearpoint`'s group and friends): geode-geo's one parser and matcher,
//! with Houdini's leniency: a pattern that does not parse or apply names
//! nothing.

use geode_geo::pattern::GroupPattern;
use geode_geo::{AttribClass, Geometry};

pub use geode_geo::pattern::glob;

/// The elements of `class` the pattern names, in order, without repeats;
/// nothing when the pattern is malformed.
pub fn expand(g: &Geometry, class: AttribClass, pattern: &str) -> Vec<usize> {
    GroupPattern::parse(pattern)
        .and_then(|p| p.select(g, class))
        .unwrap_or_default()
}
