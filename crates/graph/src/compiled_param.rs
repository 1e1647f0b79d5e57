//! A parameter as loading compiles it (text, a template, numeric components
//! fixed, keyframed or expressions, list rows) and its value at a frame.

use geode_op::{ParamSpec, ParamType, ParamValue};

use crate::channel::Channel;
use crate::expr::{EvalCx, ExprComponent, Piece};
use crate::load::LoadError;

/// One numeric component of a parameter: fixed, keyframed or an expression.
#[derive(Clone, Debug)]
pub(crate) enum Component {
    Const(f64),
    Channel(Channel),
    Expr(ExprComponent),
}

#[derive(Clone, Debug)]
pub(crate) enum ParamSource {
    Text(String),
    /// A string with variables or backtick expressions.
    Template(Vec<Piece>),
    Components(Vec<Component>),
    /// A list parameter's rows, each field compiled like a parameter.
    List(Vec<Vec<CompiledParam>>),
}

#[derive(Clone, Debug)]
pub(crate) struct CompiledParam {
    pub spec: &'static ParamSpec,
    pub source: ParamSource,
}

impl CompiledParam {
    /// The value at `cx`'s frame; `name` is how errors call the parameter.
    pub(crate) fn eval_named(&self, cx: &EvalCx, name: &str) -> Result<ParamValue, LoadError> {
        let path = &cx.net.nodes[cx.node].path;
        let fail = |e: geode_op::ExprError| LoadError::param(path, name, e.message).at(e.position);
        match &self.source {
            ParamSource::Text(s) => Ok(ParamValue::String(s.clone())),
            ParamSource::Template(pieces) => {
                cx.template(pieces).map(ParamValue::String).map_err(fail)
            }
            ParamSource::List(rows) => {
                let rows: Vec<Vec<ParamValue>> = rows
                    .iter()
                    .enumerate()
                    .map(|(k, r)| {
                        r.iter()
                            .map(|f| f.eval_named(cx, &format!("{name}[{k}].{}", f.spec.name)))
                            .collect()
                    })
                    .collect::<Result<_, _>>()?;
                match self.spec.ty {
                    // A ramp's rows are its keys: sorted, checked and built here.
                    ParamType::Ramp(kind) => geode_op::ramp_from_rows(kind, &rows)
                        .map(ParamValue::Ramp)
                        .map_err(|m| LoadError::param(path, name, m)),
                    _ => Ok(ParamValue::List(rows)),
                }
            }
            ParamSource::Components(c) => {
                let v = (0..c.len())
                    .map(|k| self.component_at(cx, name, k))
                    .collect::<Result<Vec<f64>, LoadError>>()?;
                Ok(self.spec.from_components(&v))
            }
        }
    }

    /// Component `k` of a numeric parameter at `cx`'s frame (None-like 0
    /// for text and lists, which have no components).
    pub(crate) fn component_at(&self, cx: &EvalCx, name: &str, k: usize) -> Result<f64, LoadError> {
        let path = &cx.net.nodes[cx.node].path;
        let ParamSource::Components(c) = &self.source else {
            return Err(LoadError::param(path, name, "not a numeric parameter"));
        };
        match c.get(k) {
            None => Err(LoadError::param(
                path,
                name,
                format!("has no component {k}"),
            )),
            Some(Component::Const(x)) => Ok(*x),
            Some(Component::Channel(ch)) => Ok(ch.eval(cx.frame)),
            Some(Component::Expr(e)) => {
                let value = cx
                    .expression(e)
                    .map_err(|e| LoadError::param(path, name, e.message).at(e.position))?;
                self.checked(&value, cx.frame)
                    .map_err(|m| LoadError::param(path, name, m))
            }
        }
    }

    /// The value at `cx`'s frame, errors naming the declared parameter.
    pub(crate) fn eval(&self, cx: &EvalCx) -> Result<ParamValue, LoadError> {
        self.eval_named(cx, self.spec.name)
    }

    /// An expression's value as one component, within the declared range.
    fn checked(&self, value: &geode_op::ExprValue, frame: f64) -> Result<f64, String> {
        let x = match value {
            geode_op::ExprValue::Num(v) if v.len() == 1 => v[0],
            geode_op::ExprValue::Num(v) => {
                return Err(format!(
                    "the expression gives {} numbers at frame {frame}; a component takes one (write one expression per component, or .x)",
                    v.len()
                ))
            }
            geode_op::ExprValue::Str(s) => {
                return Err(format!(
                    "the expression gives the text {s:?} at frame {frame}; this parameter takes a number"
                ))
            }
        };
        if !x.is_finite() {
            return Err(format!("the expression gives {x} at frame {frame}"));
        }
        // Expressions compute in VEX's 32-bit floats: shown as such.
        let shown = x as f32;
        if let Some(min) = self.spec.min.filter(|m| x < *m) {
            return Err(format!(
                "the expression gives {shown} at frame {frame}, below the minimum {min}"
            ));
        }
        if let Some(max) = self.spec.max.filter(|m| x > *m) {
            return Err(format!(
                "the expression gives {shown} at frame {frame}, above the maximum {max}"
            ));
        }
        Ok(x)
    }
}
