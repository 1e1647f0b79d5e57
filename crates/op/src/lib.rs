//! The contract between nodes and the cook engine: an [`Operator`] declares
//! its inputs, output and parameters once ([`NodeSpec`]); the engine hands it
//! input [`Value`]s, evaluated [`Params`] and a [`CookContext`] (frame,
//! cancellation, progress) and gets a `Value` or a [`CookError`] back.

mod context;
mod param;
mod registry;
mod value;

pub use context::{CancelToken, CookContext, CookError, ProgressFn};
pub use param::{ParamDefault, ParamSpec, ParamType, ParamValue, Params};
pub use registry::{edit_distance, Registry};
pub use value::{Bundle, PortType, Value};

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
}

impl NodeSpec {
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
}
