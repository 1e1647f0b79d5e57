//! Compiling a wrangle's snippet without its input geometry (`geode check`):
//! what an attribute the snippet reads holds is unknown, so an error counts
//! only if no typing of those attributes that a short search tries makes it
//! go away (otherwise a snippet reading a vector attribute as `@rest.x`
//! would be refused for lack of the geometry that declares it).

use geode_geo::{AttribClass, AttribType, AttribValue, Attribute, Geometry, TypeInfo};
use geode_vex::{BindSpec, Channel, CompileError};

/// The attribute types tried for an unknown attribute (VEX reads a
/// quaternion as a vector4, so that is tried once).
const TYPES: [AttribType; 12] = [
    AttribType::Float,
    AttribType::Vec3,
    AttribType::Int,
    AttribType::String,
    AttribType::Vec4,
    AttribType::Vec2,
    AttribType::Mat3,
    AttribType::Mat4,
    AttribType::FloatArray,
    AttribType::IntArray,
    AttribType::Vec3Array,
    AttribType::StringArray,
];

/// At most this many attribute names are typed by the search.
const MAX_NAMES: usize = 48;
/// The search's bounds (compiles, and bytes of snippet compiled): past
/// them the snippet is given the benefit of the doubt.
const MAX_COMPILES: usize = 600;
const MAX_BYTES: usize = 32 << 20;

/// What a snippet is compiled against when its inputs are not cooked.
pub struct Unknown<'a> {
    pub run_over: AttribClass,
    /// Per declared input, whether a wire feeds it (input 1 always does).
    pub wired: &'a [bool],
    pub channels: &'a dyn Fn(&str) -> Option<Channel>,
    pub channel_names: &'a dyn Fn() -> Vec<String>,
    pub frame: f64,
    pub time: f64,
}

/// Ok when the snippet compiles against some typing of the attributes it
/// names (none first: VEX's defaults), else the latest first error any
/// typing tried gives (what stands once the attributes before it are
/// typed as they compile).
pub fn compiles(src: &str, u: &Unknown) -> Result<(), CompileError> {
    let compile = |typing: &[(String, usize, Option<AttribType>)]| {
        let probe = probe(typing);
        let inputs = (0..4)
            .map(|i| (i == 0 || u.wired.get(i).copied().unwrap_or(false)).then_some(&probe))
            .collect();
        let spec = BindSpec {
            run_over: u.run_over,
            inputs,
            channels: u.channels,
            channel_names: u.channel_names,
            frame: u.frame,
            time: u.time,
        };
        geode_vex::compile(src, &spec).map(|_| ())
    };
    let mut typing: Vec<(String, usize, Option<AttribType>)> = attribute_names(src)
        .into_iter()
        .map(|(n, line)| (n, line, None))
        .collect();
    let first = match compile(&typing) {
        Ok(()) => return Ok(()),
        Err(e) => e,
    };
    let mut best = (first.pos.line, first.pos.col);
    let mut error = first;
    let (mut compiles, mut bytes) = (1, src.len());
    // Greedy: retype one attribute at a time, keeping a change that moves
    // the first error later; only attributes named on or before the
    // error's line can have caused it.
    'search: loop {
        for i in 0..typing.len() {
            if typing[i].1 as u32 > best.0 {
                continue;
            }
            for ty in TYPES {
                if typing[i].2 == Some(ty) {
                    continue;
                }
                if compiles >= MAX_COMPILES || bytes >= MAX_BYTES {
                    return Ok(());
                }
                compiles += 1;
                bytes += src.len();
                let old = typing[i].2.replace(ty);
                match compile(&typing) {
                    Ok(()) => return Ok(()),
                    Err(e) if (e.pos.line, e.pos.col) > best => {
                        best = (e.pos.line, e.pos.col);
                        error = e;
                        continue 'search;
                    }
                    Err(_) => typing[i].2 = old,
                }
            }
        }
        return Err(error);
    }
}

/// A geometry with no elements carrying each typed name on every class.
fn probe(typing: &[(String, usize, Option<AttribType>)]) -> Geometry {
    let mut g = Geometry::new();
    for (name, _, ty) in typing {
        let Some(ty) = ty else { continue };
        for class in [
            AttribClass::Point,
            AttribClass::Vertex,
            AttribClass::Primitive,
            AttribClass::Detail,
        ] {
            let len = g.attribs(class).len();
            let a = Attribute::new(AttribValue::zero(*ty), TypeInfo::None, len);
            // `P` stays the vector it must be.
            let _ = g.set_attrib(class, name, a);
        }
    }
    g
}

/// The names a snippet may read as attributes, each once with the line it
/// first appears on: every `@name` (`@opinput1_name` also as `name`) and
/// every string literal that is a name (`point(1, "Cd", i)`); comments
/// skipped.
fn attribute_names(src: &str) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = Vec::new();
    let mut add = |name: &str, line: usize| {
        let is_name = name
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if is_name && out.len() < MAX_NAMES && !out.iter().any(|(n, _)| n == name) {
            out.push((name.to_owned(), line));
        }
    };
    let b = src.as_bytes();
    let (mut i, mut line) = (0, 1);
    let word_end = |mut j: usize| {
        while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
            j += 1;
        }
        j
    };
    while i < b.len() {
        match b[i] {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < b.len() && !(b[i] == b'*' && b.get(i + 1) == Some(&b'/')) {
                    line += usize::from(b[i] == b'\n');
                    i += 1;
                }
                i += 2;
            }
            b'@' => {
                let end = word_end(i + 1);
                let name = &src[i + 1..end];
                add(name, line);
                if let Some((k, attrib)) = name
                    .strip_prefix("opinput")
                    .and_then(|rest| rest.split_once('_'))
                {
                    if k.parse::<usize>().is_ok() {
                        add(attrib, line);
                    }
                }
                i = end.max(i + 1);
            }
            b'"' => {
                let start = i + 1;
                i = start;
                while i < b.len() && b[i] != b'"' {
                    if b[i] == b'\\' {
                        i += 1;
                    }
                    line += usize::from(b.get(i) == Some(&b'\n'));
                    i += 1;
                }
                if let Some(s) = src.get(start..i.min(b.len())) {
                    add(s, line);
                }
                i += 1;
            }
            _ => i += 1,
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(src: &str) -> Result<(), CompileError> {
        let none = |_: &str| None;
        let names = Vec::new;
        compiles(
            src,
            &Unknown {
                run_over: AttribClass::Point,
                wired: &[true, true, false, false],
                channels: &none,
                channel_names: &names,
                frame: 1.0,
                time: 0.0,
            },
        )
    }

    #[test]
    fn names_are_found_once_outside_comments() {
        let names = attribute_names(
            "// @hidden \"no\"\nv@P += @rest.x * point(1, \"Cd\", 0);\n/* @gone\n */ f@w = @opinput1_mass + @rest;",
        );
        let names: Vec<(&str, usize)> = names.iter().map(|(n, l)| (n.as_str(), *l)).collect();
        assert_eq!(
            names,
            vec![
                ("P", 2),
                ("rest", 2),
                ("Cd", 2),
                ("w", 4),
                ("opinput1_mass", 4),
                ("mass", 4)
            ]
        );
    }

    /// The snippet compiled against a geometry without attributes.
    fn plain(src: &str) -> Result<(), CompileError> {
        let none = |_: &str| None;
        let names = Vec::new;
        let g = Geometry::new();
        let spec = BindSpec {
            run_over: AttribClass::Point,
            inputs: vec![Some(&g), Some(&g)],
            channels: &none,
            channel_names: &names,
            frame: 1.0,
            time: 0.0,
        };
        geode_vex::compile(src, &spec).map(|_| ())
    }

    #[test]
    fn an_error_some_attribute_type_explains_is_not_reported() {
        // Each fails with the attributes VEX's defaults make floats, and
        // compiles once the search types them (a string, a float array,
        // both at once).
        for src in [
            "s@out = @label;",
            "f@a = @weights[0];",
            "string s = @name2 + \"x\";\nf@w = @weights[1] * 2;",
            "// \"a\"\ns@out = @opinput1_label + \"!\";",
        ] {
            assert!(plain(src).is_err(), "{src} fails without attributes");
            assert!(check(src).is_ok(), "{src}: {:?}", check(src));
        }
    }

    #[test]
    fn an_error_no_typing_explains_is_reported_where_it_is() {
        let e = check("f@a = 1;\nf@b = @a +;").unwrap_err();
        assert_eq!((e.pos.line, e.pos.col), (2, 11), "{e}");
        let e = check("v@P = @rest.x;\nf@x = nosuchfunction(@rest);").unwrap_err();
        assert_eq!(e.pos.line, 2, "{e}");
        assert!(e.msg.contains("nosuchfunction"), "{e}");
    }
}
