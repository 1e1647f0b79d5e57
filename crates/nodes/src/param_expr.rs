//! The language of parameter expressions: the wrangle's (geode-vex), plugged
//! into the registry so the engine evaluates `sin($F)` in a field with the
//! same functions and semantics as in a snippet.

use std::sync::Arc;

use geode_op::{ExprError, ExprLanguage, ExprScope, ExprValue, Expression, TextPosition};
use geode_vex::Channel;

/// VEX expressions for parameters.
pub struct VexExpressions;

#[derive(Debug)]
struct Parsed(geode_vex::Expression);

fn error(e: geode_vex::CompileError) -> ExprError {
    ExprError {
        position: Some(TextPosition {
            line: e.pos.line,
            column: e.pos.col,
        }),
        message: e.msg,
    }
}

impl ExprLanguage for VexExpressions {
    fn parse(&self, text: &str) -> Result<Arc<dyn Expression>, ExprError> {
        Ok(Arc::new(Parsed(
            geode_vex::parse_expression(text).map_err(error)?,
        )))
    }
}

impl Expression for Parsed {
    fn references(&self) -> &[String] {
        self.0.references()
    }

    fn reads_time(&self) -> bool {
        self.0.reads_time()
    }

    fn eval(&self, scope: &ExprScope) -> Result<ExprValue, ExprError> {
        let channel = |path: &str| {
            (scope.channel)(path).map(|v| match v {
                ExprValue::Num(n) => Channel::Num(n),
                ExprValue::Str(s) => Channel::Str(s),
            })
        };
        let globals = geode_vex::Globals {
            frame: scope.frame,
            fps: scope.fps,
            hip: scope.hip,
            node: scope.node,
        };
        match self.0.eval(&globals, &channel).map_err(error)? {
            geode_vex::Value::Num(n) => Ok(ExprValue::Num(n)),
            geode_vex::Value::Str(s) => Ok(ExprValue::Str(s)),
        }
    }
}
