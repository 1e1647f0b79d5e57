//! Fields as expression DAGs: `f(x, y, z) >= 0` inside (HyperFun's convention), built with operators and methods.

use std::ops;
use std::sync::Arc;

use crate::capsules::CapsuleSet;
use crate::dataset::Dataset;
use crate::mesh_distance::MeshDistance;
use crate::volume::VolumeField;

/// One-argument operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Unary {
    Neg,
    Abs,
    Sqrt,
    Square,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Exp,
    Ln,
    Floor,
    Ceil,
    Round,
    /// 1 where the argument is 0, else 0.
    Not,
}

/// Two-argument operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Binary {
    Add,
    Sub,
    Mul,
    Div,
    Min,
    Max,
    Atan2,
    /// Euclidean remainder (always in [0, |b|)).
    Mod,
    /// The sign of a - b: -1, 0 or 1.
    Compare,
    /// b where a is non-zero, else a (0).
    And,
    /// a where a is non-zero, else b.
    Or,
}

/// A node of the DAG.
impl Unary {
    /// Every operation. The field codec numbers them by their place here:
    /// append, never reorder.
    pub const ALL: [Unary; 16] = [
        Unary::Neg,
        Unary::Abs,
        Unary::Sqrt,
        Unary::Square,
        Unary::Sin,
        Unary::Cos,
        Unary::Tan,
        Unary::Asin,
        Unary::Acos,
        Unary::Atan,
        Unary::Exp,
        Unary::Ln,
        Unary::Floor,
        Unary::Ceil,
        Unary::Round,
        Unary::Not,
    ];
}

impl Binary {
    /// Every operation. The field codec numbers them by their place here:
    /// append, never reorder.
    pub const ALL: [Binary; 11] = [
        Binary::Add,
        Binary::Sub,
        Binary::Mul,
        Binary::Div,
        Binary::Min,
        Binary::Max,
        Binary::Atan2,
        Binary::Mod,
        Binary::Compare,
        Binary::And,
        Binary::Or,
    ];
}

#[derive(Debug, PartialEq)]
pub enum Node {
    X,
    Y,
    Z,
    Const(f64),
    Unary(Unary, Field),
    Binary(Binary, Field, Field),
    /// Data (a union of capsules, a mesh's distance) evaluated at the point
    /// given by three fields (x, y and z unless space-mapped).
    Dataset(Arc<Dataset>, [Field; 3]),
}

/// A node with its structural hash and size, computed once at construction.
#[derive(Debug, PartialEq)]
pub(crate) struct Inner {
    node: Node,
    hash: u128,
    size: u64,
}

/// A scalar field over space: a shared DAG of [`Node`]s. Cloning shares.
/// Equal structure gives an equal [`Field::identity`], however it was built.
#[derive(Clone, Debug, PartialEq)]
pub struct Field(pub(crate) Arc<Inner>);

fn make(node: Node) -> Field {
    use xxhash_rust::xxh3::Xxh3;
    let mut h = Xxh3::new();
    let size = match &node {
        Node::X => {
            h.update(b"x");
            1
        }
        Node::Y => {
            h.update(b"y");
            1
        }
        Node::Z => {
            h.update(b"z");
            1
        }
        Node::Const(c) => {
            h.update(b"c");
            h.update(&c.to_bits().to_le_bytes());
            1
        }
        Node::Unary(op, a) => {
            h.update(format!("u{op:?}").as_bytes());
            h.update(&a.0.hash.to_le_bytes());
            a.0.size.saturating_add(1)
        }
        Node::Binary(op, a, b) => {
            h.update(format!("b{op:?}").as_bytes());
            h.update(&a.0.hash.to_le_bytes());
            h.update(&b.0.hash.to_le_bytes());
            a.0.size.saturating_add(b.0.size).saturating_add(1)
        }
        Node::Dataset(set, args) => {
            h.update(b"dataset");
            h.update(&set.identity().to_le_bytes());
            for a in args {
                h.update(&a.0.hash.to_le_bytes());
            }
            let args = args.iter().fold(0u64, |s, a| s.saturating_add(a.0.size));
            args.saturating_add(set.len() as u64)
        }
    };
    Field(Arc::new(Inner {
        node,
        hash: h.digest128(),
        size,
    }))
}

impl Field {
    pub fn x() -> Field {
        make(Node::X)
    }

    pub fn y() -> Field {
        make(Node::Y)
    }

    pub fn z() -> Field {
        make(Node::Z)
    }

    pub fn constant(v: f64) -> Field {
        make(Node::Const(v))
    }

    /// The union of a set of capsules at (x, y, z).
    pub fn capsules(set: CapsuleSet) -> Field {
        Field::dataset_at(
            &Arc::new(Dataset::Capsules(set)),
            [Field::x(), Field::y(), Field::z()],
        )
    }

    /// A mesh's signed distance at (x, y, z).
    pub fn mesh(mesh: MeshDistance) -> Field {
        Field::dataset_at(
            &Arc::new(Dataset::Mesh(mesh)),
            [Field::x(), Field::y(), Field::z()],
        )
    }

    /// A sparse volume's values at (x, y, z) (see [`VolumeField`]).
    pub fn volume(volume: VolumeField) -> Field {
        Field::dataset_at(
            &Arc::new(Dataset::Volume(volume)),
            [Field::x(), Field::y(), Field::z()],
        )
    }

    /// Shared data (capsules, a mesh, a volume) evaluated at the point `args` give.
    pub fn dataset_at(set: &Arc<Dataset>, args: [Field; 3]) -> Field {
        make(Node::Dataset(Arc::clone(set), args))
    }

    pub fn node(&self) -> &Node {
        &self.0.node
    }

    /// Structural identity (xxh3-128): equal for structurally equal fields.
    pub fn identity(&self) -> u128 {
        self.0.hash
    }

    /// Nodes of the expanded tree (an upper bound on the DAG's, saturating).
    pub fn tree_size(&self) -> u64 {
        self.0.size
    }

    /// Bytes held by the shared DAG: its distinct nodes and datasets.
    pub fn memory_bytes(&self) -> usize {
        let mut sets = std::collections::HashSet::new();
        let mut bytes = 0;
        self.fold(
            |_| true,
            |f, _: &dyn Fn(&Field)| {
                bytes += std::mem::size_of::<Inner>() + 16;
                if let Node::Dataset(set, _) = f.node() {
                    if sets.insert(Arc::as_ptr(set)) {
                        bytes += set.memory_bytes();
                    }
                }
            },
        );
        bytes
    }

    /// The nodes this one reads, in order.
    pub fn children(&self) -> Vec<&Field> {
        match self.node() {
            Node::Unary(_, a) => vec![a],
            Node::Binary(_, a, b) => vec![a, b],
            Node::Dataset(_, args) => args.iter().collect(),
            Node::X | Node::Y | Node::Z | Node::Const(_) => Vec::new(),
        }
    }

    /// A value per node, children first (in order), each shared node once: `visit`
    /// gets the node and the values of its children (looked up by the
    /// function it is given). Iterative, so chains of many thousands of
    /// nodes do not overflow the stack. Nodes `descend` rejects get no
    /// children visited (their lookups must not be called).
    pub fn fold<T: Clone>(
        &self,
        descend: impl Fn(&Field) -> bool,
        mut visit: impl FnMut(&Field, &dyn Fn(&Field) -> T) -> T,
    ) -> T {
        let mut done: std::collections::HashMap<*const (), T> = std::collections::HashMap::new();
        let mut stack: Vec<(&Field, bool)> = vec![(self, false)];
        while let Some((f, ready)) = stack.pop() {
            if done.contains_key(&f.ptr()) {
                continue;
            }
            if !ready && descend(f) {
                stack.push((f, true));
                // Reversed, so the first child is visited first.
                stack.extend(f.children().into_iter().rev().map(|c| (c, false)));
                continue;
            }
            let value = visit(f, &|c: &Field| done[&c.ptr()].clone());
            done.insert(f.ptr(), value);
        }
        done.remove(&self.ptr()).expect("the root is visited last")
    }

    /// The address identifying this shared node (for memoised traversals).
    pub(crate) fn ptr(&self) -> *const () {
        Arc::as_ptr(&self.0) as *const ()
    }

    pub fn unary(&self, op: Unary) -> Field {
        make(Node::Unary(op, self.clone()))
    }

    pub fn binary(&self, op: Binary, other: impl Into<Field>) -> Field {
        make(Node::Binary(op, self.clone(), other.into()))
    }

    pub fn abs(&self) -> Field {
        self.unary(Unary::Abs)
    }
    pub fn sqrt(&self) -> Field {
        self.unary(Unary::Sqrt)
    }
    pub fn square(&self) -> Field {
        self.unary(Unary::Square)
    }
    pub fn sin(&self) -> Field {
        self.unary(Unary::Sin)
    }
    pub fn cos(&self) -> Field {
        self.unary(Unary::Cos)
    }
    pub fn tan(&self) -> Field {
        self.unary(Unary::Tan)
    }
    pub fn asin(&self) -> Field {
        self.unary(Unary::Asin)
    }
    pub fn acos(&self) -> Field {
        self.unary(Unary::Acos)
    }
    pub fn atan(&self) -> Field {
        self.unary(Unary::Atan)
    }
    pub fn exp(&self) -> Field {
        self.unary(Unary::Exp)
    }
    pub fn ln(&self) -> Field {
        self.unary(Unary::Ln)
    }
    pub fn floor(&self) -> Field {
        self.unary(Unary::Floor)
    }
    pub fn ceil(&self) -> Field {
        self.unary(Unary::Ceil)
    }
    pub fn round(&self) -> Field {
        self.unary(Unary::Round)
    }
    pub fn min(&self, o: impl Into<Field>) -> Field {
        self.binary(Binary::Min, o)
    }
    pub fn max(&self, o: impl Into<Field>) -> Field {
        self.binary(Binary::Max, o)
    }
    pub fn atan2(&self, o: impl Into<Field>) -> Field {
        self.binary(Binary::Atan2, o)
    }
    pub fn modulo(&self, o: impl Into<Field>) -> Field {
        self.binary(Binary::Mod, o)
    }

    /// Evaluates by walking the DAG (slow; the reference for the tape evaluators).
    pub fn eval_tree(&self, p: [f64; 3]) -> f64 {
        match self.node() {
            Node::X => p[0],
            Node::Y => p[1],
            Node::Z => p[2],
            Node::Const(c) => *c,
            Node::Unary(op, a) => unary(*op, a.eval_tree(p)),
            Node::Binary(op, a, b) => binary(*op, a.eval_tree(p), b.eval_tree(p)),
            Node::Dataset(set, args) => set.value(args.each_ref().map(|a| a.eval_tree(p))),
        }
    }
}

/// Dropping is iterative: a field may be a chain of many thousands of nodes,
/// which a recursive drop would overflow the stack on.
impl Drop for Field {
    fn drop(&mut self) {
        fn take_children(arc: &mut Arc<Inner>, stack: &mut Vec<Field>) {
            if let Some(inner) = Arc::get_mut(arc) {
                match std::mem::replace(&mut inner.node, Node::X) {
                    Node::Unary(_, a) => stack.push(a),
                    Node::Binary(_, a, b) => {
                        stack.push(a);
                        stack.push(b);
                    }
                    Node::Dataset(_, args) => stack.extend(args),
                    _ => {}
                }
            }
        }
        let mut stack = Vec::new();
        take_children(&mut self.0, &mut stack);
        while let Some(mut f) = stack.pop() {
            take_children(&mut f.0, &mut stack);
        }
    }
}

/// The scalar semantics every evaluator reproduces.
#[inline(always)]
pub fn unary(op: Unary, a: f64) -> f64 {
    match op {
        Unary::Neg => -a,
        Unary::Abs => a.abs(),
        Unary::Sqrt => a.sqrt(),
        Unary::Square => a * a,
        Unary::Sin => a.sin(),
        Unary::Cos => a.cos(),
        Unary::Tan => a.tan(),
        Unary::Asin => a.asin(),
        Unary::Acos => a.acos(),
        Unary::Atan => a.atan(),
        Unary::Exp => a.exp(),
        Unary::Ln => a.ln(),
        Unary::Floor => a.floor(),
        Unary::Ceil => a.ceil(),
        Unary::Round => a.round(),
        Unary::Not => (a == 0.0) as u8 as f64,
    }
}

/// The scalar semantics every evaluator reproduces.
#[inline]
pub fn binary(op: Binary, a: f64, b: f64) -> f64 {
    match op {
        Binary::Add => a + b,
        Binary::Sub => a - b,
        Binary::Mul => a * b,
        Binary::Div => a / b,
        Binary::Min => a.min(b),
        Binary::Max => a.max(b),
        Binary::Atan2 => a.atan2(b),
        Binary::Mod => a.rem_euclid(b),
        Binary::Compare => {
            if a < b {
                -1.0
            } else if a > b {
                1.0
            } else {
                0.0
            }
        }
        Binary::And => {
            if a == 0.0 {
                a
            } else {
                b
            }
        }
        Binary::Or => {
            if a != 0.0 {
                a
            } else {
                b
            }
        }
    }
}

impl From<f64> for Field {
    fn from(v: f64) -> Field {
        Field::constant(v)
    }
}

impl From<&Field> for Field {
    fn from(f: &Field) -> Field {
        f.clone()
    }
}

macro_rules! binop {
    ($trait:ident, $method:ident, $op:ident) => {
        impl<T: Into<Field>> ops::$trait<T> for Field {
            type Output = Field;
            fn $method(self, rhs: T) -> Field {
                self.binary(Binary::$op, rhs)
            }
        }
        impl<T: Into<Field>> ops::$trait<T> for &Field {
            type Output = Field;
            fn $method(self, rhs: T) -> Field {
                self.binary(Binary::$op, rhs)
            }
        }
        impl ops::$trait<Field> for f64 {
            type Output = Field;
            fn $method(self, rhs: Field) -> Field {
                Field::constant(self).binary(Binary::$op, rhs)
            }
        }
        impl ops::$trait<&Field> for f64 {
            type Output = Field;
            fn $method(self, rhs: &Field) -> Field {
                Field::constant(self).binary(Binary::$op, rhs)
            }
        }
    };
}

binop!(Add, add, Add);
binop!(Sub, sub, Sub);
binop!(Mul, mul, Mul);
binop!(Div, div, Div);

impl ops::Neg for Field {
    type Output = Field;
    fn neg(self) -> Field {
        self.unary(Unary::Neg)
    }
}

impl ops::Neg for &Field {
    type Output = Field;
    fn neg(self) -> Field {
        self.unary(Unary::Neg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_is_structural() {
        let a = Field::x() * 2.0 + Field::y().sin();
        let b = Field::x() * 2.0 + Field::y().sin();
        assert_eq!(a.identity(), b.identity());
        assert_ne!(
            a.identity(),
            (Field::x() * 2.5 + Field::y().sin()).identity()
        );
        assert_ne!(
            (Field::x() - Field::y()).identity(),
            (Field::y() - Field::x()).identity()
        );
        assert_eq!(a.tree_size(), 6);
    }
}
