//! The wrangle library as one table: every builtin function is one
//! [`Function`] entry (name, category, a docs line, its forms with their
//! argument and return types, and how it lowers: to the lane function of
//! the form the call resolves to, or by the compiler itself for the math
//! that becomes instructions). The checker and the lowering resolve calls
//! against it, call sites carry its lane functions to the runtime,
//! `docs/wrangle.md` and the studio's completion are written from it.
//!
//! Adding a function is one entry in its category's file.

mod arrays;
mod channels;
mod constants;
mod crack;
mod edit;
mod geometry;
mod math;
mod matrix;
mod measure;
mod noise;
mod pointcloud;
mod strings;
mod support;

use std::collections::HashMap;
use std::sync::LazyLock;

use crate::program::{BytesFn, EditFn, LaneFn, NumFn};
use crate::ty::{Elem, Ty};

pub use constants::{constant, Constant, CONSTANTS};
pub use measure::intrinsic_type;

/// Where a function sits in SideFX's function index; docs and completion
/// group by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Category {
    Math,
    Vectors,
    Matrices,
    Quaternions,
    Noise,
    Parameters,
    Attributes,
    Geometry,
    Groups,
    Topology,
    Measuring,
    PointClouds,
    Editing,
    Strings,
    Arrays,
    Conversion,
}

impl Category {
    pub fn title(self) -> &'static str {
        match self {
            Category::Math => "Math",
            Category::Vectors => "Vectors",
            Category::Matrices => "Matrices and transforms",
            Category::Quaternions => "Quaternions",
            Category::Noise => "Random numbers and noise",
            Category::Parameters => "The node's parameters",
            Category::Attributes => "Attributes and intrinsics",
            Category::Geometry => "Reading geometry",
            Category::Groups => "Groups",
            Category::Topology => "Half-edges and vertices",
            Category::Measuring => "Measuring and bounds",
            Category::PointClouds => "Point clouds and nearest points",
            Category::Editing => "Writing geometry",
            Category::Strings => "Strings",
            Category::Arrays => "Arrays",
            Category::Conversion => "Conversion and output",
        }
    }
}

/// A type as a form names it: one type, or one VEX documents generically.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum T {
    /// This type (ints convert to floats and floats to vectors, as VEX
    /// converts arguments).
    Is(Ty),
    /// A float or any vector or matrix: every `Num` argument of a form has
    /// the type of the widest one given (floats widen).
    Num,
    /// Any vector (vector2, vector, vector4).
    Vector,
    /// Any array (`<type>[]`).
    Array,
    /// The element type of the form's array argument (`<type>`).
    Elem,
    /// An array or a string (both index and slice alike).
    Seq,
    /// Any value (printf's arguments, an attribute's value).
    Any,
}

/// One argument of a form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Arg {
    pub ty: T,
    pub name: &'static str,
    /// VEX's by-reference output: the function writes it; the call needs
    /// a variable (or attribute, element or component) there.
    pub out: bool,
}

/// What a form gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ret {
    Is(Ty),
    /// The type of the form's `Num` arguments.
    Num,
    /// The type of the form's array (or string) argument.
    Same,
    /// The element type of the form's array argument.
    Elem,
    /// Chosen by the context among these (a declaration, an assignment,
    /// a cast), else the first: `rand`, `noise`, `ident`.
    Context(&'static [Ty]),
    /// The attribute's type when input and name are literals, else the
    /// context's, else float: `point`, `prim`, `vertex`, `detail`.
    Attrib(geode_geo::AttribClass),
    /// The type of the intrinsic the literal name argument names:
    /// `primintrinsic`, `detailintrinsic`.
    Intrinsic,
}

/// One form of a function.
#[derive(Clone, Copy, Debug)]
pub struct Form {
    pub ret: Ret,
    pub args: &'static [Arg],
    /// How many trailing arguments may be left out.
    pub optional: u8,
    /// Whether the last argument may repeat.
    pub variadic: bool,
    /// The lane function (`None` where the compiler lowers the function).
    pub lane: Option<LaneFn>,
    /// What the result will hold before it is made (growing calls).
    pub bytes: Option<BytesFn>,
    /// The lane function as a function of numbers, for calls whose
    /// arguments and result are all numbers.
    pub num: Option<NumFn>,
    /// The lane function as a function of edits, for calls whose
    /// arguments are numbers and string literals.
    pub edit: Option<EditFn>,
}

/// How calls of a function are lowered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lowering {
    /// Resolved to a form and run as that form's lane function.
    Lane,
    /// Lowered by the compiler itself (math that becomes instructions,
    /// parameters read at compile time); the forms serve checking and docs.
    Compiler,
}

/// One builtin function.
#[derive(Clone, Copy, Debug)]
pub struct Function {
    pub name: &'static str,
    pub category: Category,
    /// One line for docs and completion.
    pub summary: &'static str,
    pub forms: &'static [Form],
    pub lowering: Lowering,
}

/// A function's name, lane function and budget estimate: what a call site
/// needs (also for the operators lowered to calls: indexing, slicing,
/// matrix products, string joins).
#[derive(Clone, Copy, Debug)]
pub struct Callee {
    pub name: &'static str,
    pub lane: LaneFn,
    pub bytes: Option<BytesFn>,
}

pub(crate) use arrays::intrinsics as array_ops;
pub(crate) use channels::intrinsics as channel_ops;
pub(crate) use matrix::intrinsics as matrix_ops;
pub(crate) use strings::intrinsics as string_ops;

// Constructors the category files write their entries with.

pub(crate) const fn a(ty: T, name: &'static str) -> Arg {
    Arg {
        ty,
        name,
        out: false,
    }
}

/// A by-reference argument the function writes.
pub(crate) const fn out(ty: T, name: &'static str) -> Arg {
    Arg {
        ty,
        name,
        out: true,
    }
}

pub(crate) const fn form(ret: Ret, args: &'static [Arg], lane: LaneFn) -> Form {
    Form {
        ret,
        args,
        optional: 0,
        variadic: false,
        lane: Some(lane),
        bytes: None,
        num: None,
        edit: None,
    }
}

/// A form the compiler lowers.
pub(crate) const fn shape(ret: Ret, args: &'static [Arg]) -> Form {
    Form {
        ret,
        args,
        optional: 0,
        variadic: false,
        lane: None,
        bytes: None,
        num: None,
        edit: None,
    }
}

impl Form {
    /// The last `n` arguments may be left out.
    pub(crate) const fn opt(self, n: u8) -> Form {
        Form {
            optional: n,
            ..self
        }
    }

    /// The last argument may repeat.
    pub(crate) const fn many(self) -> Form {
        Form {
            variadic: true,
            ..self
        }
    }

    /// The lane function computes through `f`, which calls of numbers run
    /// directly.
    pub(crate) const fn num(self, f: NumFn) -> Form {
        Form {
            num: Some(f),
            ..self
        }
    }

    /// The lane function goes through `f`, which calls of numbers and
    /// string literals run directly.
    pub(crate) const fn edit(self, f: EditFn) -> Form {
        Form {
            edit: Some(f),
            ..self
        }
    }

    pub(crate) const fn bytes(self, f: BytesFn) -> Form {
        Form {
            bytes: Some(f),
            ..self
        }
    }

    pub fn required(&self) -> usize {
        self.args.len() - self.optional as usize
    }

    /// Whether `n` arguments fit the form.
    pub fn takes(&self, n: usize) -> bool {
        n >= self.required() && (n <= self.args.len() || self.variadic)
    }

    /// The argument at position `k` (a repeated last one past the end).
    pub fn arg(&self, k: usize) -> Option<&Arg> {
        self.args
            .get(k)
            .or_else(|| self.variadic.then(|| self.args.last()).flatten())
    }
}

pub(crate) const fn lane(
    name: &'static str,
    category: Category,
    summary: &'static str,
    forms: &'static [Form],
) -> Function {
    Function {
        name,
        category,
        summary,
        forms,
        lowering: Lowering::Lane,
    }
}

/// A function the compiler lowers itself (its forms serve checks and docs).
pub(crate) const fn compiler(
    name: &'static str,
    category: Category,
    summary: &'static str,
    forms: &'static [Form],
) -> Function {
    Function {
        lowering: Lowering::Compiler,
        ..lane(name, category, summary, forms)
    }
}

// Type shorthands for the entries.
pub(crate) const I: T = T::Is(Ty::Int);
pub(crate) const F: T = T::Is(Ty::Float);
pub(crate) const V: T = T::Is(Ty::Vec3);
pub(crate) const V4: T = T::Is(Ty::Vec4);
pub(crate) const M3: T = T::Is(Ty::Mat3);
pub(crate) const M4: T = T::Is(Ty::Mat4);
pub(crate) const S: T = T::Is(Ty::Str);
pub(crate) const IA: T = T::Is(Ty::Array(Elem::Int));
pub(crate) const SA: T = T::Is(Ty::Array(Elem::Str));

#[cfg(test)]
mod tests;

static TABLE: LazyLock<Vec<&'static Function>> = LazyLock::new(|| {
    [
        math::FUNCTIONS,
        channels::FUNCTIONS,
        noise::FUNCTIONS,
        geometry::FUNCTIONS,
        measure::FUNCTIONS,
        pointcloud::FUNCTIONS,
        edit::FUNCTIONS,
        arrays::FUNCTIONS,
        strings::FUNCTIONS,
        matrix::FUNCTIONS,
    ]
    .into_iter()
    .flatten()
    .collect()
});

static BY_NAME: LazyLock<HashMap<&'static str, &'static Function>> =
    LazyLock::new(|| TABLE.iter().map(|f| (f.name, *f)).collect());

/// Every builtin function, grouped by category in the order docs list them.
pub fn functions() -> &'static [&'static Function] {
    &TABLE
}

/// The builtin called `name`.
pub fn find(name: &str) -> Option<&'static Function> {
    BY_NAME.get(name).copied()
}

/// Every library name, for suggestions.
pub fn names() -> impl Iterator<Item = &'static str> {
    TABLE.iter().map(|f| f.name)
}

/// One form of a library function as editors show it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signature {
    pub name: &'static str,
    pub category: Category,
    /// The form as VEX documents it: `float fit01(float x, float nmin, float nmax)`.
    pub display: String,
    pub summary: &'static str,
    /// Arguments (type as written, name).
    pub args: Vec<(String, &'static str)>,
    pub ret: String,
    /// How many trailing arguments may be left out.
    pub optional: usize,
    /// Whether the last argument may repeat.
    pub variadic: bool,
}

impl T {
    pub fn spelling(self) -> String {
        match self {
            T::Is(t) => t.to_string(),
            T::Num => "<float|vector>".into(),
            T::Vector => "<vector>".into(),
            T::Array => "<type>[]".into(),
            T::Elem => "<type>".into(),
            T::Seq => "<type>[]|string".into(),
            T::Any => "<any>".into(),
        }
    }
}

impl Ret {
    pub fn spelling(self) -> String {
        match self {
            Ret::Is(t) => t.to_string(),
            Ret::Num => "<float|vector>".into(),
            Ret::Same => "<type>[]".into(),
            Ret::Elem => "<type>".into(),
            Ret::Context(ts) => ts[0].to_string(),
            Ret::Attrib(_) | Ret::Intrinsic => "<type>".into(),
        }
    }
}

impl Form {
    /// `float fit01(float x, float nmin, float nmax)`, optional arguments
    /// in brackets, a repeatable last one followed by `...`, outputs `&`.
    pub fn display(&self, name: &str) -> String {
        let required = self.required();
        let mut text = format!("{} {}(", self.ret.spelling(), name);
        for (k, arg) in self.args.iter().enumerate() {
            let sep = if k == 0 { "" } else { ", " };
            let amp = if arg.out { "&" } else { "" };
            let one = format!("{}{amp} {}", arg.ty.spelling(), arg.name);
            if k >= required {
                text.push_str(&format!("[{sep}{one}]"));
            } else {
                text.push_str(&format!("{sep}{one}"));
            }
        }
        if self.variadic {
            text.push_str(", ...");
        }
        text.push(')');
        text
    }
}

/// Every form of every function, for editors' completion and help.
pub fn signatures() -> Vec<Signature> {
    TABLE
        .iter()
        .flat_map(|f| {
            f.forms.iter().map(|form| Signature {
                name: f.name,
                category: f.category,
                display: form.display(f.name),
                summary: f.summary,
                args: form
                    .args
                    .iter()
                    .map(|a| (a.ty.spelling(), a.name))
                    .collect(),
                ret: form.ret.spelling(),
                optional: form.optional as usize,
                variadic: form.variadic,
            })
        })
        .collect()
}

/// The function reference of `docs/wrangle.md`: a section per category,
/// each function's forms and its line.
pub fn docs_markdown() -> String {
    let mut by_cat: Vec<&&Function> = TABLE.iter().collect();
    by_cat.sort_by_key(|f| f.category);
    let mut text = String::new();
    let mut last = None;
    for f in by_cat {
        if last != Some(f.category) {
            text.push_str(&format!("\n### {}\n\n", f.category.title()));
            last = Some(f.category);
        }
        let forms: Vec<String> = f
            .forms
            .iter()
            .map(|form| format!("`{}`", form.display(f.name)))
            .collect();
        text.push_str(&format!("- {}: {}\n", forms.join(", "), f.summary));
    }
    text.push_str("\n### Constants (math.h)\n\n");
    let names: Vec<String> = CONSTANTS
        .iter()
        .map(|(name, c)| match c {
            Constant::Float(x) => format!("`{name}` = {x}"),
            Constant::Int(i) => format!("`{name}` = {i}"),
        })
        .collect();
    text.push_str(&names.join(", "));
    text.push('\n');
    text
}
