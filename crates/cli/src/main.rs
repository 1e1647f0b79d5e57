//! The `geode` command: cook, check and format networks, farm frames, serve
//! the studio, inspect and convert geometry files, manage the disk cache.

/// `println!` that ends the process quietly when standard output is a
/// closed pipe (`geode nodes | head`), as a Unix tool does, instead of
/// panicking.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

mod catalogue;
mod convert;
mod cook;
mod disk_cache;
mod exit;
mod farm;
mod info;
mod progress;
mod telemetry;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand};

/// Huge pages for large geometry columns (see geode-alloc).
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

const EXAMPLES: &str = "\
Examples:
  geode cook examples/primitives.json -o /tmp/primitives.glb
  geode cook examples/primitives.json --frames 1-24 -o '/tmp/prim.$F4.obj'
  geode cook examples/primitives.json --node /spin --frame 12 -o /tmp/spin.ply --trace /tmp/trace.json
  geode check examples/primitives.json
  geode nodes transform
  geode info examples/assets/creased_box.obj
  geode info --json model.glb
  geode convert examples/assets/creased_box.obj /tmp/box.glb
  geode convert scan.ply print.stl

Exit status: 0 success, 1 internal, 2 usage, 3 the network, 4 the cook,
5 the system refused a file, 6 the memory budget, 130 interrupted (README).";

/// geode: a procedural geometry engine.
#[derive(Parser)]
#[command(name = "geode", version, about, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Write a Chrome trace (open in Perfetto or chrome://tracing) with a span per cook.
    #[arg(long, global = true, value_name = "FILE")]
    trace: Option<PathBuf>,
    /// Export a span per cook to an OpenTelemetry collector over OTLP/HTTP
    /// (e.g. Jaeger at http://localhost:4318/v1/traces). Needs the `otlp` build feature.
    #[arg(long, global = true, value_name = "URL")]
    otlp: Option<String>,
}

#[derive(Subcommand)]
enum Command {
    /// Cook a network's output (or any node) at one or more frames and write the result.
    #[command(
        after_help = "Examples:\n  geode cook examples/primitives.json -o /tmp/out.glb\n  geode cook examples/primitives.json --frames 1-48 -o '/tmp/out.$F4.stl'\n\n\
        $F is the frame, $F4 the frame padded to 4 digits, $FF the fractional frame.\n\
        GEODE_CACHE=off disables the cook cache; GEODE_CACHE_MB sizes it (default 2048);\n\
        GEODE_CACHE_DIR adds a disk cache other processes share (see `geode cache`)."
    )]
    Cook {
        /// Network file (.json).
        network: PathBuf,
        /// Cook this node instead of the network's output (any path, inside subnets too).
        #[arg(long, value_name = "PATH")]
        node: Option<String>,
        /// The frame to cook (default 1).
        #[arg(long, value_name = "F", conflicts_with = "frames")]
        frame: Option<f64>,
        /// An inclusive range of frames, e.g. 1-24.
        #[arg(long, value_name = "A-B")]
        frames: Option<String>,
        /// Output file; the extension picks the format. May contain $F, $F4, $FF.
        #[arg(short, long, value_name = "OUT")]
        output: Option<String>,
        /// Print what cooked and what came from the cache, per frame.
        #[arg(long)]
        stats: bool,
        /// Set a parameter before cooking: NODE/PARAM=VALUE (the value as JSON,
        /// else text); repeatable. `geode farm --wedge` cooks with these.
        #[arg(long = "set", value_name = "NODE/PARAM=VALUE")]
        sets: Vec<String>,
    },
    /// Open a network in the studio: a browser node editor and viewport that recook live.
    #[command(
        after_help = "Examples:\n  geode serve examples/coral.json\n  geode serve examples/coral.json --port 9000 --open\n\n\
        The studio listens on 127.0.0.1 only; the printed URL carries the session's token.\n\
        Its cooks and saves read and write regular files only under the network's folder\n\
        (the current folder without a network) and the folders given with --allow, symlinks\n\
        resolved first; a file larger than the memory budget (GEODE_MEMORY_MB) is refused unread."
    )]
    Serve {
        /// Network file (.json); a missing file starts an empty network saved there.
        network: Option<PathBuf>,
        /// Port to listen on (0 picks a free one).
        #[arg(long, default_value_t = 8765)]
        port: u16,
        /// Open the studio in the default browser.
        #[arg(long)]
        open: bool,
        /// Listen on another address than loopback (other machines can then reach
        /// the studio: anyone with the token can edit the network and its file).
        #[arg(long, value_name = "ADDR")]
        bind: Option<std::net::IpAddr>,
        /// Also let the studio read and write files under this folder (repeatable).
        #[arg(long, value_name = "DIR")]
        allow: Vec<PathBuf>,
    },
    /// Load and check a network without cooking it: every parameter
    /// evaluated at frame 1 and every wrangle snippet compiled; every problem
    /// is reported.
    Check { network: PathBuf },
    /// Rewrite a network file in canonical form (atomically; unknown fields are kept).
    Fmt { network: PathBuf },
    /// List node types, show one, or write the markdown catalogue.
    #[command(
        after_help = "Examples:\n  geode nodes\n  geode nodes sphere\n  geode nodes --markdown docs/nodes"
    )]
    Nodes {
        /// A node type to describe.
        node_type: Option<String>,
        /// Write one markdown page per node type (and an index) into this folder.
        #[arg(long, value_name = "DIR")]
        markdown: Option<PathBuf>,
    },
    /// Print counts, bounds, attributes, groups, topology and content hash of a file
    /// (of a .vdb file: its grids, voxel sizes, active voxels and bounds).
    #[command(after_help = "Example:\n  geode info examples/assets/creased_box.obj")]
    Info {
        /// Geometry file (.obj, .stl, .ply, .gltf, .glb, .geo, .bgeo), or an
        /// OpenVDB .vdb file (its float grids).
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Convert between formats (chosen by extension), a .vdb level set to a mesh, or a closed mesh to a .vdb level set. The output is written atomically.
    #[command(
        after_help = "Examples:\n  geode convert examples/assets/creased_box.obj /tmp/box.glb\n  \
        geode convert part.stl part.vdb --voxel-size 0.01\n  geode convert part.vdb part.obj\n\n\
        Formats without instancing (.obj, .stl, .ply) get packed instances unpacked;\n\
        what a format cannot hold is named in a warning. A .vdb grid is meshed one cell a voxel\n\
        (up to 4096 a side) over its active voxels; a mesh becomes a level set \"surface\" (exact\n\
        signed distance, sign by winding number) within --half-width voxels of its surface."
    )]
    Convert(convert::ConvertArgs),
    /// Cook frames (and a wedge of one parameter's values) as independent tasks on a scheduler, sharing a disk cache.
    #[command(
        after_help = "Examples:\n  geode farm examples/coral.json --frames 1-24 -o 'out/$F4.bgeo'\n  geode farm examples/chain.json --wedge /spacing/count=48,96,192 -o 'out/$WEDGE/$F4.bgeo'\n  geode farm examples/coral.json --frames 1-240 --scheduler slurm --retry 2 --task-timeout 10m -o '/shared/coral/$F4.bgeo'\n\n\
        Each task is `geode cook NETWORK --frame F [--set NODE/PARAM=V] -o OUT` with GEODE_CACHE_DIR set\n\
        (--cache-dir, else GEODE_CACHE_DIR, else .geode-cache beside the network): a farm writes the\n\
        bytes a local cook writes. $WEDGE is PARAM_VALUE. Logs and exit statuses go to the farm folder\n\
        (.geode-farm/ beside the network); a failed task is reported with the end of its log.\n\n\
        A task past --task-timeout is cancelled (`timed out after ...`); a started task whose heartbeat\n\
        (a file its cook touches every 2 s or faster) is older than --stall-limit is cancelled\n\
        (`stalled: no heartbeat for ...`); both are retried as --retry allows. A task cancelled from\n\
        outside is reported as `cancelled (by the scheduler)`. Ctrl-C or SIGTERM kills the local tasks\n\
        or scancels the Slurm jobs, then exits 130 (--scheduler k8s only writes a manifest: nothing to\n\
        cancel; --task-timeout becomes the pods' activeDeadlineSeconds)."
    )]
    Farm(farm::FarmArgs),
    /// The disk cache cooks share (GEODE_CACHE_DIR): its size, or a collection down to 90% of its bound.
    #[command(
        after_help = "Examples:\n  GEODE_CACHE_DIR=/shared/geode-cache geode cook net.json -o out.bgeo\n  geode cache stats --dir /shared/geode-cache\n  geode cache gc --dir /shared/geode-cache --max-mb 2048\n\n\
        GEODE_CACHE_DIR turns the disk cache on for `geode cook`; GEODE_CACHE_DISK_MB bounds it (megabytes of 10^6 bytes, default 10240)\n\
        across every process sharing it: the save that passes the bound collects, least recently used first."
    )]
    Cache {
        #[command(subcommand)]
        action: CacheAction,
    },
}

#[derive(Subcommand)]
enum CacheAction {
    /// Entries, shared packed sources and bytes held.
    Stats(CacheDir),
    /// Remove the least recently used entries until the folder fits its bound.
    Gc(CacheDir),
}

/// Which disk cache, and its bound.
#[derive(clap::Args)]
struct CacheDir {
    /// The cache folder (default: GEODE_CACHE_DIR).
    #[arg(long, value_name = "DIR")]
    dir: Option<PathBuf>,
    /// The bound, in megabytes of 10^6 bytes (default: GEODE_CACHE_DISK_MB, else 10240).
    #[arg(long, value_name = "MB")]
    max_mb: Option<u64>,
}

fn run(cli: Cli) -> anyhow::Result<()> {
    // The guard flushes the trace sinks when the command ends.
    let _telemetry = telemetry::init(cli.trace.as_deref(), cli.otlp.as_deref())?;
    match cli.command {
        Command::Cook {
            network,
            node,
            frame,
            frames,
            output,
            stats,
            sets,
        } => {
            cook::cook(cook::CookArgs {
                network: &network,
                sets: &sets,
                node: node.as_deref(),
                frames: cook::frames(frame, frames.as_deref())?,
                output: output.as_deref(),
                stats,
            })?;
        }
        Command::Serve {
            network,
            port,
            open,
            bind,
            allow,
        } => serve(network, port, open, bind, allow)?,
        Command::Check { network } => cook::check(&network)?,
        Command::Farm(args) => farm::farm(args)?,
        Command::Cache { action } => match action {
            CacheAction::Stats(c) => disk_cache::stats(c.dir, c.max_mb)?,
            CacheAction::Gc(c) => disk_cache::gc(c.dir, c.max_mb)?,
        },
        Command::Fmt { network } => cook::fmt(&network)?,
        Command::Nodes {
            node_type,
            markdown,
        } => match markdown {
            Some(dir) => catalogue::write_markdown(&dir)?,
            None => catalogue::list(node_type.as_deref())?,
        },
        Command::Info { file, json }
            if file
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("vdb")) =>
        {
            let bytes = geode_op::FileAccess::anywhere().read(
                &file,
                geode_op::budget_from_env(),
                &|| false,
            )?;
            let volumes = geode_io::vdb::read_vdb(&bytes, geode_op::budget_from_env(), &|| false)
                .with_context(|| file.display().to_string())?;
            if json {
                say!("{}", info::volumes_json(&file, &volumes));
            } else {
                write_stdout(format_args!("{}", info::volumes_text(&file, &volumes)));
            }
        }
        Command::Info { file, json } => {
            let g = read_geometry(&file, &progress::Bar::new())?;
            let report = info::Report::new(&file, &g);
            if json {
                say!("{}", report.to_json());
            } else {
                write_stdout(format_args!("{}", report.to_text()));
            }
        }
        Command::Convert(args) => convert::convert(&args)?,
    }
    Ok(())
}

/// A geometry file named on the command line: a regular file no larger
/// than the memory budget (GEODE_MEMORY_MB), refused unread otherwise.
fn read_geometry(
    path: &std::path::Path,
    progress: &dyn geode_io::Progress,
) -> anyhow::Result<geode_geo::Geometry> {
    let format = geode_io::read_format(path)?;
    let bytes =
        geode_op::FileAccess::anywhere().read(path, geode_op::budget_from_env(), &|| false)?;
    Ok(geode_io::read_bytes(&bytes, format, path, progress)?)
}

fn serve(
    network: Option<PathBuf>,
    port: u16,
    open: bool,
    bind: Option<std::net::IpAddr>,
    allow: Vec<PathBuf>,
) -> anyhow::Result<()> {
    if let Some(ip) = bind.filter(|ip| !ip.is_loopback()) {
        eprintln!(
            "warning: listening on {ip}: other machines can reach this studio; anyone with \
             the URL's token can edit the network and overwrite its file"
        );
    }
    let running = geode_server::start(geode_server::Options {
        network,
        port,
        bind,
        cache: Some(std::sync::Arc::new(disk_cache::new_cache()?)),
        allow,
    })?;
    say!("geode studio: {}", running.url);
    if bind.is_some_and(|ip| ip.is_unspecified()) {
        eprintln!(
            "from another machine: http://<this machine's address>:{}/?token={}",
            running.addr.port(),
            running.token
        );
    }
    use std::io::Write as _;
    let _ = std::io::stdout().flush();
    if open {
        let opener = if cfg!(target_os = "macos") {
            "open"
        } else {
            "xdg-open"
        };
        if let Err(e) = std::process::Command::new(opener).arg(&running.url).spawn() {
            eprintln!("could not open a browser ({opener}: {e}); open the URL above");
        }
    }
    running.wait();
    Ok(())
}

/// Writes `args` to standard output (see `say!`).
fn write_stdout(args: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: writing to standard output: {e}");
        std::process::exit(1);
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        // A status per kind of failure (README: Exit status).
        Err(e) => {
            eprintln!("error: {}", chain_message(&e));
            ExitCode::from(exit::Exit::of(&e).code())
        }
    }
}

/// An error and its causes, `: `-joined, each cause said once: geode's
/// errors say their source in their own message and also return it as
/// their source (so it can be inspected), which `{:#}` would repeat.
fn chain_message(e: &anyhow::Error) -> String {
    let mut out = String::new();
    let mut said = String::new();
    for cause in e.chain() {
        let message = cause.to_string();
        if !said.contains(&message) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&message);
        }
        said = message;
    }
    out
}
