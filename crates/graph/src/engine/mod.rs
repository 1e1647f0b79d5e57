//! The cook engine: cooks what a node needs in waves (independent branches in parallel, no thread ever waiting on another's cook), keys every cook by content, consults the cache, traces each cook.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use geode_op::{
    CancelToken, CookContext, CookEnv, CookError, ErrorKind, NodeSpec, ParamValue, Params,
    ProgressFn, Value, Warnings,
};
use rayon::prelude::*;
use xxhash_rust::xxh3::Xxh3;

use crate::block::FeedSlot;
use crate::cache::{Cache, Cached};
use crate::network::{Network, NodeKind};

mod blocks;

/// How to cook.
pub struct CookOptions<'a> {
    pub frame: f64,
    pub cancel: CancelToken,
    /// Called with (node path, fraction) as kernels report progress, and
    /// with 1.0 when a node finishes.
    pub progress: Option<&'a ProgressFn<'a>>,
    /// Hidden inputs and limits, handed to every cook.
    pub env: CookEnv,
    /// Whether output nodes may write their files; when not, cooking one is
    /// an error (looking at a node, as the info panel does, writes nothing).
    pub writes: bool,
}

impl CookOptions<'_> {
    /// Frame `frame`, the environment taken from the process.
    pub fn at_frame(frame: f64) -> CookOptions<'static> {
        CookOptions {
            frame,
            cancel: CancelToken::new(),
            progress: None,
            env: CookEnv::from_process(),
            writes: true,
        }
    }
}

/// Whether a node writes files with these parameters: such a cook is an
/// output, run whenever pulled, never a cached side effect.
fn writes_files(spec: &NodeSpec, params: &Params) -> bool {
    spec.writes
        .iter()
        .any(|w| matches!(params.get(*w), Ok(ParamValue::String(s)) if !s.is_empty()))
}

/// A node's load problem as the error of cooking it.
fn load_problem(e: &crate::LoadError) -> CookError {
    let err = match &e.param {
        Some(p) => CookError::param(&e.path, p, e.message.clone()),
        None => CookError::new(&e.path, ErrorKind::Network, e.message.clone()),
    };
    match e.position {
        Some(p) => err.at_position(p.line, p.column),
        None => err,
    }
}

/// What happened to one node during a cook.
#[derive(Clone, Debug, PartialEq)]
pub struct CookEvent {
    pub path: String,
    pub node_type: &'static str,
    pub key: u128,
    /// Served from the cache (the node's cook did not run).
    pub hit: bool,
    /// Served from the cache's second level (the disk cache).
    pub from_store: bool,
    /// When the node's own cook began, in seconds since the cook was asked
    /// for (inputs are pulled before it begins).
    pub start: f64,
    pub seconds: f64,
    pub bytes: usize,
    /// What the cook warned of (replayed from the cache on a hit).
    pub warnings: Arc<[String]>,
}

/// A cook's value and what ran to produce it.
pub struct CookResult {
    pub value: Value,
    pub events: Vec<CookEvent>,
}

impl CookResult {
    /// Paths of the nodes whose cook actually ran (cache misses), sorted.
    pub fn cooked(&self) -> Vec<&str> {
        let mut v: Vec<&str> = self
            .events
            .iter()
            .filter(|e| !e.hit)
            .map(|e| e.path.as_str())
            .collect();
        v.sort_unstable();
        v
    }
}

/// Cooks nodes of one network against a cache.
pub struct Engine<'c> {
    net: Network,
    cache: &'c Cache,
}

/// A node's value in a run, with its content identity once computed (a
/// cook key reading it, or its producer knowing it will be read).
#[derive(Clone)]
struct Cooked {
    value: Value,
    identity: OnceLock<u128>,
}

impl Cooked {
    fn of(value: Value) -> Cooked {
        Cooked {
            value,
            identity: OnceLock::new(),
        }
    }

    fn identity(&self) -> u128 {
        *self.identity.get_or_init(|| self.value.identity())
    }
}

type Slot = OnceLock<Result<Cooked, Vec<CookError>>>;

struct Run<'e, 'o> {
    engine: &'e Engine<'e>,
    opts: &'o CookOptions<'o>,
    slots: Vec<Slot>,
    /// Nodes another node of this run reads: their cooks hash their output
    /// (its identity, for the readers' keys) inside their own span. The
    /// node asked for is hashed only if something asks its identity.
    read: Vec<AtomicBool>,
    /// Inside a loop's or solver's pass: the values its feed nodes give.
    feeds: Vec<(usize, Cooked)>,
    events: Mutex<Vec<CookEvent>>,
    began: Instant,
}

fn no_progress(_: &str, _: f32) {}

/// The cache key: node type and version, parameter values at the frame and
/// input identities (and the frame itself for time-dependent nodes).
fn cook_key(
    spec: &NodeSpec,
    reads_frame: bool,
    params: &Params,
    inputs: &[Option<Cooked>],
    extra: Option<u128>,
    frame: f64,
    fps: f64,
) -> u128 {
    let mut h = Xxh3::new();
    h.update(b"geode-cook-v1");
    h.update(&(spec.name.len() as u64).to_le_bytes());
    h.update(spec.name.as_bytes());
    h.update(&spec.version.to_le_bytes());
    for (name, v) in params.iter() {
        h.update(name.as_bytes());
        h.update(b"=");
        v.hash_into(&mut h);
    }
    for (name, v) in params.spares() {
        h.update(b"spare:");
        h.update(&(name.len() as u64).to_le_bytes());
        h.update(name.as_bytes());
        v.hash_into(&mut h);
    }
    for inp in inputs {
        match inp {
            Some(c) => h.update(&c.identity().to_le_bytes()),
            None => h.update(b"none"),
        }
    }
    if let Some(x) = extra {
        h.update(&x.to_le_bytes());
    }
    if reads_frame {
        // A cook that reads the frame may read the time, which the frame
        // rate decides.
        h.update(&frame.to_le_bytes());
        h.update(&fps.to_le_bytes());
    }
    h.digest128()
}

impl Run<'_, '_> {
    /// The node's cooked value, cooking what it needs first (see `prepare`).
    fn node(&self, i: usize) -> Result<Cooked, Vec<CookError>> {
        if let Some(done) = self.slots[i].get() {
            return done.clone();
        }
        self.prepare(i);
        self.slots[i].get_or_init(|| self.cook_node(i)).clone()
    }

    /// The nodes `cook_node(i)` reads besides itself: its inputs, a
    /// subnet's output, a feed's block input outside a pass.
    fn reads(&self, i: usize) -> Vec<usize> {
        let net = &self.engine.net;
        let n = &net.nodes[i];
        if !n.problems.is_empty() {
            // Fails without reading anything (a node on a cycle included).
            return Vec::new();
        }
        if Self::shifts_time(n) {
            // Its input cooks in a pass of its own, at another frame.
            return Vec::new();
        }
        let mut reads: Vec<usize> = n.inputs.iter().flatten().copied().collect();
        if n.bypass {
            return reads;
        }
        match &n.kind {
            NodeKind::Subnet {
                block: None,
                output: Some(o),
                ..
            } => reads.push(*o),
            NodeKind::Feed {
                block,
                slot: FeedSlot::Input(k),
            } if !self.feeds.iter().any(|(j, _)| *j == i) => {
                reads.extend(net.nodes[*block].inputs.get(*k).copied().flatten());
            }
            _ => {}
        }
        reads
    }

    /// Cooks every node `target` needs that is not cooked yet, in waves:
    /// each wave's nodes read only earlier waves', and cook in parallel.
    /// Nothing ever waits for a node another thread is cooking (a worker
    /// blocked on one, with that cook waiting on the worker's stolen job,
    /// would deadlock), so independent branches still cook side by side.
    fn prepare(&self, target: usize) {
        // Depth of each needed node: one more than the deepest it reads.
        let mut depth: Vec<Option<usize>> = vec![None; self.slots.len()];
        let mut stack = vec![(target, false)];
        while let Some((i, ready)) = stack.pop() {
            if depth[i].is_some() || self.slots[i].get().is_some() {
                continue;
            }
            let reads = self.reads(i);
            if !ready {
                stack.push((i, true));
                stack.extend(reads.into_iter().map(|j| (j, false)));
                continue;
            }
            let below = reads.iter().filter_map(|&j| depth[j]).max();
            depth[i] = Some(below.map_or(0, |d| d + 1));
        }
        for (i, d) in depth.iter().enumerate() {
            if d.is_some() && i != target {
                self.read[i].store(true, Ordering::Relaxed);
            }
        }
        let deepest = depth.iter().flatten().copied().max().unwrap_or(0);
        let mut waves: Vec<Vec<usize>> = vec![Vec::new(); deepest + 1];
        for (i, d) in depth.iter().enumerate() {
            if let Some(d) = d {
                waves[*d].push(i);
            }
        }
        for wave in waves {
            wave.par_iter().for_each(|&i| {
                self.slots[i].get_or_init(|| self.cook_node(i));
            });
        }
    }

    fn cook_node(&self, i: usize) -> Result<Cooked, Vec<CookError>> {
        let net = &self.engine.net;
        let n = &net.nodes[i];
        if self.opts.cancel.is_cancelled() {
            return Err(vec![CookError::cancelled(&n.path)]);
        }
        if !n.problems.is_empty() {
            return Err(n.problems.iter().map(load_problem).collect());
        }
        if Self::shifts_time(n) {
            return self.time_shift(i);
        }
        // Cooked already (`prepare`); every error is reported.
        let results: Vec<Result<Option<Cooked>, Vec<CookError>>> = n
            .inputs
            .iter()
            .map(|inp| match inp {
                Some(j) => self.node(*j).map(Some),
                None => Ok(None),
            })
            .collect();
        let mut errors: Vec<CookError> = Vec::new();
        let mut inputs = Vec::with_capacity(results.len());
        for r in results {
            match r {
                Ok(c) => inputs.push(c),
                Err(e) => {
                    for x in e {
                        if !errors.contains(&x) {
                            errors.push(x);
                        }
                    }
                }
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        if n.bypass {
            return match inputs.into_iter().next().flatten() {
                Some(c) => Ok(c),
                None => Err(vec![CookError::new(
                    &n.path,
                    ErrorKind::Input,
                    "bypassed, but has no input to pass through",
                )]),
            };
        }
        let op = match &n.kind {
            NodeKind::Feed { block, slot } => return self.feed(i, *block, *slot),
            NodeKind::Subnet {
                block: Some(b),
                output,
                ..
            } => return self.cook_block(i, b.kind, *output, inputs),
            NodeKind::Subnet {
                output: Some(o), ..
            } => return self.node(*o),
            NodeKind::Subnet { output: None, .. } => {
                return Err(vec![CookError::new(
                    &n.path,
                    ErrorKind::Network,
                    "the subnet has no output node",
                )])
            }
            NodeKind::Op { op, .. } => op,
            NodeKind::Invalid => {
                return Err(vec![CookError::new(
                    &n.path,
                    ErrorKind::Network,
                    "unknown node type",
                )])
            }
        };
        let spec = op.spec();
        let params = net
            .params_at(i, self.opts.frame, &self.opts.env)
            .map_err(|e| vec![load_problem(&e)])?;
        let output = writes_files(spec, &params);
        if output && !self.opts.writes {
            return Err(vec![CookError::new(
                &n.path,
                ErrorKind::Io,
                "not cooked here: it writes files (view it, or cook it with geode cook, to write them)",
            )]);
        }
        let key_ctx = geode_op::KeyContext {
            path: &n.path,
            frame: self.opts.frame,
            env: &self.opts.env,
            cancel: &self.opts.cancel,
        };
        let extra = op.key_extra(&key_ctx, &params).map_err(|e| vec![e])?;
        let key = cook_key(
            spec,
            op.reads_frame(&params),
            &params,
            &inputs,
            extra,
            self.opts.frame,
            self.opts.env.fps,
        );
        let span = tracing::info_span!(
            "cook",
            node = %n.path,
            node_type = spec.name,
            frame = self.opts.frame,
            key = %format!("{key:032x}"),
            hit = tracing::field::Empty,
            store = tracing::field::Empty,
            bytes = tracing::field::Empty,
        );
        let _enter = span.enter();
        let start = Instant::now();
        let progress = self.opts.progress.unwrap_or(&no_progress);
        if let Some(c) = (!output).then(|| self.engine.cache.get(key)).flatten() {
            span.record("hit", true);
            span.record("store", c.from_store);
            span.record("bytes", c.bytes);
            self.record(CookEvent {
                path: n.path.clone(),
                node_type: spec.name,
                key,
                hit: true,
                from_store: c.from_store,
                start: (start - self.began).as_secs_f64(),
                seconds: start.elapsed().as_secs_f64(),
                bytes: c.bytes,
                warnings: c.warnings,
            });
            progress(&n.path, 1.0);
            return Ok(Cooked {
                value: c.value,
                identity: c.identity,
            });
        }
        span.record("hit", false);
        // Reported before the first kernel call, so a watcher knows from the
        // first millisecond which node is cooking.
        progress(&n.path, 0.0);
        let warnings = Warnings::new();
        let ctx = CookContext {
            path: &n.path,
            frame: self.opts.frame,
            cancel: &self.opts.cancel,
            on_progress: progress,
            env: &self.opts.env,
            warnings: &warnings,
        };
        let values: Vec<Option<Value>> = inputs
            .iter()
            .map(|c| c.as_ref().map(|c| c.value.clone()))
            .collect();
        let value = op.cook(&ctx, &values, &params).map_err(|e| vec![e])?;
        if value.port_type() != spec.output {
            return Err(vec![CookError::new(
                &n.path,
                ErrorKind::Network,
                format!(
                    "produced {} but declares {}",
                    value.port_type(),
                    spec.output
                ),
            )]);
        }
        let cooked = Cached::new(value, warnings.take().into());
        if self.read[i].load(Ordering::Relaxed) {
            cooked.identity();
        }
        span.record("bytes", cooked.bytes);
        for w in cooked.warnings.iter() {
            tracing::warn!(node = %n.path, "{w}");
        }
        if !output {
            self.engine.cache.insert(key, cooked.clone());
        }
        self.record(CookEvent {
            path: n.path.clone(),
            node_type: spec.name,
            key,
            hit: false,
            from_store: false,
            start: (start - self.began).as_secs_f64(),
            seconds: start.elapsed().as_secs_f64(),
            bytes: cooked.bytes,
            warnings: Arc::clone(&cooked.warnings),
        });
        progress(&n.path, 1.0);
        Ok(Cooked {
            value: cooked.value,
            identity: cooked.identity,
        })
    }

    fn record(&self, e: CookEvent) {
        self.events
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(e);
    }
}

impl<'c> Engine<'c> {
    pub fn new(net: Network, cache: &'c Cache) -> Engine<'c> {
        Engine { net, cache }
    }

    pub fn network(&self) -> &Network {
        &self.net
    }

    pub fn cache(&self) -> &Cache {
        self.cache
    }

    /// Cooks the node at `path` (any node, inside subnetworks too: solo view).
    pub fn cook(&self, path: &str, opts: &CookOptions) -> Result<CookResult, Vec<CookError>> {
        let i = self
            .net
            .index(path)
            .ok_or_else(|| vec![CookError::new(path, ErrorKind::Network, "no such node")])?;
        // The network's own frame rate, where it sets one, is the cook's.
        let with_fps;
        let opts = match self.net.fps() {
            Some(fps) if fps != opts.env.fps => {
                with_fps = CookOptions {
                    frame: opts.frame,
                    cancel: opts.cancel.clone(),
                    progress: opts.progress,
                    env: opts.env.clone().with_fps(fps),
                    writes: opts.writes,
                };
                &with_fps
            }
            _ => opts,
        };
        let run = Run {
            engine: self,
            opts,
            slots: (0..self.net.nodes.len()).map(|_| OnceLock::new()).collect(),
            read: (0..self.net.nodes.len())
                .map(|_| AtomicBool::new(false))
                .collect(),
            feeds: Vec::new(),
            events: Mutex::new(Vec::new()),
            began: Instant::now(),
        };
        let cooked = run.node(i)?;
        let mut events = run.events.into_inner().unwrap_or_else(|p| p.into_inner());
        events.sort_by(|a, b| a.path.cmp(&b.path));
        Ok(CookResult {
            value: cooked.value,
            events,
        })
    }

    /// Cooks the network's output node.
    pub fn cook_output(&self, opts: &CookOptions) -> Result<CookResult, Vec<CookError>> {
        let out = self
            .net
            .output()
            .ok_or_else(|| {
                vec![CookError::new(
                    "/",
                    ErrorKind::Network,
                    "the network names no output node (set \"output\" or a display flag)",
                )]
            })?
            .to_owned();
        self.cook(&out, opts)
    }

    /// Solo view's auto mode: given the parameters that changed (node path,
    /// parameter name), the node to show. A promoted subnet parameter shows
    /// the inner node it drives; any other parameter shows its own node. The
    /// last change wins, as in seed 004.
    pub fn solo_target(&self, changed: &[(&str, &str)]) -> Option<String> {
        changed.iter().rev().find_map(|(node, param)| {
            self.net
                .tagged_target(node, param)
                .or_else(|| self.net.index(node).map(|_| node.to_string()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::glam::Vec3;
    use geode_geo::Geometry;
    use geode_op::{geometry_input, Registry};

    static SOURCE: NodeSpec = NodeSpec::new("source", "Source", "test", "Two points.", &[], &[]);
    static SHIFT: NodeSpec = NodeSpec::new(
        "shift",
        "Shift",
        "test",
        "Its input moved up.",
        &[geometry_input("geometry")],
        &[],
    );

    fn source(_: &CookContext, _: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
        let mut g = Geometry::new();
        g.add_points(&[Vec3::ZERO, Vec3::X]);
        Ok(Value::geometry(g))
    }

    fn shift(_: &CookContext, inputs: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
        let input = inputs[0].as_ref().and_then(|v| v.as_geometry()).unwrap();
        let mut g = Geometry::clone(input);
        g.positions_mut().iter_mut().for_each(|p| p.y += 1.0);
        Ok(Value::geometry(g))
    }

    /// An output is hashed (for its readers' keys) only when a node of the
    /// run reads it; the node asked for is not, until something asks.
    #[test]
    fn only_outputs_that_are_read_are_hashed() {
        let mut reg = Registry::new();
        reg.node(&SOURCE, source);
        reg.node(&SHIFT, shift);
        let net = crate::load_str(
            r#"{"geode": "network", "version": 1, "output": "b", "nodes": {
                "a": {"type": "source"}, "b": {"type": "shift", "inputs": ["a"]}}}"#,
            &reg,
        )
        .unwrap();
        let cache = Cache::new(1 << 20);
        let engine = Engine::new(net, &cache);
        let r = engine.cook_output(&CookOptions::at_frame(1.0)).unwrap();
        assert_eq!(r.cooked(), ["/a", "/b"]);
        for e in &r.events {
            let entry = cache.get(e.key).unwrap();
            assert_eq!(entry.identity.get().is_some(), e.path == "/a", "{}", e.path);
        }
        let b = r.events.iter().find(|e| e.path == "/b").unwrap();
        let entry = cache.get(b.key).unwrap();
        assert_eq!(entry.identity(), r.value.identity());
    }
}
