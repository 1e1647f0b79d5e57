//! Loops, solvers, for-each and time shifts: the cook engine running a
//! block's body pass after pass with its feeds, a node at another frame,
//! and pieces cooked apart and merged.

use std::sync::atomic::AtomicBool;
use std::sync::{Mutex, OnceLock};

use geode_op::{CookError, ErrorKind, Value};

use crate::block::{self, BlockKind, FeedSlot, ForEach};
use crate::network::NodeKind;

use super::{load_problem, CookOptions, Cooked, Run};

impl Run<'_, '_> {
    /// Runs `f` on a fresh run of the network at `frame` whose feed nodes
    /// give `feeds` (a loop's or solver's pass); its events join this run's.
    fn pass<T>(&self, frame: f64, feeds: Vec<(usize, Cooked)>, f: impl FnOnce(&Run) -> T) -> T {
        let opts = CookOptions {
            frame,
            cancel: self.opts.cancel.clone(),
            progress: self.opts.progress,
            env: self.opts.env.clone(),
            writes: self.opts.writes,
        };
        let run = Run {
            engine: self.engine,
            opts: &opts,
            slots: (0..self.engine.net.nodes.len())
                .map(|_| OnceLock::new())
                .collect(),
            read: (0..self.engine.net.nodes.len())
                .map(|_| AtomicBool::new(false))
                .collect(),
            feeds,
            events: Mutex::new(Vec::new()),
            began: self.began,
        };
        let out = f(&run);
        let events = run.events.into_inner().unwrap_or_else(|p| p.into_inner());
        self.events
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .extend(events);
        out
    }

    /// A feed's value: the pass's, or outside a pass (solo view of a node in
    /// a block) the first pass's.
    pub(super) fn feed(
        &self,
        i: usize,
        block: usize,
        slot: FeedSlot,
    ) -> Result<Cooked, Vec<CookError>> {
        if let Some((_, c)) = self.feeds.iter().find(|(j, _)| *j == i) {
            return Ok(c.clone());
        }
        let net = &self.engine.net;
        match slot {
            FeedSlot::Input(k) => match net.nodes[block].inputs.get(k).copied().flatten() {
                Some(j) => self.node(j),
                None => Err(vec![CookError::new(
                    &net.nodes[i].path,
                    ErrorKind::Input,
                    format!("input {k} of {} is not connected", net.nodes[block].path),
                )]),
            },
            FeedSlot::Meta => Ok(Cooked::of(block::meta(&[
                ("iteration", 0),
                ("numiterations", 1),
            ]))),
        }
    }

    /// The feeds of one pass of block `i`: the feedback, the block's other
    /// inputs and the pass's numbers.
    fn feeds_of(
        &self,
        i: usize,
        feedback: &Cooked,
        inputs: &[Option<Cooked>],
        meta: &Cooked,
    ) -> Vec<(usize, Cooked)> {
        let net = &self.engine.net;
        (0..net.nodes.len())
            .filter_map(|j| match &net.nodes[j].kind {
                NodeKind::Feed { block, slot } if *block == i => match slot {
                    FeedSlot::Input(0) => Some((j, feedback.clone())),
                    FeedSlot::Input(k) => inputs.get(*k).cloned().flatten().map(|c| (j, c)),
                    FeedSlot::Meta => Some((j, meta.clone())),
                },
                _ => None,
            })
            .collect()
    }

    /// Cooks a loop (N passes, or until its stop attribute) or a solver
    /// (a pass per frame from its start frame to this one).
    pub(super) fn cook_block(
        &self,
        i: usize,
        kind: BlockKind,
        output: Option<usize>,
        inputs: Vec<Option<Cooked>>,
    ) -> Result<Cooked, Vec<CookError>> {
        let net = &self.engine.net;
        let path = net.nodes[i].path.clone();
        let fail = |m: String| vec![CookError::new(&path, ErrorKind::Network, m)];
        let out = output.ok_or_else(|| fail(format!("the {} has no output node", kind.name())))?;
        let first = inputs
            .first()
            .cloned()
            .flatten()
            .ok_or_else(|| fail(format!("the {} needs input 1 to start from", kind.name())))?;
        let params = net
            .params_at(i, self.opts.frame, &self.opts.env)
            .map_err(|e| vec![load_problem(&e)])?;
        let mut value = first;
        match kind {
            BlockKind::Loop => {
                let (n, stop) = block::loop_settings(&params).map_err(|e| vec![e])?;
                value = self.feedback(i, out, n, &stop, value, &inputs)?;
            }
            // Cooked before its inputs are (`cook_node`); never reaches here.
            BlockKind::TimeShift => return self.time_shift(i),
            BlockKind::ForEach => match block::for_each_settings(&params).map_err(|e| vec![e])? {
                ForEach::Count(n, stop) => {
                    value = self.feedback(i, out, n, &stop, value, &inputs)?
                }
                how => value = self.each_piece(i, out, &how, value, &inputs)?,
            },
            BlockKind::Solver => {
                let start = block::start_frame(&params).map_err(|e| vec![e])?;
                let frame = self.opts.frame;
                if frame < start {
                    return Ok(value);
                }
                // The input at the start frame, and the other inputs at each frame.
                let input_node = net.nodes[i].inputs[0].expect("input 1 is connected");
                if frame != start {
                    value = self.pass(start, Vec::new(), |r| r.node(input_node))?;
                }
                let mut f = start;
                loop {
                    if self.opts.cancel.is_cancelled() {
                        return Err(vec![CookError::cancelled(&path)]);
                    }
                    let at_f: Vec<Option<Cooked>> = if f == frame {
                        inputs.clone()
                    } else {
                        let nodes = net.nodes[i].inputs.clone();
                        self.pass(f, Vec::new(), |r| {
                            nodes
                                .iter()
                                .map(|n| n.map(|j| r.node(j)).transpose())
                                .collect::<Result<Vec<_>, _>>()
                        })?
                    };
                    let meta = Cooked::of(block::meta(&[
                        ("frame", f as i32),
                        ("start_frame", start as i32),
                    ]));
                    let feeds = self.feeds_of(i, &value, &at_f, &meta);
                    value = self.pass(f, feeds, |r| r.node(out)).map_err(|e| {
                        e.into_iter()
                            .map(|x| block::in_pass(x, &path, &format!("frame {f}")))
                            .collect::<Vec<_>>()
                    })?;
                    if f + 1.0 > frame {
                        break;
                    }
                    f += 1.0;
                }
            }
        }
        Ok(value)
    }

    /// Whether `n` is a time shift (not bypassed).
    pub(super) fn shifts_time(n: &crate::network::Node) -> bool {
        !n.bypass
            && matches!(&n.kind, NodeKind::Subnet { block: Some(b), .. } if b.kind == BlockKind::TimeShift)
    }

    /// A time shift: its input cooked at the frame its parameters give,
    /// in a pass of its own (a block's feeds carried in).
    pub(super) fn time_shift(&self, i: usize) -> Result<Cooked, Vec<CookError>> {
        let net = &self.engine.net;
        let n = &net.nodes[i];
        let params = net
            .params_at(i, self.opts.frame, &self.opts.env)
            .map_err(|e| vec![load_problem(&e)])?;
        let frame = block::shifted_frame(&params, self.opts.frame).map_err(|e| vec![e])?;
        let Some(input) = n.inputs.first().copied().flatten() else {
            return Err(vec![CookError::new(
                &n.path,
                ErrorKind::Input,
                "input 1 is not connected",
            )]);
        };
        if frame == self.opts.frame {
            return self.node(input);
        }
        self.pass(frame, self.feeds.clone(), |r| r.node(input))
    }

    /// `n` passes of block `i`'s network, each on the previous one's
    /// result, until a pass's `stop` detail attribute says so.
    fn feedback(
        &self,
        i: usize,
        out: usize,
        n: usize,
        stop: &str,
        mut value: Cooked,
        inputs: &[Option<Cooked>],
    ) -> Result<Cooked, Vec<CookError>> {
        let path = &self.engine.net.nodes[i].path;
        for k in 0..n {
            if self.opts.cancel.is_cancelled() {
                return Err(vec![CookError::cancelled(path)]);
            }
            let meta = Cooked::of(block::meta(&[
                ("iteration", k as i32),
                ("numiterations", n as i32),
            ]));
            let feeds = self.feeds_of(i, &value, inputs, &meta);
            value = self
                .pass(self.opts.frame, feeds, |r| r.node(out))
                .map_err(|e| {
                    e.into_iter()
                        .map(|x| block::in_pass(x, path, &format!("iteration {k}")))
                        .collect::<Vec<_>>()
                })?;
            if block::stops(&value.value, stop) {
                break;
            }
        }
        Ok(value)
    }

    /// Block `i`'s network once per piece of `first` (in parallel), the
    /// results merged in piece order.
    fn each_piece(
        &self,
        i: usize,
        out: usize,
        how: &ForEach,
        first: Cooked,
        inputs: &[Option<Cooked>],
    ) -> Result<Cooked, Vec<CookError>> {
        use rayon::prelude::*;
        let path = &self.engine.net.nodes[i].path;
        let fail = |kind, m: String| vec![CookError::new(path, kind, m)];
        let Some(g) = first.value.as_geometry() else {
            return Err(fail(
                ErrorKind::Input,
                "input 1 is not a geometry: a for-each over pieces splits geometry".into(),
            ));
        };
        let cancel = || self.opts.cancel.is_cancelled();
        let pieces = block::pieces_of(g, how, &cancel)
            .map_err(|m| fail(ErrorKind::Parameter, m))?
            .ok_or_else(|| vec![CookError::cancelled(path)])?;
        let count = pieces.len();
        // A cancel stops the passes not yet begun; otherwise every piece
        // cooks, so the error reported is the first in piece order
        // whatever the threads did.
        let results: Vec<Result<Cooked, Vec<CookError>>> = pieces
            .into_par_iter()
            .enumerate()
            .map(|(k, (piece, value))| {
                if self.opts.cancel.is_cancelled() {
                    return Err(vec![CookError::cancelled(path)]);
                }
                let meta = Cooked::of(block::piece_meta(k, count, &value));
                let feeds = self.feeds_of(i, &Cooked::of(Value::geometry(piece)), inputs, &meta);
                self.pass(self.opts.frame, feeds, |r| r.node(out))
                    .map_err(|e| {
                        e.into_iter()
                            .map(|x| block::in_pass(x, path, &format!("piece {k}")))
                            .collect::<Vec<_>>()
                    })
            })
            .collect();
        if self.opts.cancel.is_cancelled() {
            return Err(vec![CookError::cancelled(path)]);
        }
        let mut cooked = Vec::with_capacity(count);
        for r in results {
            cooked.push(r?);
        }
        let geometries: Vec<&geode_geo::Geometry> = cooked
            .iter()
            .filter_map(|c| c.value.as_geometry().map(|g| &**g))
            .collect();
        if geometries.len() != cooked.len() {
            return Err(fail(
                ErrorKind::Network,
                "a piece's pass gave no geometry to merge".into(),
            ));
        }
        let merged =
            geode_geo::ops::merge_cancellable(&geometries, &|| self.opts.cancel.is_cancelled())
                .map_err(|e| fail(ErrorKind::Resource, e.to_string()))?
                .ok_or_else(|| vec![CookError::cancelled(path)])?;
        Ok(Cooked::of(Value::geometry(merged)))
    }
}
