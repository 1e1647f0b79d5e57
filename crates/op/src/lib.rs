//! The contract between nodes and the cook engine: an [`Operator`] declares
//! its inputs, output and parameters once ([`NodeSpec`]); the engine hands it
//! input [`Value`]s, evaluated [`Params`] and a [`CookContext`] (frame,
//! cancellation, progress) and gets a `Value` or a [`CookError`] back.

mod context;
mod env;
mod expr;
mod files;
mod param;
mod registry;
mod value;

pub use context::{
    CancelToken, CheckContext, CookContext, CookError, ErrorKind, KeyContext, ProgressFn,
    TextPosition, Warnings,
};
pub use env::{
    budget_from_env, expand_frame, human_bytes, network_identity, CookEnv, HeldGeometry, MB,
};
pub use expr::{ExprError, ExprLanguage, ExprScope, ExprValue, Expression};
pub use files::{FileAccess, FileRefusal};
pub use param::{
    ramp_from_rows, ramp_to_rows, LegacyRows, ListSpec, ParamDefault, ParamName, ParamSpec,
    ParamType, ParamValue, Params, COLOR_RAMP_ROWS, DEFAULT_COLOR_RAMP, DEFAULT_FLOAT_RAMP,
    FLOAT_RAMP_ROWS, SPARE_TYPES,
};
pub use registry::{edit_distance, Registry};
pub use value::{Bundle, PortType, Value};

mod docs;
pub use docs::markdown;

/// One input of a node type.
#[derive(Clone, Copy, Debug)]
pub struct InputSpec {
    pub name: &'static str,
    pub ty: PortType,
    /// A missing required input is a load error.
    pub required: bool,
}

/// Everything a node type declares about itself.
#[derive(Clone, Copy, Debug)]
pub struct NodeSpec {
    /// The type name used in network files (`box`, `transform`).
    pub name: &'static str,
    /// Bumped whenever the cook's output for the same inputs and parameters
    /// changes: it is part of every cache key.
    pub version: u32,
    pub label: &'static str,
    pub category: &'static str,
    pub help: &'static str,
    pub inputs: &'static [InputSpec],
    /// Whether any number of further inputs of the last input's type may follow.
    pub variadic: bool,
    pub output: PortType,
    pub params: &'static [ParamSpec],
    /// The cook reads the frame itself (beyond its animated parameters), so a
    /// frame change always recooks it.
    pub time_dependent: bool,
    /// File parameters the cook writes to (outputs, not cached side effects):
    /// while any of them names a file, the node cooks every time it is pulled
    /// and its result is never served from or stored in the cache.
    pub writes: &'static [&'static ParamSpec],
    /// Whether a network may declare spare parameters on the node (read by
    /// its cook by name: a wrangle's `ch()`).
    pub spare: bool,
    /// A string parameter naming other nodes of the network (paths,
    /// space-separated): the loader wires them in as inputs after the
    /// declared ones, so the cook reads them as inputs and the cache keys
    /// on them ("" for none; object_merge's `objects`).
    pub references: &'static str,
    /// A parameter that, when it names something, points `references`
    /// elsewhere (object_merge's `file`: the paths are of that file's
    /// network), so the loader wires nothing ("" for none).
    pub references_unless: &'static str,
}

/// A required geometry input.
pub const fn geometry_input(name: &'static str) -> InputSpec {
    InputSpec {
        name,
        ty: PortType::Geometry,
        required: true,
    }
}

impl NodeSpec {
    /// A geometry-producing node type at version 1 (override with the setters).
    pub const fn new(
        name: &'static str,
        label: &'static str,
        category: &'static str,
        help: &'static str,
        inputs: &'static [InputSpec],
        params: &'static [ParamSpec],
    ) -> NodeSpec {
        NodeSpec {
            name,
            version: 1,
            label,
            category,
            help,
            inputs,
            variadic: false,
            output: PortType::Geometry,
            params,
            time_dependent: false,
            writes: &[],
            spare: false,
            references: "",
            references_unless: "",
        }
    }

    /// The node reads the nodes parameter `param` names, as extra inputs.
    pub const fn references(mut self, param: &'static str) -> NodeSpec {
        self.references = param;
        self
    }

    /// ... unless parameter `other` names something (then the paths point
    /// elsewhere and the cook resolves them itself).
    pub const fn references_unless(mut self, other: &'static str) -> NodeSpec {
        self.references_unless = other;
        self
    }

    /// The node takes spare parameters declared in the network.
    pub const fn spare_params(mut self) -> NodeSpec {
        self.spare = true;
        self
    }

    /// Declares the file parameters the cook writes.
    pub const fn writes(mut self, params: &'static [&'static ParamSpec]) -> NodeSpec {
        self.writes = params;
        self
    }

    pub const fn variadic(mut self) -> NodeSpec {
        self.variadic = true;
        self
    }

    pub const fn output(mut self, ty: PortType) -> NodeSpec {
        self.output = ty;
        self
    }

    pub const fn version(mut self, v: u32) -> NodeSpec {
        self.version = v;
        self
    }

    /// The first sentence of the help text.
    pub fn summary(&self) -> &'static str {
        self.help
            .split(". ")
            .next()
            .unwrap_or("")
            .trim_end_matches('.')
    }

    pub fn param(&self, name: &str) -> Option<&'static ParamSpec> {
        self.params.iter().find(|p| p.name == name)
    }
}

/// A node type: declared once, cooked many times, from many threads.
pub trait Operator: Send + Sync {
    fn spec(&self) -> &'static NodeSpec;

    /// Cooks the node. `inputs` follow the declaration (absent optional
    /// inputs are `None`); `params` hold every declared parameter at the frame.
    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        params: &Params,
    ) -> Result<Value, CookError>;

    /// Extra content for the cache key that parameters do not capture: a node
    /// reading a file returns the file's content hash, so editing the file
    /// recooks the node (DESIGN.md invariant 4).
    fn key_extra(&self, _ctx: &KeyContext, _params: &Params) -> Result<Option<u128>, CookError> {
        Ok(None)
    }

    /// Whether a cook with these parameters reads the frame (then the frame
    /// is in its key): the spec's flag, or the operator's finer answer (a
    /// wrangle reads it only when its snippet names `@Frame` or `@Time`).
    fn reads_frame(&self, _params: &Params) -> bool {
        self.spec().time_dependent
    }

    /// Finds what a cook with these parameters would refuse, without
    /// cooking and without its inputs' values (`geode check`): a wrangle
    /// compiles its snippet. The error names the node, the parameter and,
    /// for text, the line and column. The default finds nothing.
    fn check(&self, _ctx: &CheckContext, _params: &Params) -> Result<(), CookError> {
        Ok(())
    }
}

/// A node's cook as a plain function: most node types need nothing else.
pub type CookFn = fn(&CookContext, &[Option<Value>], &Params) -> Result<Value, CookError>;

/// Extra cache-key content of a node that reads files (see [`Operator::key_extra`]).
pub type KeyExtraFn = fn(&KeyContext, &Params) -> Result<Option<u128>, CookError>;

/// A node type made of its declaration and its cook function (no per-node skeleton).
pub struct FnOperator {
    pub spec: &'static NodeSpec,
    pub cook: CookFn,
    /// Extra key content (see [`Operator::key_extra`]), where the node reads files.
    pub key_extra: Option<KeyExtraFn>,
}

impl Operator for FnOperator {
    fn spec(&self) -> &'static NodeSpec {
        self.spec
    }
    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        params: &Params,
    ) -> Result<Value, CookError> {
        (self.cook)(ctx, inputs, params)
    }
    fn key_extra(&self, ctx: &KeyContext, params: &Params) -> Result<Option<u128>, CookError> {
        self.key_extra.map_or(Ok(None), |f| f(ctx, params))
    }
}
