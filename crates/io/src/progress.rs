//! Progress reporting hooks for long reads and writes (the CLI draws bars from them).

/// Receives progress of a long operation: a total, then the amount done.
pub trait Progress: Sync {
    fn start(&self, _what: &str, _total: u64) {}
    fn set(&self, _done: u64) {}
    fn finish(&self) {}
    /// Whether the caller asks the operation to stop: writers poll it as
    /// they go and then fail with [`crate::IoError::Cancelled`], writing nothing.
    fn cancelled(&self) -> bool {
        false
    }
    /// The bytes a reader's result may need (`GEODE_MEMORY_MB`'s budget
    /// where the caller has one): a file whose counts claim more is refused
    /// before anything is allocated for them.
    fn memory_budget(&self) -> u64 {
        u64::MAX
    }
    /// Something the user should know of a result that stands (an
    /// attribute a format had to leave out); the message names the file.
    fn warn(&self, _message: &str) {}
}

/// How a warning names an attribute: `point `tags` (int array)`.
pub(crate) fn describe_attrib(
    class: geode_geo::AttribClass,
    name: &str,
    ty: geode_geo::AttribType,
) -> String {
    format!("{class} `{name}` ({ty})")
}

/// Reports, in one warning, what a format could not carry (attributes as
/// [`describe_attrib`] names them, groups).
pub(crate) fn report_dropped(
    progress: &dyn Progress,
    path: &std::path::Path,
    format: &str,
    dropped: &[String],
) {
    if dropped.is_empty() {
        return;
    }
    progress.warn(&format!(
        "{}: {format} cannot hold {}; not written",
        path.display(),
        dropped.join(", ")
    ));
}

/// Reports nothing.
pub struct NoProgress;

impl Progress for NoProgress {}

/// Calls `set` only every `step` units, so hot loops stay cheap.
pub(crate) struct Throttle<'a> {
    progress: &'a dyn Progress,
    step: u64,
    next: u64,
}

impl<'a> Throttle<'a> {
    pub fn new(progress: &'a dyn Progress, what: &str, total: u64) -> Throttle<'a> {
        progress.start(what, total);
        Throttle {
            progress,
            step: (total / 200).max(1 << 16),
            next: 0,
        }
    }

    #[inline]
    pub fn tick(&mut self, done: u64) {
        if done >= self.next {
            self.progress.set(done);
            self.next = done + self.step;
        }
    }

    pub fn finish(self) {
        self.progress.finish();
    }
}
