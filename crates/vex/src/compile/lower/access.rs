//! Lowering of element access: vector and matrix components (`v[0]`,
//! swizzles like `v.zyx`), array and string indexing and slices.

use crate::compile::ast::*;
use crate::compile::lex::Pos;
use crate::ir::*;
use crate::library::array_ops;
use crate::ty::Ty;

use super::{LResult, Lower};

use super::expr::{err, Target};

/// Component index of a swizzle letter.
fn component(c: char) -> Option<u32> {
    match c {
        'x' | 'r' | 'u' => Some(0),
        'y' | 'g' | 'v' => Some(1),
        'z' | 'b' => Some(2),
        'w' | 'a' => Some(3),
        _ => None,
    }
}

impl Lower<'_> {
    /// `v[k]` of a vector (a component) or a matrix (a row), `k` constant:
    /// the registers themselves, so it reads and assigns alike.
    pub(super) fn component(&mut self, v: Loc, i: &Expr) -> LResult<Loc> {
        let t = v.ty;
        let k = self.const_index(i)?;
        let width = if t.is_matrix() {
            (t.floats() as f64).sqrt() as u32
        } else {
            t.floats() as u32
        };
        if k >= width {
            return err(i.pos, format!("index {k} is past the end of {}", t.a()));
        }
        if t.is_matrix() {
            let row = Ty::of_floats(width as usize).expect("a row");
            return Ok(Loc {
                ty: row,
                reg: v.reg + k * width,
            });
        }
        Ok(Loc {
            ty: Ty::Float,
            reg: v.reg + k,
        })
    }

    pub(super) fn const_index(&mut self, i: &Expr) -> LResult<u32> {
        match i.kind {
            ExprKind::Int(k) if k >= 0 => Ok(k as u32),
            _ => err(i.pos, "a vector or matrix index must be a constant"),
        }
    }

    pub fn read_target(&mut self, t: Target, pos: Pos) -> LResult<Loc> {
        match t {
            Target::Regs(l) => Ok(l),
            Target::Elem { arr, idx } => {
                let Ty::Array(e) = arr.ty else {
                    return err(pos, "not an array");
                };
                Ok(self.call_site(array_ops::INDEX_GET, vec![arr, idx], e.ty(), pos))
            }
        }
    }

    pub fn write_target(&mut self, t: Target, v: Loc, pos: Pos) -> LResult<()> {
        match t {
            Target::Regs(l) => {
                let v = self.convert(v, l.ty, pos)?;
                self.store(l, v);
            }
            Target::Elem { arr, idx } => {
                let Ty::Array(e) = arr.ty else {
                    return err(pos, "not an array");
                };
                let v = self.convert(v, e.ty(), pos)?;
                self.call_site_outs(
                    array_ops::INDEX_SET,
                    vec![arr, idx, v],
                    vec![true, false, false],
                    Ty::Void,
                    pos,
                );
            }
        }
        Ok(())
    }

    pub(super) fn components(&self, ty: Ty, name: &str, pos: Pos) -> LResult<Vec<u32>> {
        if ty.is_matrix() {
            // m.xx, m.xy ... : row then column.
            let n = if ty == Ty::Mat3 { 3 } else { 4 };
            let cs: Vec<u32> = name.chars().filter_map(component).collect();
            if cs.len() == 2 && name.len() == 2 && cs.iter().all(|&c| c < n) {
                return Ok(vec![cs[0] * n + cs[1]]);
            }
            return err(pos, format!("{} has no component '.{name}'", ty.a()));
        }
        let width = ty.floats() as u32;
        let cs: Option<Vec<u32>> = name
            .chars()
            .map(|c| component(c).filter(|&k| k < width))
            .collect();
        match cs {
            Some(cs) if ty.is_vector() && !cs.is_empty() && cs.len() <= 4 => Ok(cs),
            _ => err(pos, format!("{} has no component '.{name}'", ty.a())),
        }
    }

    pub(super) fn swizzle(&mut self, v: Loc, name: &str, pos: Pos) -> LResult<Loc> {
        let cs = self.components(v.ty, name, pos)?;
        if cs.len() == 1 {
            return Ok(Loc {
                ty: Ty::Float,
                reg: v.reg + cs[0],
            });
        }
        let ty = Ty::of_floats(cs.len()).expect("2 to 4 components");
        let out = self.alloc(ty);
        for (k, c) in cs.iter().enumerate() {
            self.emit_op(Op::FMov {
                d: out.reg + k as u32,
                s: v.reg + c,
            });
        }
        Ok(out)
    }

    /// `seq[start:end:step]`: the parts left out are marked in the last
    /// argument (bit 0 start, bit 1 end).
    pub(super) fn slice(
        &mut self,
        seq: &Expr,
        parts: [&Option<Box<Expr>>; 3],
        pos: Pos,
    ) -> LResult<Loc> {
        let v = self.expr(seq, None)?;
        if !matches!(v.ty, Ty::Array(_) | Ty::Str) {
            return err(pos, format!("{} cannot be sliced", v.ty.a()));
        }
        let mut args = vec![v];
        let mut given = 0;
        for (k, part) in parts.into_iter().enumerate() {
            let value = match part {
                Some(x) => {
                    if k < 2 {
                        given |= 1 << k;
                    }
                    let i = self.expr(x, Some(Ty::Int))?;
                    self.convert(i, Ty::Int, x.pos)?
                }
                None => self.iconst(i32::from(k == 2)),
            };
            args.push(value);
        }
        args.push(self.iconst(given));
        Ok(self.call_site(array_ops::SLICE, args, v.ty, pos))
    }

    pub(super) fn index(&mut self, v: Loc, i: &Expr, pos: Pos) -> LResult<Loc> {
        match v.ty {
            Ty::Array(e) => {
                let idx = self.expr(i, Some(Ty::Int))?;
                let idx = self.convert(idx, Ty::Int, i.pos)?;
                Ok(self.call_site(array_ops::INDEX_GET, vec![v, idx], e.ty(), pos))
            }
            Ty::Str => {
                let idx = self.expr(i, Some(Ty::Int))?;
                let idx = self.convert(idx, Ty::Int, i.pos)?;
                Ok(self.call_site(array_ops::INDEX_GET, vec![v, idx], Ty::Str, pos))
            }
            t if t.is_vector() || t.is_matrix() => self.component(v, i),
            t => err(pos, format!("{} cannot be indexed", t.a())),
        }
    }
}
