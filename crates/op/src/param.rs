//! Parameter declarations (name, type, default, range, animatable, help, tag),
//! list parameters (Houdini's multiparms: rows of typed fields), ramps (rows
//! of keys, evaluated by `geode_geo::Ramp`) and evaluated values.

use std::fmt;

use geode_geo::{Ramp, RampBasis, RampKey, RampKind};
use xxhash_rust::xxh3::Xxh3;

use crate::context::CookError;

/// The type of a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamType {
    Float,
    Int,
    Toggle,
    Vec2,
    Vec3,
    Vec4,
    String,
    /// One of the listed tokens.
    Menu(&'static [&'static str]),
    /// A file path (read through geode-io, hashed by content where it matters).
    File,
    /// A list of records (Houdini's multiparm): each row has the declared
    /// fields, each field typed, ranged and animatable like a parameter.
    List(&'static ListSpec),
    /// A ramp (Houdini's ramp parameter): keys of position, value (a float
    /// or an RGB colour) and interpolation, written as list rows (each
    /// field animatable) and evaluated into a `geode_geo::Ramp`.
    Ramp(RampKind),
}

/// Reads the text form a list parameter had before it was a list: constant
/// rows in field order, or why the text is not of that form.
pub type LegacyRows = fn(&str) -> Result<Vec<Vec<ParamValue>>, String>;

/// The fields of a list parameter's rows.
#[derive(Debug)]
pub struct ListSpec {
    pub fields: &'static [ParamSpec],
    /// Old networks gave this parameter as text: how to read it.
    pub legacy: Option<LegacyRows>,
}

impl PartialEq for ListSpec {
    fn eq(&self, o: &ListSpec) -> bool {
        std::ptr::eq(self, o)
    }
}

impl ListSpec {
    pub fn field(&self, name: &str) -> Option<&'static ParamSpec> {
        self.fields.iter().find(|f| f.name == name)
    }
}

impl ParamType {
    /// Number of animatable components (0 for strings).
    pub fn components(self) -> usize {
        match self {
            ParamType::Float | ParamType::Int | ParamType::Toggle => 1,
            ParamType::Vec2 => 2,
            ParamType::Vec3 => 3,
            ParamType::Vec4 => 4,
            ParamType::String
            | ParamType::Menu(_)
            | ParamType::File
            | ParamType::List(_)
            | ParamType::Ramp(_) => 0,
        }
    }

    /// The rows a ramp is written as (its keys' fields), for a ramp.
    pub fn ramp_rows(self) -> Option<&'static ListSpec> {
        match self {
            ParamType::Ramp(RampKind::Float) => Some(&FLOAT_RAMP_ROWS),
            ParamType::Ramp(RampKind::Color) => Some(&COLOR_RAMP_ROWS),
            _ => None,
        }
    }

    pub fn is_textual(self) -> bool {
        matches!(
            self,
            ParamType::String | ParamType::Menu(_) | ParamType::File
        )
    }
}

impl fmt::Display for ParamType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamType::Float => f.write_str("float"),
            ParamType::Int => f.write_str("int"),
            ParamType::Toggle => f.write_str("toggle"),
            ParamType::Vec2 => f.write_str("vector2"),
            ParamType::Vec3 => f.write_str("vector3"),
            ParamType::Vec4 => f.write_str("vector4"),
            ParamType::String => f.write_str("string"),
            ParamType::Menu(items) => write!(f, "menu ({})", items.join(" | ")),
            ParamType::File => f.write_str("file"),
            ParamType::List(l) => {
                let fields: Vec<String> = l
                    .fields
                    .iter()
                    .map(|p| format!("{} {}", p.name, p.ty))
                    .collect();
                write!(f, "list of ({})", fields.join(", "))
            }
            ParamType::Ramp(RampKind::Float) => f.write_str("ramp"),
            ParamType::Ramp(RampKind::Color) => f.write_str("colour ramp"),
        }
    }
}

const RAMP_POS: ParamSpec = ParamSpec::new(
    "pos",
    "Position",
    ParamType::Float,
    ParamDefault::Float(0.0),
    "Where the key sits along the ramp (0 to 1); keys are sorted by it.",
)
.range(0.0, 1.0);
const RAMP_INTERP: ParamSpec = ParamSpec::new(
    "interp",
    "Interpolation",
    ParamType::Menu(RampBasis::NAMES),
    ParamDefault::Str("linear"),
    "How the segment from this key to the next is drawn: constant, linear, catmull-rom (smooth, through the keys), monotonecubic (smooth, never overshooting) or bspline (smooth, approximating).",
);
static FLOAT_RAMP_FIELDS: [ParamSpec; 3] = [
    RAMP_POS,
    ParamSpec::new(
        "value",
        "Value",
        ParamType::Float,
        ParamDefault::Float(0.0),
        "The key's value.",
    ),
    RAMP_INTERP,
];
static COLOR_RAMP_FIELDS: [ParamSpec; 3] = [
    RAMP_POS,
    ParamSpec::new(
        "value",
        "Colour",
        ParamType::Vec3,
        ParamDefault::Vec3([0.0; 3]),
        "The key's colour (red, green, blue).",
    ),
    RAMP_INTERP,
];

/// A float ramp's keys as rows: `pos`, `value`, `interp`. The text form
/// `u value, u value` (a sweep's radius ramp before ramps were a type)
/// reads as linear keys.
pub static FLOAT_RAMP_ROWS: ListSpec = ListSpec {
    fields: &FLOAT_RAMP_FIELDS,
    legacy: Some(float_ramp_text),
};

/// A colour ramp's keys as rows: `pos`, `value` (RGB), `interp`.
pub static COLOR_RAMP_ROWS: ListSpec = ListSpec {
    fields: &COLOR_RAMP_FIELDS,
    legacy: None,
};

/// `u value, u value`: linear keys, as sweep's radius ramp was written.
fn float_ramp_text(text: &str) -> Result<Vec<Vec<ParamValue>>, String> {
    let mut rows = Vec::new();
    for (k, pair) in text
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .enumerate()
    {
        let nums: Vec<Option<f64>> = pair
            .split_whitespace()
            .map(|s| s.parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect();
        match nums[..] {
            [Some(u), Some(v)] => rows.push(vec![
                ParamValue::Float(u),
                ParamValue::Float(v),
                ParamValue::String("linear".into()),
            ]),
            _ => {
                return Err(format!(
                    "key {} `{pair}`: expected two numbers `position value`",
                    k + 1
                ))
            }
        }
    }
    Ok(rows)
}

/// A ramp from its evaluated rows (`pos`, `value`, `interp` each), sorted
/// by position; why not, naming the row.
pub fn ramp_from_rows(kind: RampKind, rows: &[Vec<ParamValue>]) -> Result<Ramp, String> {
    let mut keys = Vec::with_capacity(rows.len());
    for (k, row) in rows.iter().enumerate() {
        let (pos, value, interp) = match row.as_slice() {
            [ParamValue::Float(p), v, ParamValue::String(i)] => (*p, v, i),
            _ => return Err(format!("key {k}: expected `pos`, `value` and `interp`")),
        };
        let value = match (kind, value) {
            (RampKind::Float, ParamValue::Float(x)) => [*x, 0.0, 0.0],
            (RampKind::Color, ParamValue::Vector(v)) if v.len() == 3 => [v[0], v[1], v[2]],
            _ => {
                return Err(format!(
                    "key {k}: `value` is not a {}",
                    ParamType::Ramp(kind)
                ))
            }
        };
        let basis = RampBasis::from_name(interp).ok_or_else(|| {
            format!(
                "key {k}: unknown interpolation `{interp}` (expected one of {})",
                RampBasis::NAMES.join(", ")
            )
        })?;
        keys.push(RampKey { pos, value, basis });
    }
    Ramp::new(kind, keys).map_err(|e| e.to_string())
}

/// A ramp's keys as rows (`pos`, `value`, `interp`), in position order.
pub fn ramp_to_rows(ramp: &Ramp) -> Vec<Vec<ParamValue>> {
    ramp.keys()
        .iter()
        .map(|k| {
            vec![
                ParamValue::Float(k.pos),
                match ramp.kind() {
                    RampKind::Float => ParamValue::Float(k.value[0]),
                    RampKind::Color => ParamValue::Vector(k.value.to_vec()),
                },
                ParamValue::String(k.basis.name().to_owned()),
            ]
        })
        .collect()
}

/// A default value, writable in a `const` declaration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamDefault {
    Float(f64),
    Int(i64),
    Toggle(bool),
    Vec2([f64; 2]),
    Vec3([f64; 3]),
    Vec4([f64; 4]),
    Str(&'static str),
    /// A list parameter starts with no rows.
    EmptyList,
    /// A ramp's keys (of a float or colour ramp).
    Ramp(RampKind, &'static [RampKey]),
}

/// A parameter, declared once: it drives validation, docs, the CLI and the studio.
#[derive(Clone, Copy, Debug)]
pub struct ParamSpec {
    pub name: &'static str,
    pub label: &'static str,
    pub ty: ParamType,
    pub default: ParamDefault,
    /// Inclusive hard limits on every numeric component (values outside are errors).
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub animatable: bool,
    pub help: &'static str,
    /// Name of the inner node this parameter affects (solo view's auto mode).
    pub affects: Option<&'static str>,
    /// A string holding code (a wrangle's snippet): shown as a multi-line
    /// editor.
    pub code: bool,
}

/// The type names `ParamSpec::spare` accepts, for error messages.
pub const SPARE_TYPES: &[&str] = &[
    "float",
    "int",
    "toggle",
    "vector2",
    "vector",
    "vector4",
    "string",
    "ramp",
    "colorramp",
];

/// A new float ramp: 0 to 1, linear (Houdini's default ramp).
pub const DEFAULT_FLOAT_RAMP: &[RampKey] = &[
    RampKey::float(0.0, 0.0, RampBasis::Linear),
    RampKey::float(1.0, 1.0, RampBasis::Linear),
];

/// A new colour ramp: black to white, linear.
pub const DEFAULT_COLOR_RAMP: &[RampKey] = &[
    RampKey::color(0.0, [0.0; 3], RampBasis::Linear),
    RampKey::color(1.0, [1.0; 3], RampBasis::Linear),
];

const SPARE_HELP: &str = "A spare parameter declared by the network.";

static SPARE_SPECS: [ParamSpec; 9] = [
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::Float,
        ParamDefault::Float(0.0),
        SPARE_HELP,
    ),
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::Int,
        ParamDefault::Int(0),
        SPARE_HELP,
    ),
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::Toggle,
        ParamDefault::Toggle(false),
        SPARE_HELP,
    ),
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::Vec2,
        ParamDefault::Vec2([0.0; 2]),
        SPARE_HELP,
    ),
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::Vec3,
        ParamDefault::Vec3([0.0; 3]),
        SPARE_HELP,
    ),
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::Vec4,
        ParamDefault::Vec4([0.0; 4]),
        SPARE_HELP,
    ),
    ParamSpec::new(
        "spare",
        "Spare",
        ParamType::String,
        ParamDefault::Str(""),
        SPARE_HELP,
    ),
    ParamSpec::ramp(
        "spare",
        "Spare",
        RampKind::Float,
        DEFAULT_FLOAT_RAMP,
        SPARE_HELP,
    ),
    ParamSpec::ramp(
        "spare",
        "Spare",
        RampKind::Color,
        DEFAULT_COLOR_RAMP,
        SPARE_HELP,
    ),
];

impl ParamSpec {
    /// A parameter with no range, animatable when numeric, no tag.
    pub const fn new(
        name: &'static str,
        label: &'static str,
        ty: ParamType,
        default: ParamDefault,
        help: &'static str,
    ) -> ParamSpec {
        ParamSpec {
            name,
            label,
            ty,
            default,
            min: None,
            max: None,
            animatable: !matches!(
                ty,
                ParamType::String | ParamType::Menu(_) | ParamType::File | ParamType::List(_)
            ),
            help,
            affects: None,
            code: false,
        }
    }

    /// Marks a string parameter as code (a multi-line editor in the studio).
    pub const fn code(mut self) -> ParamSpec {
        self.code = true;
        self
    }

    pub const fn range(mut self, min: f64, max: f64) -> ParamSpec {
        self.min = Some(min);
        self.max = Some(max);
        self
    }

    pub const fn at_least(mut self, min: f64) -> ParamSpec {
        self.min = Some(min);
        self
    }

    pub const fn not_animatable(mut self) -> ParamSpec {
        self.animatable = false;
        self
    }

    pub fn default_value(&self) -> ParamValue {
        match self.default {
            ParamDefault::Float(x) => ParamValue::Float(x),
            ParamDefault::Int(x) => ParamValue::Int(x),
            ParamDefault::Toggle(x) => ParamValue::Toggle(x),
            ParamDefault::Vec2(v) => ParamValue::Vector(v.to_vec()),
            ParamDefault::Vec3(v) => ParamValue::Vector(v.to_vec()),
            ParamDefault::Vec4(v) => ParamValue::Vector(v.to_vec()),
            ParamDefault::Str(s) => ParamValue::String(s.to_owned()),
            ParamDefault::EmptyList => ParamValue::List(Vec::new()),
            ParamDefault::Ramp(kind, keys) => ParamValue::Ramp(
                Ramp::new(kind, keys.to_vec()).expect("declared ramp defaults are finite"),
            ),
        }
    }

    /// A ramp parameter with these default keys.
    pub const fn ramp(
        name: &'static str,
        label: &'static str,
        kind: RampKind,
        keys: &'static [RampKey],
        help: &'static str,
    ) -> ParamSpec {
        ParamSpec::new(
            name,
            label,
            ParamType::Ramp(kind),
            ParamDefault::Ramp(kind, keys),
            help,
        )
    }

    /// A list parameter with these row fields (and, for networks written
    /// before it was a list, a reader of its old text form).
    pub const fn list(
        name: &'static str,
        label: &'static str,
        rows: &'static ListSpec,
        help: &'static str,
    ) -> ParamSpec {
        ParamSpec::new(
            name,
            label,
            ParamType::List(rows),
            ParamDefault::EmptyList,
            help,
        )
    }

    /// The declaration a spare parameter of type `ty` (as a network names
    /// it: float, int, toggle, vector2, vector, vector4, string, ramp,
    /// colorramp) takes: one
    /// static spec per type, the name carried beside it. `ramp` and
    /// `colorramp` are float and colour ramps (`chramp()` in a wrangle).
    pub fn spare(ty: &str) -> Option<&'static ParamSpec> {
        Some(match ty {
            "float" => &SPARE_SPECS[0],
            "int" => &SPARE_SPECS[1],
            "toggle" => &SPARE_SPECS[2],
            "vector2" => &SPARE_SPECS[3],
            "vector" => &SPARE_SPECS[4],
            "vector4" => &SPARE_SPECS[5],
            "string" => &SPARE_SPECS[6],
            "ramp" => &SPARE_SPECS[7],
            "colorramp" => &SPARE_SPECS[8],
            _ => return None,
        })
    }

    /// Builds a value of this parameter's type from numeric components.
    pub fn from_components(&self, c: &[f64]) -> ParamValue {
        match self.ty {
            ParamType::Float => ParamValue::Float(c[0]),
            // Animated ints and toggles round: a channel may pass between integers.
            ParamType::Int => ParamValue::Int(c[0].round() as i64),
            ParamType::Toggle => ParamValue::Toggle(c[0] >= 0.5),
            _ => ParamValue::Vector(c.to_vec()),
        }
    }
}

/// A parameter's value at a frame.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    Float(f64),
    Int(i64),
    Toggle(bool),
    Vector(Vec<f64>),
    String(String),
    /// Rows of a list parameter, each with its fields in declaration order.
    List(Vec<Vec<ParamValue>>),
    /// A ramp, its keys sorted by position.
    Ramp(Ramp),
}

impl ParamValue {
    /// The numbers of a numeric value (a toggle is 0 or 1); none for text,
    /// lists and ramps.
    pub fn as_components(&self) -> Vec<f64> {
        match self {
            ParamValue::Float(x) => vec![*x],
            ParamValue::Int(i) => vec![*i as f64],
            ParamValue::Toggle(b) => vec![f64::from(u8::from(*b))],
            ParamValue::Vector(v) => v.clone(),
            ParamValue::String(_) | ParamValue::List(_) | ParamValue::Ramp(_) => Vec::new(),
        }
    }

    /// Feeds a canonical encoding into a cache key.
    pub fn hash_into(&self, h: &mut Xxh3) {
        match self {
            ParamValue::Float(x) => {
                h.update(b"f");
                h.update(&canonical(*x).to_le_bytes());
            }
            ParamValue::Int(x) => {
                h.update(b"i");
                h.update(&x.to_le_bytes());
            }
            ParamValue::Toggle(x) => h.update(if *x { b"t1" } else { b"t0" }),
            ParamValue::Vector(v) => {
                h.update(b"v");
                h.update(&(v.len() as u64).to_le_bytes());
                for x in v {
                    h.update(&canonical(*x).to_le_bytes());
                }
            }
            ParamValue::String(s) => {
                h.update(b"s");
                h.update(&(s.len() as u64).to_le_bytes());
                h.update(s.as_bytes());
            }
            ParamValue::List(rows) => {
                h.update(b"l");
                h.update(&(rows.len() as u64).to_le_bytes());
                for row in rows {
                    h.update(&(row.len() as u64).to_le_bytes());
                    for v in row {
                        v.hash_into(h);
                    }
                }
            }
            ParamValue::Ramp(r) => {
                h.update(match r.kind() {
                    RampKind::Float => b"rf",
                    RampKind::Color => b"rc",
                });
                h.update(&(r.keys().len() as u64).to_le_bytes());
                for k in r.keys() {
                    h.update(&canonical(k.pos).to_le_bytes());
                    for x in k.value {
                        h.update(&canonical(x).to_le_bytes());
                    }
                    h.update(&[k.basis as u8]);
                }
            }
        }
    }
}

/// -0 and 0 are the same parameter value.
fn canonical(x: f64) -> u64 {
    if x == 0.0 {
        0
    } else {
        x.to_bits()
    }
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::Float(x) => write!(f, "{x}"),
            ParamValue::Int(x) => write!(f, "{x}"),
            ParamValue::Toggle(x) => write!(f, "{x}"),
            ParamValue::Vector(v) => write!(f, "{v:?}"),
            ParamValue::String(s) => write!(f, "{s:?}"),
            ParamValue::List(rows) => write!(f, "{} rows", rows.len()),
            ParamValue::Ramp(r) => {
                let keys: Vec<String> = r
                    .keys()
                    .iter()
                    .map(|k| match r.kind() {
                        RampKind::Float => format!("{} {} {}", k.pos, k.value[0], k.basis),
                        RampKind::Color => format!("{} {:?} {}", k.pos, k.value, k.basis),
                    })
                    .collect();
                write!(f, "ramp [{}]", keys.join(", "))
            }
        }
    }
}

/// What a parameter is read by: its declaration (`p.float(&RADIUS)`, the
/// name written once). No string stands for a declared parameter; a
/// node's spare parameters, declared by the network, are read by name
/// (`Params::spare`).
pub trait ParamName {
    fn param_name(&self) -> &str;
}

impl ParamName for ParamSpec {
    fn param_name(&self) -> &str {
        self.name
    }
}

/// Every declared parameter of a node, evaluated at the cook's frame.
#[derive(Clone, Debug, Default)]
pub struct Params {
    path: String,
    /// `edits[2].` for a row of a list parameter: errors name the field fully.
    prefix: String,
    values: Vec<(&'static str, ParamValue)>,
    /// The declarations, where known (list rows need their fields).
    specs: Vec<&'static ParamSpec>,
    /// Spare parameters the network declared on the node, by name.
    spare: Vec<(String, ParamValue)>,
}

impl Params {
    pub fn new(path: impl Into<String>, values: Vec<(&'static str, ParamValue)>) -> Params {
        Params {
            path: path.into(),
            prefix: String::new(),
            values,
            specs: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// Values with their declarations (what the engine hands a cook).
    pub fn declared(
        path: impl Into<String>,
        values: Vec<(&'static ParamSpec, ParamValue)>,
    ) -> Params {
        Params {
            path: path.into(),
            prefix: String::new(),
            specs: values.iter().map(|(s, _)| *s).collect(),
            values: values.into_iter().map(|(s, v)| (s.name, v)).collect(),
            spare: Vec::new(),
        }
    }

    /// The full name of a parameter or row field, for error messages
    /// (`edits[2].level`).
    pub fn name(&self, name: &(impl ParamName + ?Sized)) -> String {
        self.full_name(name.param_name())
    }

    fn full_name(&self, name: &str) -> String {
        format!("{}{name}", self.prefix)
    }

    /// These parameters with the node's spare parameters beside them.
    pub fn with_spare(mut self, spare: Vec<(String, ParamValue)>) -> Params {
        self.spare = spare;
        self
    }

    /// A spare parameter's value.
    pub fn spare(&self, name: &str) -> Option<&ParamValue> {
        self.spare.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }

    /// The spare parameters, in declaration order (cache keys cover them).
    pub fn spares(&self) -> &[(String, ParamValue)] {
        &self.spare
    }

    pub fn iter(&self) -> impl Iterator<Item = &(&'static str, ParamValue)> {
        self.values.iter()
    }

    pub fn get(&self, name: &(impl ParamName + ?Sized)) -> Result<&ParamValue, CookError> {
        self.get_named(name.param_name())
    }

    fn get_named(&self, name: &str) -> Result<&ParamValue, CookError> {
        self.values
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v)
            .ok_or_else(|| {
                CookError::param(
                    &self.path,
                    &self.full_name(name),
                    "the node asked for a parameter it does not declare",
                )
            })
    }

    fn wrong(&self, name: &(impl ParamName + ?Sized), want: &str) -> CookError {
        CookError::param(&self.path, &self.name(name), format!("expected a {want}"))
    }

    pub fn float(&self, name: &(impl ParamName + ?Sized)) -> Result<f64, CookError> {
        match self.get(name)? {
            ParamValue::Float(x) => Ok(*x),
            ParamValue::Int(x) => Ok(*x as f64),
            _ => Err(self.wrong(name, "float")),
        }
    }

    pub fn int(&self, name: &(impl ParamName + ?Sized)) -> Result<i64, CookError> {
        match self.get(name)? {
            ParamValue::Int(x) => Ok(*x),
            _ => Err(self.wrong(name, "int")),
        }
    }

    pub fn toggle(&self, name: &(impl ParamName + ?Sized)) -> Result<bool, CookError> {
        match self.get(name)? {
            ParamValue::Toggle(x) => Ok(*x),
            _ => Err(self.wrong(name, "toggle")),
        }
    }

    pub fn vector<const N: usize>(
        &self,
        name: &(impl ParamName + ?Sized),
    ) -> Result<[f64; N], CookError> {
        match self.get(name)? {
            ParamValue::Vector(v) if v.len() == N => Ok(std::array::from_fn(|i| v[i])),
            _ => Err(self.wrong(name, &format!("vector{N}"))),
        }
    }

    pub fn string(&self, name: &(impl ParamName + ?Sized)) -> Result<&str, CookError> {
        match self.get(name)? {
            ParamValue::String(s) => Ok(s),
            _ => Err(self.wrong(name, "string")),
        }
    }

    /// A ramp parameter's value (evaluate it with `eval` or `eval_float`).
    pub fn ramp(&self, name: &(impl ParamName + ?Sized)) -> Result<&Ramp, CookError> {
        match self.get(name)? {
            ParamValue::Ramp(r) => Ok(r),
            _ => Err(self.wrong(name, "ramp")),
        }
    }

    /// The rows of a list parameter, each read by field name.
    pub fn list(&self, spec: &(impl ParamName + ?Sized)) -> Result<Vec<Params>, CookError> {
        let name = spec.param_name();
        let list_spec = self
            .specs
            .iter()
            .find(|s| s.name == name)
            .and_then(|s| match s.ty {
                ParamType::List(l) => Some(l),
                _ => None,
            });
        match (self.get_named(name)?, list_spec) {
            (ParamValue::List(rows), Some(l)) => Ok(rows
                .iter()
                .enumerate()
                .map(|(k, row)| Params {
                    path: self.path.clone(),
                    prefix: format!("{}{name}[{k}].", self.prefix),
                    values: l
                        .fields
                        .iter()
                        .map(|f| f.name)
                        .zip(row.iter().cloned())
                        .collect(),
                    specs: l.fields.iter().collect(),
                    spare: Vec::new(),
                })
                .collect()),
            _ => Err(self.wrong(spec, "list")),
        }
    }
}
