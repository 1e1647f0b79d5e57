//! String functions (SideFX's "Strings" category), C-style formatting
//! (`sprintf`, `printf`), conversions, and the string join operator.
//! Indices count characters, not bytes. Regular expressions use
//! `regex-lite`, whose matching is linear in the text (no pattern can hang
//! a cook); compiled patterns are kept per thread.

use std::cell::RefCell;
use std::collections::HashMap;

use super::{a, form, lane, Category, Function, Ret, I, S, SA, T};
use crate::effect::EffectKind;
use crate::program::{Host, Lane, Request, Stop};
use crate::ty::Ty;
use crate::value::{HeapBytes, Val};

const C: Category = Category::Strings;
const O: Category = Category::Conversion;

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("strlen", C, "Number of characters of a string.", &[
        form(Ret::Is(Ty::Int), &[a(S, "s")], strlen),
    ]),
    lane("concat", C, "The strings joined.", &[
        form(Ret::Is(Ty::Str), &[a(S, "a"), a(S, "b")], concat).many().bytes(concat_bytes),
    ]),
    lane("join", C, "The strings of an array joined with a separator (a space by default).", &[
        form(Ret::Is(Ty::Str), &[a(SA, "strings"), a(S, "separator")], join).opt(1).bytes(join_bytes),
    ]),
    lane("split", C, "The pieces between separator characters (whitespace by default); with maxsplits, at most that many splits.", &[
        form(Ret::Is(Ty::Array(crate::ty::Elem::Str)), &[a(S, "s"), a(S, "separators"), a(I, "maxsplits")], split).opt(2).bytes(split_bytes),
    ]),
    lane("startswith", C, "1 if s starts with prefix.", &[
        form(Ret::Is(Ty::Int), &[a(S, "s"), a(S, "prefix")], startswith),
    ]),
    lane("endswith", C, "1 if s ends with suffix.", &[
        form(Ret::Is(Ty::Int), &[a(S, "s"), a(S, "suffix")], endswith),
    ]),
    lane("toupper", C, "The string in upper case.", &[
        form(Ret::Is(Ty::Str), &[a(S, "s")], toupper),
    ]),
    lane("tolower", C, "The string in lower case.", &[
        form(Ret::Is(Ty::Str), &[a(S, "s")], tolower),
    ]),
    lane("strip", C, "The string without leading and trailing whitespace (or the given characters).", &[
        form(Ret::Is(Ty::Str), &[a(S, "s"), a(S, "chars")], strip).opt(1),
    ]),
    lane("lstrip", C, "The string without leading whitespace (or the given characters).", &[
        form(Ret::Is(Ty::Str), &[a(S, "s"), a(S, "chars")], lstrip).opt(1),
    ]),
    lane("rstrip", C, "The string without trailing whitespace (or the given characters).", &[
        form(Ret::Is(Ty::Str), &[a(S, "s"), a(S, "chars")], rstrip).opt(1),
    ]),
    lane("replace", C, "The string with every occurrence of old replaced by new (at most count when given).", &[
        form(Ret::Is(Ty::Str), &[a(S, "s"), a(S, "old"), a(S, "new"), a(I, "count")], replace).opt(1).bytes(replace_bytes),
    ]),
    lane("chr", C, "The one-character string of a Unicode code point.", &[
        form(Ret::Is(Ty::Str), &[a(I, "value")], chr),
    ]),
    lane("ord", C, "The Unicode code point of a string's first character.", &[
        form(Ret::Is(Ty::Int), &[a(S, "s")], ord),
    ]),
    lane("match", C, "1 if the string matches a glob pattern (* and ? wildcards).", &[
        form(Ret::Is(Ty::Int), &[a(S, "pattern"), a(S, "s")], glob_match),
    ]),
    lane("re_match", C, "1 if the regular expression matches the whole string.", &[
        form(Ret::Is(Ty::Int), &[a(S, "regex"), a(S, "s")], re_match),
    ]),
    lane("re_find", C, "The first match of the regular expression in the string (\"\" if none).", &[
        form(Ret::Is(Ty::Str), &[a(S, "regex"), a(S, "s")], re_find),
    ]),
    lane("re_findall", C, "Every match of the regular expression in the string.", &[
        form(Ret::Is(Ty::Array(crate::ty::Elem::Str)), &[a(S, "regex"), a(S, "s")], re_findall),
    ]),
    lane("re_replace", C, "The string with matches of the regular expression replaced (\\1 or $1 name groups).", &[
        form(Ret::Is(Ty::Str), &[a(S, "regex"), a(S, "replacement"), a(S, "s"), a(I, "count")], re_replace).opt(1),
    ]),
    lane("re_split", C, "The pieces between matches of the regular expression.", &[
        form(Ret::Is(Ty::Array(crate::ty::Elem::Str)), &[a(S, "regex"), a(S, "s")], re_split),
    ]),
    lane("sprintf", O, "Formats values as C's printf: %d %i %u %x %X %o %f %e %g %s %c %%, flags, width and precision; vectors print as {x,y,z}.", &[
        form(Ret::Is(Ty::Str), &[a(S, "format"), a(T::Any, "value")], sprintf_lane).opt(1).many().bytes(format_bytes),
    ]),
    lane("printf", O, "Prints formatted values to the cook's log, in element order.", &[
        form(Ret::Is(Ty::Void), &[a(S, "format"), a(T::Any, "value")], printf).opt(1).many().bytes(format_bytes),
    ]),
    lane("error", O, "Stops the cook with the formatted message as its error (SideFX: \"reports a custom runtime VEX error\").", &[
        form(Ret::Is(Ty::Void), &[a(S, "format"), a(T::Any, "value")], error).opt(1).many().bytes(format_bytes),
    ]),
    lane("itoa", O, "The int as decimal text.", &[
        form(Ret::Is(Ty::Str), &[a(I, "value")], itoa),
    ]),
    lane("atof", O, "The float the text starts with (0 if none).", &[
        form(Ret::Is(Ty::Float), &[a(S, "s")], atof),
    ]),
    lane("atoi", O, "The int the text starts with (0 if none), in base 10 or the given base (0: from the prefix).", &[
        form(Ret::Is(Ty::Int), &[a(S, "s"), a(I, "base")], atoi).opt(1),
    ]),
];

/// The operators on strings lowered to calls.
pub mod intrinsics {
    use super::super::Callee;

    pub const CONCAT: Callee = Callee {
        name: "+",
        lane: super::concat,
        bytes: Some(super::concat_bytes),
    };
    pub const FORMAT: Callee = Callee {
        name: "string",
        lane: super::sprintf_lane,
        bytes: Some(super::format_bytes),
    };
    pub const ATOI: Callee = Callee {
        name: "int",
        lane: super::atoi,
        bytes: None,
    };
    pub const ATOF: Callee = Callee {
        name: "float",
        lane: super::atof,
        bytes: None,
    };
}

fn strlen(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(a[0].s().chars().count() as i32))
}

fn concat(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::S(a.iter().map(|v| v.s()).collect()))
}

fn concat_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let total: u64 = a.iter().map(|v| v.s().len() as u64).sum();
    Some((Request::Concat(total), total))
}

fn join(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let sep = a.get(1).map_or(" ", Val::s);
    Ok(Val::S(match &a[0] {
        Val::AS(v) => v.join(sep),
        _ => String::new(),
    }))
}

fn join_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let sep = a.get(1).map_or(1, |s| s.s().len()) as u64;
    let total = match &a[0] {
        Val::AS(v) => v.iter().map(|s| s.len() as u64 + sep).sum(),
        _ => 0,
    };
    Some((Request::Concat(total), total))
}

fn split(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[0].s();
    let max = a.get(2).map_or(-1, Val::i);
    let sep = a.get(1).map(Val::s).filter(|s| !s.is_empty());
    let mut parts = Vec::new();
    let mut rest = s;
    loop {
        if parts.len() % super::support::FILL_CHUNK == super::support::FILL_CHUNK - 1
            && lane.host.cancelled()
        {
            return Err(Stop::Cancelled);
        }
        let is_sep = |c: char| match sep {
            Some(sep) => sep.contains(c),
            None => c.is_whitespace(),
        };
        rest = rest.trim_start_matches(is_sep);
        if rest.is_empty() {
            break;
        }
        if max >= 0 && parts.len() as i32 == max {
            parts.push(rest.to_string());
            break;
        }
        let end = rest.find(is_sep).unwrap_or(rest.len());
        parts.push(rest[..end].to_string());
        rest = &rest[end..];
    }
    Ok(Val::AS(parts))
}

fn split_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    // At most a piece per two characters, each a string's slot and the
    // smallest allocation.
    let len = a[0].s().len() as u64;
    let pieces = len / 2 + 1;
    let bytes = pieces * (std::mem::size_of::<String>() as u64 + 16) + len;
    Some((Request::Split(len), bytes))
}

fn startswith(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(i32::from(a[0].s().starts_with(a[1].s()))))
}

fn endswith(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(i32::from(a[0].s().ends_with(a[1].s()))))
}

fn toupper(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::S(a[0].s().to_uppercase()))
}

fn tolower(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::S(a[0].s().to_lowercase()))
}

/// Whether `c` is stripped: the given characters, else whitespace.
fn strippable(chars: Option<&str>) -> impl Fn(char) -> bool + '_ {
    move |c| chars.map_or(c.is_whitespace(), |set| set.contains(c))
}

fn strip(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let set = a.get(1).map(Val::s);
    Ok(Val::S(a[0].s().trim_matches(strippable(set)).to_string()))
}

fn lstrip(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let set = a.get(1).map(Val::s);
    Ok(Val::S(
        a[0].s().trim_start_matches(strippable(set)).to_string(),
    ))
}

fn rstrip(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let set = a.get(1).map(Val::s);
    Ok(Val::S(
        a[0].s().trim_end_matches(strippable(set)).to_string(),
    ))
}

fn replace(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (s, old, new) = (a[0].s(), a[1].s(), a[2].s());
    if old.is_empty() {
        return Ok(Val::S(s.to_string()));
    }
    Ok(Val::S(match a.get(3).map(Val::i) {
        Some(n) if n >= 0 => s.replacen(old, new, n as usize),
        _ => s.replace(old, new),
    }))
}

fn replace_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let (s, old, new) = (a[0].s(), a[1].s(), a[2].s());
    let hits = if old.is_empty() {
        0
    } else {
        (s.len() / old.len()) as u64
    };
    let total = s.len() as u64 + hits * new.len() as u64;
    Some((Request::Concat(total), total))
}

fn chr(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::S(
        u32::try_from(a[0].i())
            .ok()
            .and_then(char::from_u32)
            .map(String::from)
            .unwrap_or_default(),
    ))
}

fn ord(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(a[0].s().chars().next().map_or(0, |c| c as i32)))
}

fn glob_match(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(i32::from(crate::pattern::glob(a[0].s(), a[1].s()))))
}

thread_local! {
    static PATTERNS: RefCell<HashMap<String, Result<regex_lite::Regex, String>>> =
        RefCell::new(HashMap::new());
}

/// Runs `f` with the compiled pattern, compiled once per thread.
fn with_regex<R>(pattern: &str, f: impl FnOnce(&regex_lite::Regex) -> R) -> Result<R, Stop> {
    PATTERNS.with(|cache| {
        let mut cache = cache.borrow_mut();
        if cache.len() > 256 {
            cache.clear();
        }
        let compiled = cache
            .entry(pattern.to_string())
            .or_insert_with(|| regex_lite::Regex::new(pattern).map_err(|e| e.to_string()));
        match compiled {
            Ok(re) => Ok(f(re)),
            Err(e) => Err(Stop::Msg(format!(
                "invalid regular expression \"{pattern}\": {e}"
            ))),
        }
    })
}

fn re_match(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[1].s();
    let whole = with_regex(a[0].s(), |re| {
        re.find(s)
            .is_some_and(|m| m.start() == 0 && m.end() == s.len())
            || re.captures_iter(s).any(|c| {
                c.get(0)
                    .is_some_and(|m| m.start() == 0 && m.end() == s.len())
            })
    })?;
    // A pattern that matches the whole string only through a longer
    // alternative: anchor it.
    let anchored = if whole {
        true
    } else {
        with_regex(&format!("^(?:{})$", a[0].s()), |re| re.is_match(s))?
    };
    Ok(Val::I(i32::from(anchored)))
}

fn re_find(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[1].s();
    let found = with_regex(a[0].s(), |re| {
        re.find(s)
            .map(|m| m.as_str().to_string())
            .unwrap_or_default()
    })?;
    Ok(Val::S(found))
}

fn re_findall(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[1].s();
    let found = with_regex(a[0].s(), |re| {
        re.find_iter(s).map(|m| m.as_str().to_string()).collect()
    })?;
    Ok(Val::AS(found))
}

fn re_replace(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    // Python's and VEX's `\1` group references are regex-lite's `${1}`.
    let mut replacement = String::new();
    let mut it = a[1].s().chars().peekable();
    while let Some(c) = it.next() {
        let next = it.peek().copied();
        match (c, next) {
            ('\\', Some(d)) if d.is_ascii_digit() => {
                it.next();
                replacement.push_str(&format!("${{{d}}}"));
            }
            ('$', d) if !matches!(d, Some(d) if d.is_ascii_digit() || d == '{') => {
                replacement.push_str("$$")
            }
            (c, _) => replacement.push(c),
        }
    }
    let s = a[2].s();
    let limit = a.get(3).map_or(0, |v| v.i().max(0) as usize);
    let out = with_regex(a[0].s(), |re| {
        re.replacen(s, limit, replacement.as_str()).into_owned()
    })?;
    Ok(Val::S(out))
}

fn re_split(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[1].s();
    // "a,b, will only split into two strings": empty pieces are dropped.
    let parts = with_regex(a[0].s(), |re| {
        re.split(s)
            .filter(|p| !p.is_empty())
            .map(str::to_string)
            .collect()
    })?;
    Ok(Val::AS(parts))
}

fn itoa(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::S(a[0].i().to_string()))
}

fn atof(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[0].s();
    Ok(Val::float(
        s.trim()
            .parse::<f32>()
            .unwrap_or_else(|_| leading_number(s)),
    ))
}

fn atoi(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = a[0].s().trim();
    let base = a.get(1).map_or(10, Val::i);
    let (neg, digits) = match s.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let (base, digits) = match base {
        0 => {
            if let Some(h) = digits
                .strip_prefix("0x")
                .or_else(|| digits.strip_prefix("0X"))
            {
                (16, h)
            } else if digits.len() > 1 && digits.starts_with('0') {
                (8, &digits[1..])
            } else {
                (10, digits)
            }
        }
        16 => (
            16,
            digits
                .strip_prefix("0x")
                .or_else(|| digits.strip_prefix("0X"))
                .unwrap_or(digits),
        ),
        b if (2..=36).contains(&b) => (b as u32, digits),
        _ => (10, digits),
    };
    let end = digits
        .char_indices()
        .find(|(_, c)| !c.is_digit(base))
        .map_or(digits.len(), |(i, _)| i);
    let v = i64::from_str_radix(&digits[..end], base).unwrap_or(0);
    let v = if neg { -v } else { v };
    Ok(Val::I(
        v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
    ))
}

/// The number at the start of `s` (`atof("3.5abc")` is 3.5), else 0.
fn leading_number(s: &str) -> f32 {
    let s = s.trim_start();
    let end = s
        .char_indices()
        .take_while(|(i, c)| {
            c.is_ascii_digit() || *c == '.' || (*i == 0 && (*c == '-' || *c == '+'))
        })
        .map(|(i, c)| i + c.len_utf8())
        .last()
        .unwrap_or(0);
    s[..end].parse().unwrap_or(0.0)
}

fn sprintf_lane(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::S(sprintf(a[0].s(), &a[1..])))
}

fn printf(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let text = sprintf(a[0].s(), &a[1..]);
    lane.host.queue(EffectKind::Print(text))?;
    Ok(Val::I(0))
}

fn error(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Err(Stop::Msg(sprintf(a[0].s(), &a[1..])))
}

fn format_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let args: u64 = a.iter().map(|v| v.heap_bytes() + 32).sum();
    let total = sprintf_bytes(a[0].s()).saturating_add(args);
    Some((Request::Format(total), total))
}

/// An upper bound on what `sprintf`'s widths and precisions add: every
/// number in a conversion's flags, twice (a conversion is formatted, then
/// copied into the result).
fn sprintf_bytes(fmt: &str) -> u64 {
    let mut total = fmt.len() as u64;
    let mut number: u64 = 0;
    let mut in_spec = false;
    for c in fmt.chars() {
        match (in_spec, c) {
            (false, '%') => in_spec = true,
            (true, '0'..='9') => {
                number = number
                    .saturating_mul(10)
                    .saturating_add(u64::from(c as u8 - b'0'));
            }
            (true, '.' | '-' | '+' | ' ' | '#') => {
                total = total.saturating_add(number.saturating_mul(2));
                number = 0;
            }
            (true, _) => {
                total = total.saturating_add(number.saturating_mul(2));
                number = 0;
                in_spec = false;
            }
            _ => {}
        }
    }
    total.saturating_add(number.saturating_mul(2))
}

/// A value as `%s` and `%g` print it: floats shortest, vectors and arrays
/// in braces.
pub fn fmt_val(v: &Val) -> String {
    let list = |items: Vec<String>| format!("{{{}}}", items.join(", "));
    match v {
        Val::I(i) => i.to_string(),
        Val::S(s) => s.clone(),
        Val::F(a, 1) => fmt_float(a[0]),
        Val::F(a, n) => list(a[..*n as usize].iter().map(|x| fmt_float(*x)).collect()),
        Val::AI(a) => list(a.iter().map(|x| x.to_string()).collect()),
        Val::AS(a) => list(a.iter().map(|x| format!("\"{x}\"")).collect()),
        Val::AF(a, w) => list(
            a.chunks((*w).max(1) as usize)
                .map(|c| {
                    if c.len() == 1 {
                        fmt_float(c[0])
                    } else {
                        fmt_val(&Val::vec(c))
                    }
                })
                .collect(),
        ),
    }
}

/// The shortest decimal that reads back as the same float.
fn fmt_float(x: f32) -> String {
    format!("{x}")
}

/// One conversion's flags, width and precision.
#[derive(Default)]
struct Spec {
    left: bool,
    zero: bool,
    plus: bool,
    space: bool,
    alt: bool,
    width: usize,
    prec: Option<usize>,
}

/// C's `%e`: one digit, a point, `prec` digits, `e`, a sign and at least
/// two exponent digits.
fn fmt_exp(x: f64, prec: usize, upper: bool) -> String {
    let s = format!("{x:.prec$e}");
    let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let e = if upper { 'E' } else { 'e' };
    format!(
        "{mant}{e}{}{:02}",
        if exp < 0 { '-' } else { '+' },
        exp.abs()
    )
}

/// C's `%g`: `prec` significant digits (6 by default, 0 means 1), `%e`
/// when the exponent is below -4 or at least the precision, trailing zeros
/// removed unless `#`.
fn fmt_general(x: f64, prec: Option<usize>, alt: bool, upper: bool) -> String {
    let p = prec.unwrap_or(6).max(1);
    if x == 0.0 {
        return if alt {
            format!("{:.*}", p - 1, 0.0)
        } else {
            "0".into()
        };
    }
    if !x.is_finite() {
        return fmt_special(x, upper);
    }
    let exp = fmt_exp(x, p - 1, false);
    let e: i32 = exp
        .rsplit_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    let trim = |s: String| -> String {
        if alt || !s.contains('.') {
            return s;
        }
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    if e < -4 || e >= p as i32 {
        let (mant, tail) = exp.split_once('e').unwrap_or((&exp, ""));
        let mant = trim(mant.to_string());
        let e = if upper { 'E' } else { 'e' };
        format!("{mant}{e}{tail}")
    } else {
        let decimals = (p as i32 - 1 - e).max(0) as usize;
        trim(format!("{x:.decimals$}"))
    }
}

fn fmt_special(x: f64, upper: bool) -> String {
    let s = if x.is_nan() {
        "nan"
    } else if x > 0.0 {
        "inf"
    } else {
        "-inf"
    };
    if upper {
        s.to_uppercase()
    } else {
        s.into()
    }
}

/// One number converted by `conv`.
fn fmt_number(x: f64, int: Option<i64>, conv: char, spec: &Spec) -> String {
    let sign = |neg: bool| {
        if neg {
            "-"
        } else if spec.plus {
            "+"
        } else if spec.space {
            " "
        } else {
            ""
        }
    };
    let whole = || int.unwrap_or(x as i64);
    match conv {
        'd' | 'i' => {
            let v = whole();
            let digits = v.unsigned_abs().to_string();
            let digits = match spec.prec {
                Some(p) if digits.len() < p => format!("{digits:0>p$}"),
                _ => digits,
            };
            format!("{}{digits}", sign(v < 0))
        }
        'u' => (whole() as i32 as u32).to_string(),
        'x' | 'X' | 'o' => {
            // C prints the 32-bit two's complement of negative ints.
            let v = whole() as i32 as u32;
            let (body, prefix) = match conv {
                'x' => (format!("{v:x}"), "0x"),
                'X' => (format!("{v:X}"), "0X"),
                _ => (format!("{v:o}"), "0"),
            };
            if spec.alt && v != 0 {
                format!("{prefix}{body}")
            } else {
                body
            }
        }
        'c' => char::from_u32(whole() as u32)
            .map(String::from)
            .unwrap_or_default(),
        'f' | 'F' => {
            if !x.is_finite() {
                return fmt_special(x, conv == 'F');
            }
            let p = spec.prec.unwrap_or(6);
            format!("{}{:.p$}", sign(x.is_sign_negative() && x != 0.0), x.abs())
        }
        'e' | 'E' => {
            if !x.is_finite() {
                return fmt_special(x, conv == 'E');
            }
            let body = fmt_exp(x.abs(), spec.prec.unwrap_or(6), conv == 'E');
            format!("{}{body}", sign(x < 0.0))
        }
        _ => {
            let body = fmt_general(x.abs(), spec.prec, spec.alt, conv == 'G');
            format!("{}{body}", sign(x < 0.0))
        }
    }
}

/// C-style formatting with VEX's additions: a vector or array argument
/// formats each component with the conversion, in braces.
pub fn sprintf(fmt: &str, args: &[Val]) -> String {
    let mut out = String::new();
    let mut it = fmt.chars().peekable();
    let mut next = args.iter();
    while let Some(c) = it.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let mut spec = Spec::default();
        while let Some(&d) = it.peek() {
            match d {
                '-' => spec.left = true,
                '0' => spec.zero = true,
                '+' => spec.plus = true,
                ' ' => spec.space = true,
                '#' => spec.alt = true,
                _ => break,
            }
            it.next();
        }
        let digits = |it: &mut std::iter::Peekable<std::str::Chars>| {
            let mut n: usize = 0;
            while let Some(d) = it.peek().and_then(|d| d.to_digit(10)) {
                n = n.saturating_mul(10).saturating_add(d as usize);
                it.next();
            }
            n
        };
        spec.width = digits(&mut it);
        if it.peek() == Some(&'.') {
            it.next();
            spec.prec = Some(digits(&mut it));
        }
        // Length modifiers (`%ld`, `%lf`) mean nothing here.
        while matches!(it.peek(), Some('l' | 'h')) {
            it.next();
        }
        let Some(conv) = it.next() else {
            break;
        };
        if conv == '%' {
            out.push('%');
            continue;
        }
        let arg = next.next().cloned().unwrap_or(Val::I(0));
        let body = match (&arg, conv) {
            (Val::S(s), _) => match spec.prec {
                Some(p) if conv == 's' => s.chars().take(p).collect(),
                _ => s.clone(),
            },
            (v, 's') => fmt_val(v),
            (Val::I(i), _) => fmt_number(*i as f64, Some(i64::from(*i)), conv, &spec),
            (Val::F(a, 1), _) => fmt_number(f64::from(a[0]), None, conv, &spec),
            (Val::F(a, n), _) => format!(
                "{{{}}}",
                a[..*n as usize]
                    .iter()
                    .map(|x| fmt_number(f64::from(*x), None, conv, &spec))
                    .collect::<Vec<_>>()
                    .join(",")
            ),
            (v, _) => fmt_val(v),
        };
        // Padding goes straight into the result: a wide field is one
        // allocation, not two.
        let pad = spec.width.saturating_sub(body.chars().count());
        let fill = |out: &mut String, c: char| out.extend(std::iter::repeat_n(c, pad));
        let numeric = !matches!(arg, Val::S(_)) && !matches!(conv, 's' | 'c');
        if spec.left {
            out.push_str(&body);
            fill(&mut out, ' ');
        } else if spec.zero && numeric && !(spec.prec.is_some() && matches!(conv, 'd' | 'i')) {
            let (sign, digits) = body.split_at(usize::from(body.starts_with(['-', '+', ' '])));
            out.push_str(sign);
            fill(&mut out, '0');
            out.push_str(digits);
        } else {
            fill(&mut out, ' ');
            out.push_str(&body);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Expected strings are C's printf (ISO C 7.21.6.1), which VEX follows.
    #[test]
    fn formats_as_c() {
        let cases: &[(&str, Val, &str)] = &[
            ("%x", Val::I(255), "ff"),
            ("%X", Val::I(255), "FF"),
            ("%#x", Val::I(255), "0xff"),
            ("%08.3f", Val::float(-1.23456), "-001.235"),
            ("%5d|", Val::I(42), "   42|"),
            ("%-5d|", Val::I(42), "42   |"),
            ("%+d", Val::I(5), "+5"),
            ("%05d", Val::I(-42), "-0042"),
            ("%.3d", Val::I(7), "007"),
            ("%o", Val::I(8), "10"),
            ("%x", Val::I(-1), "ffffffff"),
            ("%e", Val::float(1234.5), "1.234500e+03"),
            ("%g", Val::float(0.0001), "0.0001"),
            ("%g", Val::float(1e-5), "1e-05"),
            ("%g", Val::float(123456.0), "123456"),
            ("%g", Val::float(1234567.0), "1.23457e+06"),
            ("%.2s", Val::S("hello".into()), "he"),
            ("%c", Val::I(65), "A"),
            ("%5.1f%%", Val::float(99.44), " 99.4%"),
        ];
        for (fmt, v, want) in cases {
            assert_eq!(sprintf(fmt, std::slice::from_ref(v)), *want, "{fmt}");
        }
    }

    #[test]
    fn globs_match_without_backtracking() {
        assert!(crate::pattern::glob("*.bgeo", "a.bgeo"));
        assert!(crate::pattern::glob("p?t", "pat"));
        assert!(!crate::pattern::glob("p?t", "part"));
        let long = "a".repeat(10_000);
        assert!(!crate::pattern::glob(
            &format!("{}b", "*a".repeat(50)),
            &long
        ));
    }
}
