//! The cook's environment: the hidden inputs a node may read (`$HIP`) and
//! the memory budget, taken from the process once and then passed down, so
//! that no cook reads process state behind its cache key.

use crate::files::FileAccess;

/// Houdini's default frame rate.
pub const DEFAULT_FPS: f64 = 24.0;

/// Hidden inputs and limits of a cook.
#[derive(Clone, Debug, PartialEq)]
pub struct CookEnv {
    /// The network file's folder (Houdini's `$HIP`); `.` when unknown.
    pub hip: String,
    /// Frames per second (`$FPS`; `$T` and `@Time` follow it): the
    /// network's, 24 when it names none.
    pub fps: f64,
    /// Bytes a single node's result may take before it is refused.
    pub memory_budget: u64,
    /// Where cooks may read and write files (not in any key: a refused
    /// file is an error, and errors are not cached).
    pub files: FileAccess,
    /// The network files being cooked, outermost first (each cooks the
    /// next through object_merge's `file`), so a file that reaches itself
    /// is refused instead of recursing. Not in any key: it changes only
    /// whether a cook is refused, and errors are not cached.
    pub nesting: Vec<String>,
    /// Geometry a host holds in memory (Python's `Geometry.from_arrays`),
    /// which `python_input` reads by content hash. Not in any key: the
    /// hash is the node's parameter, so a cook is still a function of it.
    pub held: HeldGeometry,
}

/// Geometries a host process hands to its cooks, by content hash.
#[derive(Clone, Debug, Default)]
pub struct HeldGeometry(
    std::sync::Arc<std::collections::BTreeMap<u128, std::sync::Arc<geode_geo::Geometry>>>,
);

impl HeldGeometry {
    /// Holds `geometries`, each under its content hash.
    pub fn new(
        geometries: impl IntoIterator<Item = std::sync::Arc<geode_geo::Geometry>>,
    ) -> HeldGeometry {
        HeldGeometry(std::sync::Arc::new(
            geometries
                .into_iter()
                .map(|g| (g.content_hash(), g))
                .collect(),
        ))
    }

    /// The geometry whose content hash is `hash`.
    pub fn get(&self, hash: u128) -> Option<&std::sync::Arc<geode_geo::Geometry>> {
        self.0.get(&hash)
    }
}

impl PartialEq for HeldGeometry {
    /// Two holds are equal when they hold the same hashes (their geometry is
    /// then equal by definition of the hash).
    fn eq(&self, other: &HeldGeometry) -> bool {
        self.0.keys().eq(other.0.keys())
    }
}

impl Default for CookEnv {
    fn default() -> CookEnv {
        CookEnv {
            hip: ".".into(),
            fps: DEFAULT_FPS,
            memory_budget: default_budget(),
            files: FileAccess::anywhere(),
            nesting: Vec::new(),
            held: HeldGeometry::default(),
        }
    }
}

impl CookEnv {
    /// From the process: `HIP` if set (else `.`), `GEODE_MEMORY_MB` if set
    /// (else 60% of physical memory).
    pub fn from_process() -> CookEnv {
        let hip = std::env::var("HIP")
            .ok()
            .filter(|h| !h.is_empty())
            .unwrap_or_else(|| ".".into());
        CookEnv {
            hip,
            fps: DEFAULT_FPS,
            memory_budget: budget_from_env(),
            files: FileAccess::anywhere(),
            nesting: Vec::new(),
            held: HeldGeometry::default(),
        }
    }

    /// For a network file: `$HIP` is the file's folder, as in Houdini
    /// (unless the process sets `HIP`).
    pub fn for_network(network: &std::path::Path) -> CookEnv {
        let mut env = CookEnv::from_process();
        env.nesting = vec![network_identity(network)];
        if std::env::var_os("HIP").is_some() {
            return env;
        }
        let dir = network
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        env.with_hip(dir.to_string_lossy().into_owned())
    }

    /// With files confined as `files` says.
    pub fn with_files(mut self, files: FileAccess) -> CookEnv {
        self.files = files;
        self
    }

    /// With `fps` frames per second (ignored unless finite and positive).
    pub fn with_fps(mut self, fps: f64) -> CookEnv {
        if fps.is_finite() && fps > 0.0 {
            self.fps = fps;
        }
        self
    }

    /// The time of `frame` in seconds (frame 1 is time 0, as in Houdini).
    pub fn time(&self, frame: f64) -> f64 {
        (frame - 1.0) / self.fps
    }

    /// With `$HIP` set to `hip`.
    pub fn with_hip(mut self, hip: impl Into<String>) -> CookEnv {
        self.hip = hip.into();
        self
    }

    /// Expands `$HIP`, `$F` (frame), `$F2`..`$F9` (zero-padded frame) and
    /// `$FF` (fractional frame) in a path, as the CLI does for its output.
    pub fn expand(&self, pattern: &str, frame: f64) -> String {
        expand_frame(&pattern.replace("$HIP", &self.hip), frame)
    }
}

/// What names a network file in [`CookEnv::nesting`]: its real path where
/// it has one (two spellings of one file are one file), else as given.
pub fn network_identity(path: &std::path::Path) -> String {
    std::fs::canonicalize(path)
        .unwrap_or_else(|_| path.to_owned())
        .to_string_lossy()
        .into_owned()
}

/// Replaces `$F` (frame), `$F2`..`$F9` (zero-padded frame) and `$FF` (fractional frame).
pub fn expand_frame(pattern: &str, frame: f64) -> String {
    let mut out = String::new();
    let mut rest = pattern;
    let whole = frame.round() as i64;
    while let Some(i) = rest.find("$F") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        match after.chars().next() {
            Some('F') => {
                out.push_str(&format!("{frame}"));
                rest = &after[1..];
            }
            Some(d @ '1'..='9') => {
                let width = d.to_digit(10).unwrap_or(1) as usize;
                out.push_str(&format!("{whole:0width$}"));
                rest = &after[1..];
            }
            _ => {
                out.push_str(&whole.to_string());
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// A megabyte as the `*_MB` variables count it (10^6 bytes), the unit
/// messages print sizes in: `GEODE_MEMORY_MB=2000` reads back as 2.0 GB.
pub const MB: u64 = 1_000_000;

/// `GEODE_MEMORY_MB`, or the default.
pub fn budget_from_env() -> u64 {
    std::env::var("GEODE_MEMORY_MB")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .map(|mb| mb.saturating_mul(MB))
        .unwrap_or_else(default_budget)
}

/// 60% of physical memory (from /proc/meminfo, read once per process), or
/// 8 GiB where unknown.
fn default_budget() -> u64 {
    static BUDGET: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *BUDGET.get_or_init(|| {
        let total_kb = std::fs::read_to_string("/proc/meminfo").ok().and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("MemTotal:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<u64>().ok())
        });
        match total_kb {
            Some(kb) => kb * 1024 / 10 * 6,
            None => 8 << 30,
        }
    })
}

pub use geode_geo::human_bytes;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_expand_like_the_cli() {
        let env = CookEnv::default().with_hip("/proj");
        assert_eq!(env.expand("$HIP/out.$F4.obj", 7.0), "/proj/out.0007.obj");
        assert_eq!(env.expand("out.$F.obj", 12.0), "out.12.obj");
        assert_eq!(env.expand("a$FF-$F2", 2.5), "a2.5-03");
        assert_eq!(env.expand("plain.obj", 3.0), "plain.obj");
    }

    #[test]
    fn sizes_read_well() {
        assert_eq!(human_bytes(12.0), "12 bytes");
        assert_eq!(human_bytes(1.5e9), "1.5 GB");
        assert_eq!(human_bytes(320e6), "320 MB");
    }
}
