//! The `geode` command: inspect and convert geometry files.

mod info;
mod progress;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  geode info examples/assets/creased_box.obj
  geode info --json model.glb
  geode convert examples/assets/creased_box.obj /tmp/box.glb
  geode convert scan.ply print.stl

Exit codes: 0 success, 1 a file could not be read or written, 2 bad usage.";

/// geode: a procedural geometry engine.
#[derive(Parser)]
#[command(name = "geode", version, about, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print counts, bounds, attributes, groups, topology and content hash of a file.
    #[command(after_help = "Example:\n  geode info examples/assets/creased_box.obj")]
    Info {
        /// Geometry file (.obj, .stl, .ply, .gltf, .glb).
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Convert between formats (chosen by extension). The output is written atomically.
    #[command(
        after_help = "Example:\n  geode convert examples/assets/creased_box.obj /tmp/box.glb\n\n\
        Formats without instancing (.obj, .stl, .ply) get packed instances unpacked."
    )]
    Convert {
        /// Input file (.obj, .stl, .ply, .gltf, .glb).
        input: PathBuf,
        /// Output file (.obj, .stl, .ply, .glb, .usda).
        output: PathBuf,
    },
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Info { file, json } => {
            let g = geode_io::read(&file, &progress::Bar::new())?;
            let report = info::Report::new(&file, &g);
            if json {
                println!("{}", report.to_json());
            } else {
                print!("{}", report.to_text());
            }
        }
        Command::Convert { input, output } => {
            let bar = progress::Bar::new();
            let g = geode_io::read(&input, &bar)?;
            geode_io::write(&g, &output, &bar)?;
            eprintln!(
                "wrote {} ({} points, {} primitives)",
                output.display(),
                g.num_points(),
                g.num_prims()
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
