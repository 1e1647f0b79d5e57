//! The exit status of a command by what kind of failure ended it (README:
//! "Exit status"), so a script or the farm can tell a mistake to fix from a
//! hiccup to retry.

use std::error::Error;
use std::fmt;

/// What kind of failure ended a command; each has its exit status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// A bug or a failure of no known kind (1).
    Internal,
    /// The command line is wrong: an argument, `--set`, `--frames`,
    /// `--node` (2, as clap exits on its own).
    Usage,
    /// The network cannot be loaded or does not check: bad JSON, unknown
    /// node types, bad parameters, no output node (3).
    Network,
    /// The cook failed: a node refused its parameters or inputs, a kernel
    /// failed, a file's content cannot be used (4).
    Cook,
    /// The system refused a file: missing, not permitted, disk full (5).
    Io,
    /// A memory budget (`GEODE_MEMORY_MB`) would be exceeded (6).
    Resource,
    /// Ctrl-C or SIGTERM (130: 128 + SIGINT).
    Interrupted,
}

impl Exit {
    pub fn code(self) -> u8 {
        match self {
            Exit::Internal => 1,
            Exit::Usage => 2,
            Exit::Network => 3,
            Exit::Cook => 4,
            Exit::Io => 5,
            Exit::Resource => 6,
            Exit::Interrupted => 130,
        }
    }

    /// Every kind, in status order.
    const ALL: [Exit; 7] = [
        Exit::Internal,
        Exit::Usage,
        Exit::Network,
        Exit::Cook,
        Exit::Io,
        Exit::Resource,
        Exit::Interrupted,
    ];

    /// The kind an exit status stands for.
    pub fn from_code(code: i32) -> Option<Exit> {
        Exit::ALL.into_iter().find(|e| i32::from(e.code()) == code)
    }

    /// Whether running the same command again fails the same way: the
    /// network, the arguments and the cook are deterministic, the machine
    /// is not (a file system's hiccup, memory in use by others, a crash).
    pub fn is_final(self) -> bool {
        matches!(self, Exit::Usage | Exit::Network | Exit::Cook)
    }

    /// The exit statuses no retry can change.
    pub fn final_codes() -> impl Iterator<Item = u8> {
        Exit::ALL
            .into_iter()
            .filter(|e| e.is_final())
            .map(Exit::code)
    }

    /// Whether a process that exited with `code` may succeed if run again.
    pub fn is_transient(code: i32) -> bool {
        !Exit::from_code(code).is_some_and(Exit::is_final)
    }

    /// The kind of an error a command returned: the kind it was tagged
    /// with (the outermost tag), else what its chain holds (an operating
    /// system's refusal, a memory budget), else internal.
    pub fn of(e: &anyhow::Error) -> Exit {
        if let Some(k) = e.chain().find_map(|c| c.downcast_ref::<Kinded>()) {
            return k.kind;
        }
        Exit::of_chain(e.chain()).unwrap_or(Exit::Internal)
    }

    /// The kind the first error of a chain with a known kind says.
    fn of_chain<'a>(chain: impl Iterator<Item = &'a (dyn Error + 'static)>) -> Option<Exit> {
        chain.into_iter().find_map(|cause| {
            if cause.downcast_ref::<crate::farm::Interrupted>().is_some() {
                return Some(Exit::Interrupted);
            }
            if let Some(refusal) = cause.downcast_ref::<geode_op::FileRefusal>() {
                use geode_op::FileRefusal as R;
                return Some(match refusal {
                    R::TooLarge { .. } => Exit::Resource,
                    R::Io { source, .. } => Exit::of_io(source),
                    R::Cancelled => Exit::Interrupted,
                    // A path the command may not read: the caller's to fix.
                    R::Outside { .. } | R::NotRegular { .. } => Exit::Usage,
                });
            }
            if let Some(io) = cause.downcast_ref::<geode_io::IoError>() {
                use geode_io::IoError as E;
                return Some(match io {
                    E::Os { error, .. } => Exit::of_io(error),
                    E::TooLarge { .. } => Exit::Resource,
                    E::Cancelled { .. } => Exit::Interrupted,
                    E::Parse { .. } | E::UnknownFormat { .. } | E::Unsupported { .. } => Exit::Cook,
                });
            }
            cause.downcast_ref::<std::io::Error>().map(Exit::of_io)
        })
    }

    /// An operating system's error: content that is not what it should be
    /// (not UTF-8) fails again; anything else may not.
    fn of_io(e: &std::io::Error) -> Exit {
        match e.kind() {
            std::io::ErrorKind::InvalidData => Exit::Cook,
            _ => Exit::Io,
        }
    }

    /// The kind of a failed cook's errors: interrupted when it was
    /// cancelled; a cook's failure when any error would come back on a
    /// retry (a parameter, an input, a kernel, a file's content); else the
    /// machine's (memory, the operating system refusing a file).
    pub fn of_cook(errors: &[geode_op::CookError]) -> Exit {
        use geode_op::ErrorKind as K;
        if errors.iter().any(|e| e.kind == K::Cancelled) {
            return Exit::Interrupted;
        }
        let kinds: Vec<Exit> = errors
            .iter()
            .map(|e| match e.kind {
                K::Resource => Exit::Resource,
                K::Io => {
                    let first: &(dyn Error + 'static) = e;
                    let chain = std::iter::successors(Some(first), |c| (*c).source());
                    Exit::of_chain(chain).unwrap_or(Exit::Io)
                }
                _ => Exit::Cook,
            })
            .collect();
        if kinds.is_empty() || kinds.iter().any(|k| k.is_final()) {
            Exit::Cook
        } else if kinds.contains(&Exit::Resource) {
            Exit::Resource
        } else {
            Exit::Io
        }
    }
}

/// An error tagged with its kind; shows as the error itself.
#[derive(Debug)]
struct Kinded {
    kind: Exit,
    error: anyhow::Error,
}

impl fmt::Display for Kinded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.error, f)
    }
}

impl Error for Kinded {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        self.error.source()
    }
}

/// Tags an error with the kind of failure it is.
pub fn tagged(kind: Exit, error: impl Into<anyhow::Error>) -> anyhow::Error {
    anyhow::Error::new(Kinded {
        kind,
        error: error.into(),
    })
}

/// `result.kind(Exit::Usage)`: tags the error, if any.
pub trait Kind<T> {
    fn kind(self, kind: Exit) -> anyhow::Result<T>;
}

impl<T, E: Into<anyhow::Error>> Kind<T> for Result<T, E> {
    fn kind(self, kind: Exit) -> anyhow::Result<T> {
        self.map_err(|e| tagged(kind, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn a_tag_survives_context_and_shows_as_the_error() {
        let e: anyhow::Result<()> = Err(anyhow::anyhow!("bad value")).kind(Exit::Network);
        let e = e.context("loading net.json").unwrap_err();
        assert_eq!(Exit::of(&e), Exit::Network);
        assert_eq!(format!("{e:#}"), "loading net.json: bad value");
    }

    #[test]
    fn untagged_errors_are_read_off_their_chain() {
        let os = geode_io::IoError::os("x.obj", std::io::Error::other("disk full"));
        assert_eq!(
            Exit::of(&anyhow::Error::new(os).context("writing")),
            Exit::Io
        );
        let parse = geode_io::IoError::Parse {
            path: "x.obj".into(),
            pos: None,
            message: "bad face".into(),
        };
        assert_eq!(Exit::of(&anyhow::Error::new(parse)), Exit::Cook);
        assert_eq!(Exit::of(&anyhow::anyhow!("what")), Exit::Internal);
    }

    #[test]
    fn only_deterministic_failures_are_final() {
        for (code, transient) in [
            (1, true),
            (2, false),
            (3, false),
            (4, false),
            (5, true),
            (6, true),
            (137, true),
        ] {
            assert_eq!(Exit::is_transient(code), transient, "{code}");
        }
    }
}
