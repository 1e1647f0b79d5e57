//! The wrangle's memory budget: arrays, strings and queued geometry a
//! snippet asks for are refused with the element, the line and the size
//! before they are allocated, and a long fill stops on cancel.

mod common;

use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use common::{four_points, run_with};
use geode_geo::{AttribClass, Geometry};
use geode_vex::RunError;

const MB: u64 = 1 << 20;

fn never() -> bool {
    false
}

/// The error of `src` over `class` elements of four points within `budget`,
/// and how long the refusal took.
fn refused(src: &str, class: AttribClass, budget: u64) -> (String, Duration) {
    let t0 = Instant::now();
    let r = run_with(src, class, &four_points(), &[], &never, budget);
    let took = t0.elapsed();
    match r {
        Ok(_) => panic!("{src}: ran within {budget} bytes"),
        Err(e) => (e.to_string(), took),
    }
}

#[test]
fn a_huge_resize_is_refused_before_it_allocates() {
    let (msg, took) = refused(
        "int a[];\nresize(a, 2000000000);",
        AttribClass::Detail,
        512 * MB,
    );
    assert_eq!(
        msg,
        "element 0 (line 2, column 1): resize to 2000000000 elements would need 8.0 GB, \
         more than the 537 MB left of the memory budget of 537 MB (GEODE_MEMORY_MB)"
    );
    assert!(took < Duration::from_secs(1), "{took:?}");
}

#[test]
fn a_string_doubling_forever_is_refused_at_the_budget() {
    let (msg, _) = refused(
        "string s = \"ab\";\nwhile (1) {\n    s = s + s;\n}",
        AttribClass::Detail,
        64 * MB,
    );
    assert!(
        // Refused at the join (column 11) or at the copy it is assigned
        // by (column 7), whichever first outgrows what is left.
        (msg.starts_with("element 0 (line 3, column 11): ")
            || msg.starts_with("element 0 (line 3, column 7): "))
            && msg.ends_with("of the memory budget of 67.1 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
}

#[test]
fn arrays_per_point_are_refused_in_total() {
    // One point's array fits; the four points' together do not.
    let mut g = Geometry::new();
    g.add_points(&vec![[0.0; 3].into(); 64]);
    let r = run_with(
        "int a[];\nresize(a, 1000000);",
        AttribClass::Point,
        &g,
        &[],
        &never,
        32 * MB,
    );
    let msg = r.expect_err("refused").to_string();
    assert!(
        msg.contains(
            "(line 2, column 1): resize to 1000000 elements would need 4.0 MB, more than the "
        ) && msg.ends_with("left of the memory budget of 33.6 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    // Within the budget, the same run completes.
    assert!(run_with(
        "int a[];\nresize(a, 1000000);",
        AttribClass::Point,
        &g,
        &[],
        &never,
        1024 * MB
    )
    .is_ok());
}

#[test]
fn growing_an_array_by_index_is_reserved() {
    let (msg, _) = refused(
        "int a[];\na[1999999999] = 1;",
        AttribClass::Detail,
        256 * MB,
    );
    assert_eq!(
        msg,
        "element 0 (line 2, column 15): setting element 1999999999 would need 8.0 GB, \
         more than the 268 MB left of the memory budget of 268 MB (GEODE_MEMORY_MB)"
    );
}

#[test]
fn a_format_wider_than_the_budget_is_refused() {
    let (msg, _) = refused(
        "string s = sprintf(\"%2000000000d\", 1);",
        AttribClass::Detail,
        64 * MB,
    );
    assert!(
        msg.starts_with("element 0 (line 1, column 12): formatting a string of 4000000")
            && msg.contains("would need 4.0 GB"),
        "{msg}"
    );
}

#[test]
fn endless_new_points_are_refused_at_the_budget() {
    let (msg, took) = refused(
        "for (int i = 0; i < 2000000000; i++) {\n    addpoint(0, {0, 0, 0});\n}",
        AttribClass::Detail,
        16 * MB,
    );
    assert!(
        msg.starts_with("element 0 (line 2, column 5): queueing ")
            && msg.contains(" more geometry changes would need ")
            && msg.ends_with("of the memory budget of 16.8 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    assert!(took < Duration::from_secs(5), "{took:?}");
}

#[test]
fn a_long_fill_stops_on_cancel() {
    // Asked for once at the batch's start, then between chunks of the fill.
    let polls = AtomicU32::new(0);
    let cancel = || polls.fetch_add(1, Ordering::Relaxed) >= 1;
    let r = run_with(
        "int a[];\nresize(a, 1000000000);",
        AttribClass::Detail,
        &four_points(),
        &[],
        &cancel,
        u64::MAX,
    );
    assert_eq!(r.err(), Some(RunError::Cancelled));
}

#[test]
fn ordinary_arrays_and_strings_run_within_a_small_budget() {
    let (g, _) = run_with(
        "int a[];\nfor (int i = 0; i < 1000; i++) push(a, i);\ns@s = sprintf(\"%d\", len(a));\ni@n = a[-1];",
        AttribClass::Point,
        &four_points(),
        &[],
        &never,
        16 * MB,
    )
    .expect("fits");
    let n = g.attribs(AttribClass::Point).get("n").expect("n");
    assert_eq!(n.as_i32().expect("ints"), &[999, 999, 999, 999]);
}

#[test]
fn a_width_past_any_integer_is_refused_not_a_panic() {
    for fmt in [
        "%99999999999999999999d",
        "%18446744073709551615d",
        "%.99999999999999999999f",
    ] {
        let (msg, _) = refused(
            &format!("string s = sprintf(\"{fmt}\", 1);"),
            AttribClass::Detail,
            64 * MB,
        );
        assert!(msg.contains("formatting a string of "), "{fmt}: {msg}");
    }
}

#[test]
fn splitting_a_huge_string_is_reserved() {
    let (msg, _) = refused(
        "string s = \"a,\";\nfor (int i = 0; i < 22; i++) s = s + s;\nstring p[] = split(s, \",\");",
        AttribClass::Detail,
        64 * MB,
    );
    assert!(
        msg.starts_with(
            "element 0 (line 3, column 14): splitting a string of 8388608 bytes would need "
        ),
        "{msg}"
    );
}

#[test]
fn the_first_refusal_stops_every_batch() {
    // 40,000 points each asking for 8 MB: refused within the first batches,
    // and the others stop instead of running to the end.
    let mut g = Geometry::new();
    g.add_points(&vec![[0.0; 3].into(); 40_000]);
    let t0 = Instant::now();
    let r = run_with(
        "int a[];\nresize(a, 2000000);\ni[]@a = a;",
        AttribClass::Point,
        &g,
        &[],
        &never,
        64 * MB,
    );
    let msg = r.expect_err("refused").to_string();
    assert!(
        msg.contains("resize to 2000000 elements would need 8.0 MB"),
        "{msg}"
    );
    assert!(t0.elapsed() < Duration::from_secs(3), "{:?}", t0.elapsed());
}
