//! Compiling a field DAG into a flat tape: deduplicated SSA, constant folding, register allocation, and per-region simplification.

use std::collections::HashMap;

use std::sync::Arc;

use crate::dataset::Dataset;
use crate::field::{binary, unary, Binary, Field, Node, Unary};

/// One instruction. Arguments and outputs are registers (after allocation)
/// or SSA values (in [`Tape::ssa`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Instr {
    Var {
        out: u32,
        axis: u8,
    },
    Const {
        out: u32,
        value: f64,
    },
    Unary {
        op: Unary,
        out: u32,
        a: u32,
    },
    Binary {
        op: Binary,
        out: u32,
        a: u32,
        b: u32,
    },
    /// Dataset `set` (an index into [`Tape::dataset`]) at the point in
    /// registers `x`, `y`, `z`.
    Dataset {
        set: u32,
        out: u32,
        x: u32,
        y: u32,
        z: u32,
    },
}

impl Instr {
    pub fn out(&self) -> u32 {
        match *self {
            Instr::Var { out, .. }
            | Instr::Const { out, .. }
            | Instr::Unary { out, .. }
            | Instr::Binary { out, .. }
            | Instr::Dataset { out, .. } => out,
        }
    }

    fn args(&self) -> [Option<u32>; 3] {
        match *self {
            Instr::Var { .. } | Instr::Const { .. } => [None; 3],
            Instr::Unary { a, .. } => [Some(a), None, None],
            Instr::Binary { a, b, .. } => [Some(a), Some(b), None],
            Instr::Dataset { x, y, z, .. } => [Some(x), Some(y), Some(z)],
        }
    }

    /// The same operation writing `out` from arguments `args` (unused ones ignored).
    fn with(&self, out: u32, args: [u32; 3]) -> Instr {
        let [a, b, c] = args;
        match *self {
            Instr::Var { axis, .. } => Instr::Var { out, axis },
            Instr::Const { value, .. } => Instr::Const { out, value },
            Instr::Unary { op, .. } => Instr::Unary { op, out, a },
            Instr::Binary { op, .. } => Instr::Binary { op, out, a, b },
            Instr::Dataset { set, .. } => Instr::Dataset {
                set,
                out,
                x: a,
                y: b,
                z: c,
            },
        }
    }

    fn with_args(&self, out: u32, args: [Option<u32>; 3]) -> Instr {
        self.with(out, args.map(|a| a.unwrap_or(0)))
    }
}

/// Which argument of a `min`/`max` an interval evaluation proved decisive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Choice {
    /// Not a choice instruction, or both arguments may win.
    Both,
    Left,
    Right,
}

/// What an interval evaluation over a region proved: the decisive argument
/// of every `min`/`max`, and the datasets narrowed to what
/// may win there (by instruction index).
#[derive(Clone, Debug, Default)]
pub struct Choices {
    pub per_instr: Vec<Choice>,
    pub narrowed: Vec<(u32, Arc<Dataset>)>,
}

/// A compiled field: instructions in evaluation order over `slots` registers,
/// the result in register `output`.
#[derive(Clone, Debug)]
pub struct Tape {
    /// SSA form: instruction `i` writes value `i`.
    ssa: Vec<Instr>,
    /// The same instructions with registers allocated (one per SSA instruction).
    instrs: Vec<Instr>,
    slots: u32,
    output: u32,
    /// The datasets `Instr::Dataset` refers to.
    datasets: Vec<Arc<Dataset>>,
}

#[derive(Hash, PartialEq, Eq)]
enum Key {
    Var(u8),
    Const(u64),
    Unary(Unary, u32),
    Binary(Binary, u32, u32),
    Dataset(u128, [u32; 3]),
}

impl Tape {
    /// Compiles a field: shared and structurally equal sub-expressions are
    /// computed once, constant sub-expressions are folded.
    pub fn compile(field: &Field) -> Tape {
        let mut ssa: Vec<Instr> = Vec::new();
        let mut by_key: HashMap<Key, u32> = HashMap::new();
        let mut datasets: Vec<Arc<Dataset>> = Vec::new();
        let consts = |ssa: &Vec<Instr>, v: u32| match ssa[v as usize] {
            Instr::Const { value, .. } => Some(value),
            _ => None,
        };
        // Children first, each shared node once (iterative: deep DAGs of
        // thousands of ops must not overflow the stack).
        let output = field.fold(
            |_| true,
            |f, get: &dyn Fn(&Field) -> u32| {
                let (key, instr) = match f.node() {
                    Node::X => (Key::Var(0), Instr::Var { out: 0, axis: 0 }),
                    Node::Y => (Key::Var(1), Instr::Var { out: 0, axis: 1 }),
                    Node::Z => (Key::Var(2), Instr::Var { out: 0, axis: 2 }),
                    Node::Const(c) => (Key::Const(c.to_bits()), Instr::Const { out: 0, value: *c }),
                    Node::Unary(op, a) => {
                        let a = get(a);
                        match consts(&ssa, a) {
                            Some(v) => {
                                let c = unary(*op, v);
                                (Key::Const(c.to_bits()), Instr::Const { out: 0, value: c })
                            }
                            None => (Key::Unary(*op, a), Instr::Unary { op: *op, out: 0, a }),
                        }
                    }
                    Node::Binary(op, a, b) => {
                        let (a, b) = (get(a), get(b));
                        match (consts(&ssa, a), consts(&ssa, b)) {
                            (Some(x), Some(y)) => {
                                let c = binary(*op, x, y);
                                (Key::Const(c.to_bits()), Instr::Const { out: 0, value: c })
                            }
                            _ => (
                                Key::Binary(*op, a, b),
                                Instr::Binary {
                                    op: *op,
                                    out: 0,
                                    a,
                                    b,
                                },
                            ),
                        }
                    }
                    Node::Dataset(set, args) => {
                        let [x, y, z] = args.each_ref().map(get);
                        let index =
                            match datasets.iter().position(|s| s.identity() == set.identity()) {
                                Some(i) => i,
                                None => {
                                    datasets.push(Arc::clone(set));
                                    datasets.len() - 1
                                }
                            };
                        let instr = Instr::Dataset {
                            set: index as u32,
                            out: 0,
                            x,
                            y,
                            z,
                        };
                        (Key::Dataset(set.identity(), [x, y, z]), instr)
                    }
                };
                let id = *by_key.entry(key).or_insert_with(|| {
                    let id = ssa.len() as u32;
                    ssa.push(instr.with_args(id, instr.args()));
                    id
                });
                id
            },
        );
        Tape::from_ssa(ssa, output, datasets)
    }

    /// Keeps only what the output needs, then allocates registers.
    fn from_ssa(ssa: Vec<Instr>, output: u32, datasets: Vec<Arc<Dataset>>) -> Tape {
        // Backwards, which instructions the output needs and where each of
        // them is read last (the first reader met from the end): every
        // reader of an instruction comes after it, so its liveness is known
        // when it is reached.
        const DEAD: u32 = u32::MAX;
        const KEPT: u32 = u32::MAX - 1;
        let mut last_use = vec![DEAD; ssa.len()];
        last_use[output as usize] = KEPT;
        for (i, ins) in ssa.iter().enumerate().rev() {
            if last_use[i] == DEAD {
                continue;
            }
            for a in ins.args().into_iter().flatten() {
                if last_use[a as usize] == DEAD {
                    last_use[a as usize] = i as u32;
                }
            }
        }
        // Forwards, the live instructions renumbered and, by linear scan,
        // their registers: a register is reused after the last read of its
        // value. An output never shares its arguments' registers, so batch
        // evaluation can borrow them apart.
        let mut new_id = vec![0u32; ssa.len()];
        let mut reg_of = vec![0u32; ssa.len()];
        let mut free: Vec<u32> = Vec::new();
        let mut slots = 0u32;
        let mut compact = Vec::with_capacity(ssa.len());
        let mut instrs = Vec::with_capacity(ssa.len());
        for (i, ins) in ssa.iter().enumerate() {
            if last_use[i] == DEAD {
                continue;
            }
            let args = ins.args();
            let ids = args.map(|a| a.map_or(0, |a| new_id[a as usize]));
            let regs = args.map(|a| a.map_or(0, |a| reg_of[a as usize]));
            let out = free.pop().unwrap_or_else(|| {
                slots += 1;
                slots - 1
            });
            for (k, x) in args.iter().enumerate() {
                let Some(x) = *x else { continue };
                // A value read twice here (x * x) frees its register once; no
                // other live value's register can be free already.
                if last_use[x as usize] == i as u32 && !args[..k].contains(&Some(x)) {
                    free.push(reg_of[x as usize]);
                }
            }
            reg_of[i] = out;
            new_id[i] = compact.len() as u32;
            compact.push(ins.with(compact.len() as u32, ids));
            instrs.push(ins.with(out, regs));
        }
        Tape {
            ssa: compact,
            instrs,
            slots: slots.max(1),
            output: reg_of[output as usize],
            datasets,
        }
    }

    /// Instructions with registers allocated, in evaluation order.
    pub fn instrs(&self) -> &[Instr] {
        &self.instrs
    }

    pub fn slots(&self) -> usize {
        self.slots as usize
    }

    pub fn output(&self) -> usize {
        self.output as usize
    }

    /// The dataset an `Instr::Dataset` names.
    pub fn dataset(&self, set: u32) -> &Dataset {
        &self.datasets[set as usize]
    }

    pub fn len(&self) -> usize {
        self.instrs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.instrs.is_empty()
    }

    /// A shorter tape valid wherever `choices` (from an interval evaluation
    /// over a region) hold: every decided `min`/`max` is replaced by the
    /// winning argument, datasets by their narrowed ones, and what no
    /// longer matters is dropped.
    pub fn simplify(&self, choices: &Choices) -> Tape {
        let per_instr = &choices.per_instr;
        assert_eq!(
            per_instr.len(),
            self.ssa.len(),
            "one choice per instruction"
        );
        let mut alias: Vec<u32> = (0..self.ssa.len() as u32).collect();
        let mut ssa: Vec<Instr> = Vec::with_capacity(self.ssa.len());
        let mut datasets = self.datasets.clone();
        let mut narrowed = choices.narrowed.iter().peekable();
        for (i, ins) in self.ssa.iter().enumerate() {
            let args = ins.args().map(|x| x.map(|x| alias[x as usize]));
            let mut ins = *ins;
            match (&mut ins, per_instr[i]) {
                (
                    Instr::Binary {
                        op: Binary::Min | Binary::Max,
                        ..
                    },
                    Choice::Left,
                ) => alias[i] = args[0].expect("binary"),
                (
                    Instr::Binary {
                        op: Binary::Min | Binary::Max,
                        ..
                    },
                    Choice::Right,
                ) => alias[i] = args[1].expect("binary"),
                (Instr::Dataset { set, .. }, _) => {
                    if let Some((_, narrow)) = narrowed.next_if(|(at, _)| *at as usize == i) {
                        *set = datasets.len() as u32;
                        datasets.push(Arc::clone(narrow));
                    }
                }
                _ => {}
            }
            ssa.push(ins.with_args(i as u32, args));
        }
        let output = alias[self.output_ssa() as usize];
        let mut tape = Tape::from_ssa(ssa, output, datasets);
        tape.drop_unused_datasets();
        tape
    }

    /// Keeps only the datasets live instructions name, renumbered.
    fn drop_unused_datasets(&mut self) {
        let mut renumber: Vec<Option<u32>> = vec![None; self.datasets.len()];
        let mut kept = Vec::new();
        for ins in self.ssa.iter_mut().chain(self.instrs.iter_mut()) {
            if let Instr::Dataset { set, .. } = ins {
                let new = *renumber[*set as usize].get_or_insert_with(|| {
                    kept.push(Arc::clone(&self.datasets[*set as usize]));
                    kept.len() as u32 - 1
                });
                *set = new;
            }
        }
        self.datasets = kept;
    }

    fn output_ssa(&self) -> u32 {
        (self.ssa.len() - 1) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_and_equal_subexpressions_compile_once() {
        let x = Field::x();
        let r2 = &x * &x + Field::y() * Field::y();
        // The same structure built twice dedupes; constants fold.
        let again = Field::x() * Field::x() + Field::y() * Field::y();
        let f = (r2.clone() - (Field::constant(2.0) * 3.0)).max(again - 6.0);
        let t = Tape::compile(&f);
        // x, y, x*x, y*y, +, const 6, -, max(a, a) = 8 instructions.
        assert_eq!(t.len(), 8);
        assert!(t.slots() <= 4, "registers are reused: {}", t.slots());
    }

    #[test]
    fn deep_chains_do_not_overflow() {
        let mut f = Field::x();
        for i in 0..200_000 {
            f = f + (i as f64 * 1e-6);
        }
        let t = Tape::compile(&f);
        assert_eq!(t.slots(), 3);
    }
}
