//! Every form of the group syntax against the meaning SideFX documents
//! ("Geometry groups" and "Pattern matching in parameters" in Houdini's
//! help): the expected selections are written from those pages.

use super::*;
use crate::{AttribData, Attribute, StringColumn, TypeInfo};
use glam::Vec3;

/// 40 points on a line (x = index, y = index - 20), groups `top` (30..40),
/// `top2` (0, 1) and `bottom` (0..10), a string attribute `name` (`a` for
/// the first half, `piece b` for the second).
fn points() -> Geometry {
    let mut g = Geometry::new();
    for i in 0..40 {
        g.add_point(Vec3::new(i as f32, i as f32 - 20.0, 0.0));
    }
    g.set_point_group("top", Group::from_members(40, 30..40))
        .unwrap();
    g.set_point_group("top2", Group::from_members(40, [0, 1]))
        .unwrap();
    g.set_point_group("bottom", Group::from_members(40, 0..10))
        .unwrap();
    let names = StringColumn {
        table: vec!["a".into(), "piece b".into()],
        indices: (0..40).map(|i| u32::from(i >= 20)).collect(),
    };
    g.set_attrib(
        AttribClass::Point,
        "name",
        Attribute::from_data(AttribData::String(names), TypeInfo::None),
    )
    .unwrap();
    g
}

fn sel(pattern: &str) -> Vec<usize> {
    GroupPattern::parse(pattern)
        .unwrap()
        .select(&points(), AttribClass::Point)
        .unwrap_or_else(|e| panic!("{pattern}: {e}"))
}

fn error(pattern: &str) -> PatternError {
    match GroupPattern::parse(pattern).and_then(|p| p.select(&points(), AttribClass::Point)) {
        Err(e) => e,
        Ok(s) => panic!("{pattern} selected {s:?}"),
    }
}

#[test]
fn numbers_and_inclusive_ranges() {
    assert_eq!(sel("7"), [7]);
    assert_eq!(sel("10-20"), (10..=20).collect::<Vec<_>>());
    assert_eq!(sel("3 1 2"), [3, 1, 2], "in the order named");
    assert_eq!(
        sel("5-2"),
        [5, 4, 3, 2],
        "a range written downward runs downward"
    );
    assert_eq!(sel("38-45"), [38, 39], "past the end is nothing");
}

#[test]
fn steps_and_keep_of_step() {
    // "0-30:2  Match every other number between 0 and 30 (0, 2, 4, 6, ... 30)"
    assert_eq!(sel("0-30:2"), (0..=30).step_by(2).collect::<Vec<_>>());
    // "0-30:2,3  Match every 2 of 3 numbers between 0 and 30 (0, 1, 3, 4, 6, 7, ... 30)"
    let two_of_three: Vec<usize> = (0..=30).filter(|i| i % 3 < 2).collect();
    assert_eq!(&sel("0-30:2,3")[..6], [0, 1, 3, 4, 6, 7]);
    assert_eq!(sel("0-30:2,3"), two_of_three);
}

#[test]
fn negation_and_removal() {
    // "!3-5  Match everything except 3-5."
    let all_but: Vec<usize> = (0..40).filter(|i| !(3..=5).contains(i)).collect();
    assert_eq!(sel("!3-5"), all_but);
    // "0-100:2 ^10-20  every other number between 0 and 100 except 10 to 20"
    let expect: Vec<usize> = (0..40)
        .step_by(2)
        .filter(|i| !(10..=20).contains(i))
        .collect();
    assert_eq!(sel("0-100:2 ^10-20"), expect);
    // "* ^geo1": everything except a group.
    assert_eq!(sel("* ^bottom"), (10..40).collect::<Vec<_>>());
    // Removal acts on what came before only.
    assert_eq!(sel("^bottom 0-2"), [0, 1, 2]);
    assert_eq!(sel("!bottom"), (10..40).collect::<Vec<_>>());
}

#[test]
fn group_names_and_globs() {
    assert_eq!(sel("bottom"), (0..10).collect::<Vec<_>>());
    // Groups in name order: top (30..40) then top2 (0, 1).
    let mut expect: Vec<usize> = (30..40).collect();
    expect.extend([0, 1]);
    assert_eq!(sel("top*"), expect);
    assert_eq!(sel("top?"), [0, 1]);
    assert_eq!(sel("[bt]o*"), sel("bottom top top2"));
    assert!(
        sel("nothing*").is_empty(),
        "a glob that matches no group selects nothing"
    );
}

#[test]
fn attribute_tests() {
    // "@P.y>0 ... all points whose Y component is greater than 0"
    assert_eq!(sel("@P.y>0"), (21..40).collect::<Vec<_>>());
    assert_eq!(sel("@P[0]<=2"), [0, 1, 2]);
    assert_eq!(sel("@P.x==3"), [3]);
    assert_eq!(sel("@P.x=3"), [3]);
    assert_eq!(sel("@P.x!=0 ^4-39"), [1, 2, 3]);
    assert_eq!(sel("@P>=38"), [38, 39], "no component is the first");
    // Strings: `=` with wildcards, quotes around spaces.
    assert_eq!(sel("@name=a"), (0..20).collect::<Vec<_>>());
    assert_eq!(sel("@name=\"piece b\""), (20..40).collect::<Vec<_>>());
    assert_eq!(sel("@name=piece*"), (20..40).collect::<Vec<_>>());
    assert_eq!(sel("@name!=a"), (20..40).collect::<Vec<_>>());
    // Element numbers.
    assert_eq!(sel("@ptnum<3"), [0, 1, 2]);
    assert_eq!(sel("@elemnum>=38"), [38, 39]);
    // Joined with spaces, attribute tests and numbers mix.
    assert_eq!(sel("@P.x<2 5"), [0, 1, 5]);
}

#[test]
fn empty_and_star_select_everything() {
    assert_eq!(sel(""), (0..40).collect::<Vec<_>>());
    assert_eq!(sel("   "), (0..40).collect::<Vec<_>>());
    assert_eq!(sel("*"), (0..40).collect::<Vec<_>>());
    assert!(GroupPattern::parse("*").unwrap().is_everything());
    assert!(!GroupPattern::parse("* ^3").unwrap().is_everything());
    assert_eq!(
        GroupPattern::parse("top").unwrap().single_name(),
        Some("top")
    );
    assert_eq!(GroupPattern::parse("top*").unwrap().single_name(), None);
}

#[test]
fn errors_point_at_the_column() {
    let e = error("0-5 7-x");
    assert_eq!(e.column, 7, "{e}");
    assert!(e.message.contains("last number"), "{e}");
    assert_eq!(error("1-9:0").column, 5);
    assert_eq!(error("0 @Cd>0.5").column, 4, "no attribute Cd: at its name");
    assert!(error("0 @Cd>0.5")
        .message
        .contains("no point attribute `Cd`"));
    assert_eq!(error("@P.q>0").column, 4);
    assert_eq!(error("@P.x>abc").column, 6);
    assert_eq!(error("@P.x").column, 5, "a test needs a comparison");
    assert_eq!(
        error("@name<a").column,
        2,
        "strings compare with = or != only"
    );
    assert_eq!(error("@P[5]>0").column, 2, "P has three components");
    assert_eq!(
        error("@name=\"a b").column,
        7,
        "an open quote, at the quote"
    );
    assert_eq!(error("0-10:2,0").column, 8, "a zero step, at the step");
    assert_eq!(error("3 !").column, 4);
    assert_eq!(error("a,b").column, 2, "commas do not separate patterns");
    assert_eq!(
        error("0 é-2").column,
        4,
        "columns count characters (the `-`)"
    );
}

#[test]
fn other_classes_read_their_own_attributes() {
    let mut g = Geometry::new();
    g.add_points(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE]);
    g.add_polygon(&[0, 1, 2]).unwrap();
    g.add_polygon(&[1, 3, 2]).unwrap();
    let p = GroupPattern::parse("@primnum=1").unwrap();
    assert_eq!(p.select(&g, AttribClass::Primitive).unwrap(), [1]);
    // A point attribute on primitives: by the points' average.
    let by_centroid = GroupPattern::parse("@P.x>0.5").unwrap();
    assert_eq!(by_centroid.select(&g, AttribClass::Primitive).unwrap(), [1]);
    let v = GroupPattern::parse("4-10").unwrap();
    assert_eq!(v.select(&g, AttribClass::Vertex).unwrap(), [4, 5]);
    let grp = GroupPattern::parse("!0")
        .unwrap()
        .group(&g, AttribClass::Point)
        .unwrap();
    assert_eq!(grp.members().collect::<Vec<_>>(), [1, 2, 3]);
}

#[test]
fn a_pattern_has_a_bounded_number_of_terms() {
    let long = "1 ".repeat(MAX_TERMS + 1);
    assert!(GroupPattern::parse(&long)
        .unwrap_err()
        .message
        .contains("terms"));
}

#[test]
fn glob_forms() {
    assert!(glob("*.bgeo", "a.bgeo"));
    assert!(glob("p?t", "pat"));
    assert!(!glob("p?t", "part"));
    assert!(glob("[gG]eo*", "Geo1"));
    assert!(!glob("[gG]eo*", "neo"));
    assert!(!glob("a*a*a*a*a*b", &"a".repeat(200)));
}

#[test]
fn name_patterns_add_and_remove() {
    let names = ["P", "Cd", "uv", "uv2", "N"];
    assert_eq!(match_names("*", names), names);
    assert_eq!(match_names("* ^P", names), ["Cd", "uv", "uv2", "N"]);
    assert_eq!(match_names("uv* ^uv2 N", names), ["uv", "N"]);
    assert!(match_names("", names).is_empty());
}
