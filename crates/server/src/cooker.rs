//! Latest-wins cooking: a new request cancels the cook in flight and starts its own on a worker thread; a result is delivered only if no newer request came.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use geode_graph::{Cache, CookEvent, CookOptions, Engine, Network};
use geode_op::{CancelToken, CookEnv, CookError, Value};

/// What to cook.
pub struct CookRequest {
    /// Increases with every request; results of older ones are dropped.
    pub generation: u64,
    pub network: Network,
    pub node: String,
    pub frame: f64,
    pub env: CookEnv,
    /// Nodes with the template flag, cooked after `node` and shown as ghosts.
    pub templates: Vec<String>,
}

/// A finished cook.
pub struct Finished {
    pub generation: u64,
    pub node: String,
    pub frame: f64,
    pub result: Result<(Value, Vec<CookEvent>), Vec<CookError>>,
    /// Seconds from the request to the end of the cook.
    pub seconds: f64,
}

/// Where the cooker reports: progress as it goes, then the result (only for
/// the latest request).
pub trait Reporter: Send + Sync + 'static {
    fn progress(&self, generation: u64, node: &str, fraction: f32);
    fn finished(&self, done: Finished);
    /// A templated node's result (after the viewed node's), for the ghost display.
    fn template(&self, _generation: u64, _node: &str, _value: Option<Value>) {}
}

/// Progress reports are thinned to one per node per interval (and every finish).
const PROGRESS_INTERVAL: Duration = Duration::from_millis(40);

/// The cook running now: its generation, how to stop it, and whether it
/// has finished.
struct InFlight {
    generation: u64,
    token: CancelToken,
    done: Arc<AtomicBool>,
}

pub struct Cooker {
    cache: Arc<Cache>,
    latest: Arc<AtomicU64>,
    in_flight: Mutex<Option<InFlight>>,
    reporter: Arc<dyn Reporter>,
}

impl Cooker {
    pub fn new(cache: Arc<Cache>, reporter: Arc<dyn Reporter>) -> Cooker {
        Cooker {
            cache,
            latest: Arc::new(AtomicU64::new(0)),
            in_flight: Mutex::new(None),
            reporter,
        }
    }

    /// The cache cooks share (info requests cook through it too).
    pub fn cache(&self) -> &Cache {
        &self.cache
    }

    /// Cancels the cook in flight (its result will not be delivered); the
    /// generation of the cook stopped, if one was still running.
    pub fn cancel(&self, generation: u64) -> Option<u64> {
        self.latest.fetch_max(generation, Ordering::SeqCst);
        let running = self
            .in_flight
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take()?;
        running.token.cancel();
        (!running.done.load(Ordering::SeqCst)).then_some(running.generation)
    }

    /// Cancels the cook in flight and starts this one.
    pub fn start(&self, req: CookRequest) {
        let token = CancelToken::new();
        let done = Arc::new(AtomicBool::new(false));
        {
            let mut slot = self.in_flight.lock().unwrap_or_else(|p| p.into_inner());
            let now = InFlight {
                generation: req.generation,
                token: token.clone(),
                done: done.clone(),
            };
            if let Some(old) = slot.replace(now) {
                old.token.cancel();
            }
            self.latest.fetch_max(req.generation, Ordering::SeqCst);
        }
        let cache = self.cache.clone();
        let latest = self.latest.clone();
        let reporter = self.reporter.clone();
        std::thread::Builder::new()
            .name(format!("cook-{}", req.generation))
            .spawn(move || {
                run(req, token, &cache, &latest, &*reporter);
                done.store(true, Ordering::SeqCst);
            })
            .expect("a thread can be started");
    }
}

fn run(
    req: CookRequest,
    token: CancelToken,
    cache: &Cache,
    latest: &AtomicU64,
    reporter: &dyn Reporter,
) {
    let began = Instant::now();
    let generation = req.generation;
    let current = || latest.load(Ordering::SeqCst) == generation;
    let last_sent: Mutex<HashMap<String, Instant>> = Mutex::new(HashMap::new());
    let progress = |node: &str, fraction: f32| {
        if !current() {
            return;
        }
        let now = Instant::now();
        let mut sent = last_sent.lock().unwrap_or_else(|p| p.into_inner());
        let due = sent
            .get(node)
            .is_none_or(|t| now.duration_since(*t) >= PROGRESS_INTERVAL);
        if due || fraction >= 1.0 {
            sent.insert(node.to_owned(), now);
            drop(sent);
            reporter.progress(generation, node, fraction);
        }
    };
    let engine = Engine::new(req.network, cache);
    let opts = CookOptions {
        frame: req.frame,
        cancel: token,
        progress: Some(&progress),
        env: req.env,
        writes: true,
    };
    let result = engine.cook(&req.node, &opts).map(|r| (r.value, r.events));
    // A stale result never replaces a newer one.
    if current() {
        reporter.finished(Finished {
            generation,
            node: req.node.clone(),
            frame: req.frame,
            result,
            seconds: began.elapsed().as_secs_f64(),
        });
    }
    // Templates after the viewed node: they share its inputs through the cache.
    let quiet = CookOptions {
        progress: None,
        ..opts
    };
    for t in req.templates.iter().filter(|t| **t != req.node) {
        if !current() {
            return;
        }
        let value = engine.cook(t, &quiet).ok().map(|r| r.value);
        if current() {
            reporter.template(generation, t, value);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc;

    struct Collect(Mutex<mpsc::Sender<(u64, bool)>>);

    impl Reporter for Collect {
        fn progress(&self, _: u64, _: &str, _: f32) {}
        fn finished(&self, done: Finished) {
            let _ = self
                .0
                .lock()
                .unwrap()
                .send((done.generation, done.result.is_ok()));
        }
    }

    fn network(depth: u32) -> Network {
        let text = format!(
            r#"{{"geode": "network", "version": 1, "output": "mesh", "nodes": {{
                "ball": {{"type": "frep_sphere"}},
                "mesh": {{"type": "polygonise", "inputs": ["ball"], "params": {{"min": [-1.2, -1.2, -1.2], "max": [1.2, 1.2, 1.2], "depth": {depth}}}}}}}}}"#
        );
        geode_graph::load_str(&text, &geode_nodes::registry()).unwrap()
    }

    fn request(generation: u64, depth: u32) -> CookRequest {
        CookRequest {
            generation,
            network: network(depth),
            node: "/mesh".into(),
            frame: 1.0,
            env: CookEnv::default(),
            templates: Vec::new(),
        }
    }

    #[test]
    fn a_newer_request_cancels_the_cook_in_flight_and_only_it_is_delivered() {
        let (tx, rx) = mpsc::channel();
        let cooker = Cooker::new(
            Arc::new(Cache::new(1 << 30)),
            Arc::new(Collect(Mutex::new(tx))),
        );
        // Depth 11 takes many seconds; depth 4 milliseconds.
        cooker.start(request(1, 11));
        std::thread::sleep(Duration::from_millis(100));
        let asked = Instant::now();
        cooker.start(request(2, 4));
        let (generation, ok) = rx.recv_timeout(Duration::from_secs(60)).unwrap();
        assert_eq!((generation, ok), (2, true));
        assert!(
            asked.elapsed() < Duration::from_secs(20),
            "the newer cook waited {:?}",
            asked.elapsed()
        );
        // The first cook stops (cancelled) and reports nothing.
        assert!(rx.recv_timeout(Duration::from_secs(5)).is_err());
    }

    #[test]
    fn cancel_drops_the_result_in_flight() {
        let (tx, rx) = mpsc::channel();
        let cooker = Cooker::new(
            Arc::new(Cache::new(1 << 30)),
            Arc::new(Collect(Mutex::new(tx))),
        );
        cooker.start(request(1, 11));
        std::thread::sleep(Duration::from_millis(50));
        assert_eq!(cooker.cancel(2), Some(1), "the running cook was stopped");
        assert!(rx.recv_timeout(Duration::from_secs(5)).is_err());
        assert_eq!(cooker.cancel(3), None, "nothing left to stop");
    }
}
