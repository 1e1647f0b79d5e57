//! `geode cook`, `geode check` and `geode fmt`: load a network, cook frames to files.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use geode_graph::{CookOptions, Document, Engine, Network};
use geode_op::{expand_frame, CancelToken, CookEnv, Value};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::exit::{tagged, Exit, Kind};

/// Reads and checks a network file, failing on any problem (`geode fmt`);
/// every problem is listed, each prefixed by the file.
pub fn load(path: &Path) -> Result<(Document, Network)> {
    let doc = read_document(path, &[])?;
    match Network::load(&doc, &geode_nodes::registry()) {
        Ok(net) => {
            print_notes(path, &net);
            Ok((doc, net))
        }
        Err(errors) => Err(problems(path, &errors)),
    }
}

/// Reads a network to cook, with parameters set first (`NODE/PARAM=VALUE`,
/// the node a path into subnets: `/sub/inner/param=2`; the value is JSON
/// (`0.5`, `[1, 2, 3]`, `"text"`) or else taken as text). Problems stay
/// local: each is printed as a warning and fails only the cooks that read
/// the node it belongs to.
pub fn load_with(path: &Path, sets: &[String]) -> Result<(Document, Network)> {
    let doc = read_document(path, sets)?;
    let net = Network::load_partial(&doc, &geode_nodes::registry())
        .map_err(|errors| problems(path, &errors))?;
    print_notes(path, &net);
    for e in net.problems() {
        eprintln!("{}: warning: {}", path.display(), describe(e));
    }
    Ok((doc, net))
}

fn read_document(path: &Path, sets: &[String]) -> Result<Document> {
    let text = geode_op::FileAccess::anywhere()
        .read_text(path, geode_op::budget_from_env(), &|| false)
        .context("cannot read the network")?;
    let mut doc = Document::from_json(&text)
        .with_context(|| path.display().to_string())
        .kind(Exit::Network)?;
    for set in sets {
        apply_set(&mut doc, set)
            .with_context(|| format!("{}: --set {set}", path.display()))
            .kind(Exit::Usage)?;
    }
    Ok(doc)
}

fn print_notes(path: &Path, net: &Network) {
    for note in net.notes() {
        eprintln!("{}: note: {note}", path.display());
    }
}

/// Every load problem, one a line, each prefixed by the file.
pub fn problems(path: &Path, errors: &[geode_graph::LoadError]) -> anyhow::Error {
    let lines: Vec<String> = errors
        .iter()
        .map(|e| format!("{}: {}", path.display(), describe(e)))
        .collect();
    tagged(
        Exit::Network,
        anyhow!(
            "{} problem{} in the network:\n{}",
            errors.len(),
            if errors.len() == 1 { "" } else { "s" },
            lines.join("\n")
        ),
    )
}

/// A load problem with the line and column of the parameter's text it
/// points at, where it points at one.
fn describe(e: &geode_graph::LoadError) -> String {
    match (&e.param, e.position) {
        (Some(p), Some(at)) => format!(
            "{}: parameter `{p}`: line {}, column {}: {}",
            e.path, at.line, at.column, e.message
        ),
        _ => e.to_string(),
    }
}

/// Frames from `--frame F` or `--frames A-B` (inclusive, step 1).
pub fn frames(frame: Option<f64>, range: Option<&str>) -> Result<Vec<f64>> {
    frames_given(frame, range).kind(Exit::Usage)
}

fn frames_given(frame: Option<f64>, range: Option<&str>) -> Result<Vec<f64>> {
    match (frame, range) {
        (Some(f), None) => Ok(vec![f]),
        (None, None) => Ok(vec![1.0]),
        (None, Some(r)) => {
            if let Ok(f) = r.trim().parse::<i64>() {
                return Ok(vec![f as f64]);
            }
            let (a, b) = r
                .split_once('-')
                .ok_or_else(|| anyhow!("--frames expects A-B, found `{r}`"))?;
            let (a, b): (i64, i64) = (
                a.trim().parse().context("--frames: start")?,
                b.trim().parse().context("--frames: end")?,
            );
            if b < a {
                bail!("--frames {r}: the end is before the start");
            }
            if b - a > 1_000_000 {
                bail!("--frames {r}: more than a million frames");
            }
            Ok((a..=b).map(|f| f as f64).collect())
        }
        (Some(_), Some(_)) => bail!("give --frame or --frames, not both"),
    }
}

/// Refuses an output path that does not name the frame when several
/// frames are written: each would overwrite the last.
pub fn check_per_frame(pattern: &str, frames: &[f64]) -> Result<()> {
    if frames.len() > 1 && !pattern.contains("$F") {
        return Err(tagged(
            Exit::Usage,
            anyhow!(
                "-o {pattern}: {} frames would all write this one file; name the frame with $F, $F4 or $FF",
                frames.len()
            ),
        ));
    }
    Ok(())
}

/// Replaces `$F` (frame), `$F2`..`$F9` (zero-padded frame) and `$FF`
/// (fractional frame): the rule file parameters follow too.
pub fn frame_path(pattern: &str, frame: f64) -> PathBuf {
    PathBuf::from(expand_frame(pattern, frame))
}

/// Lets Ctrl-C stop a file being written (nothing is left behind).
struct CancelOnly<'a>(&'a CancelToken);

impl geode_io::Progress for CancelOnly<'_> {
    fn cancelled(&self) -> bool {
        self.0.is_cancelled()
    }

    fn warn(&self, message: &str) {
        eprintln!("warning: {message}");
    }
}

/// Sets one parameter of the document: `NODE/PARAM=VALUE`.
fn apply_set(doc: &mut Document, set: &str) -> Result<()> {
    let (target, value) = set
        .split_once('=')
        .ok_or_else(|| anyhow!("expected NODE/PARAM=VALUE"))?;
    let (node_path, param) = target
        .trim_start_matches('/')
        .rsplit_once('/')
        .ok_or_else(|| anyhow!("expected NODE/PARAM=VALUE (no node named)"))?;
    let value: serde_json::Value =
        serde_json::from_str(value).unwrap_or_else(|_| serde_json::Value::String(value.to_owned()));
    let mut net = &mut doc.network;
    let names: Vec<&str> = node_path.split('/').collect();
    for (i, name) in names.iter().enumerate() {
        if !net.nodes.contains_key(*name) {
            let known: Vec<&str> = net.nodes.keys().map(String::as_str).collect();
            bail!("no node `{name}` (nodes: {})", known.join(", "));
        }
        let node = net.nodes.get_mut(*name).expect("checked above");
        if i + 1 == names.len() {
            node.params.insert(param.to_owned(), value);
            return Ok(());
        }
        net = node
            .network
            .as_deref_mut()
            .ok_or_else(|| anyhow!("`{name}` is not a subnet"))?;
    }
    unreachable!("the loop returns at the last name")
}

pub struct CookArgs<'a> {
    pub network: &'a Path,
    /// Parameters set before cooking (`NODE/PARAM=VALUE`).
    pub sets: &'a [String],
    pub node: Option<&'a str>,
    pub frames: Vec<f64>,
    pub output: Option<&'a str>,
    pub stats: bool,
}

pub fn cook(args: CookArgs) -> Result<()> {
    // A farm task says it is alive from the start, loading included.
    crate::farm::heartbeat::start_from_env();
    if let Some(pattern) = args.output {
        check_per_frame(pattern, &args.frames)?;
    }
    let (_, net) = load_with(args.network, args.sets)?;
    let env = CookEnv::for_network(args.network);
    let target = match args.node {
        // `spin` is `/spin`: node paths are absolute, as `--set` takes them.
        Some(n) if !n.starts_with('/') => format!("/{n}"),
        Some(n) => n.to_owned(),
        None => net.output().map(str::to_owned).ok_or_else(|| {
            tagged(
                Exit::Network,
                anyhow!(
                    "{}: the network names no output node; set \"output\" or pass --node",
                    args.network.display()
                ),
            )
        })?,
    };
    if net.node_type(&target).is_none() {
        let known: Vec<&str> = net.paths().collect();
        return Err(tagged(
            Exit::Usage,
            anyhow!(
                "{}: no node `{target}` (nodes: {})",
                args.network.display(),
                known.join(", ")
            ),
        ));
    }
    let engine = Engine::new(net, crate::disk_cache::cook_cache()?);
    let cancel = CancelToken::new();
    {
        let c = cancel.clone();
        // Ctrl-C asks running kernels to stop; nothing partial is written.
        let _ = ctrlc::set_handler(move || c.cancel());
    }
    let bar =
        ProgressBar::with_draw_target(Some(args.frames.len() as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("cooking [{bar:30}] {pos}/{len} frames {msg}")
            .expect("static template")
            .progress_chars("=> "),
    );
    let on_progress = |path: &str, _: f32| bar.set_message(path.to_owned());
    for &frame in &args.frames {
        let opts = CookOptions {
            frame,
            cancel: cancel.clone(),
            progress: Some(&on_progress),
            env: env.clone(),
            writes: true,
        };
        let result = engine.cook(&target, &opts).map_err(|errors| {
            let kind = Exit::of_cook(&errors);
            if kind == Exit::Interrupted {
                return tagged(
                    kind,
                    anyhow!("interrupted: nothing was written for frame {frame}"),
                );
            }
            let lines: Vec<String> = errors
                .iter()
                .map(|e| format!("{}: frame {frame}: {e}", args.network.display()))
                .collect();
            tagged(kind, anyhow!("the cook failed:\n{}", lines.join("\n")))
        })?;
        if cancel.is_cancelled() {
            return Err(tagged(
                Exit::Interrupted,
                anyhow!("interrupted: nothing was written for frame {frame}"),
            ));
        }
        bar.suspend(|| {
            for e in &result.events {
                for w in e.warnings.iter() {
                    eprintln!(
                        "{}: frame {frame}: warning: {}: {w}",
                        args.network.display(),
                        e.path
                    );
                }
            }
        });
        if let Some(pattern) = args.output {
            let path = frame_path(pattern, frame);
            match &result.value {
                Value::Geometry(g) => {
                    let g = geode_nodes::for_file(g, &path)?;
                    let progress = CancelOnly(&cancel);
                    geode_io::write_limited(&g, &path, &progress, env.memory_budget)?
                }
                Value::Field(_) => return Err(tagged(Exit::Network, anyhow!("{target} gives a field; mesh it with a polygonise node to write it"))),
                Value::Bundle(b) => return Err(tagged(Exit::Network, anyhow!("{target} gives a bundle ({}); extract one geometry with bundle_extract to write it", b.entries.keys().cloned().collect::<Vec<_>>().join(", ")))),
            }
            bar.suspend(|| eprintln!("frame {frame}: wrote {}", path.display()));
        }
        if args.stats {
            bar.suspend(|| {
                for e in &result.events {
                    eprintln!(
                        "  {:<40} {:<20} {:>4} {:>10.3} ms {:>12} bytes",
                        e.path,
                        e.node_type,
                        match (e.hit, e.from_store) {
                            (true, true) => "disk",
                            (true, false) => "hit",
                            _ => "cook",
                        },
                        e.seconds * 1e3,
                        e.bytes
                    );
                }
            });
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(())
}

/// Loads strictly and finds what cooking frame 1 would refuse without
/// cooking: every parameter evaluated (expressions included) and every
/// node's own check (each wrangle snippet compiled).
pub fn check(path: &Path) -> Result<()> {
    let doc = read_document(path, &[])?;
    let net = Network::load_partial(&doc, &geode_nodes::registry())
        .map_err(|errors| problems(path, &errors))?;
    print_notes(path, &net);
    // The loader's problems and the check's (of the nodes the loader
    // passed), all at once, by node path.
    let mut found = net.problems().to_vec();
    found.extend(net.check(1.0, &CookEnv::for_network(path)));
    found.sort_by(|a, b| a.path.cmp(&b.path));
    if !found.is_empty() {
        return Err(problems(path, &found));
    }
    say!(
        "{}: ok ({} nodes, output {})",
        path.display(),
        net.paths().count(),
        net.output().unwrap_or("none")
    );
    Ok(())
}

/// Rewrites a network in canonical form, atomically, keeping unknown fields.
pub fn fmt(path: &Path) -> Result<()> {
    let (doc, _) = load(path)?;
    let text = doc.to_json();
    geode_io::write_atomic(path, |w| {
        w.write_all(text.as_bytes())
            .map_err(|e| geode_io::IoError::os(path, e))
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_patterns() {
        assert_eq!(
            frame_path("out.$F4.obj", 7.0),
            PathBuf::from("out.0007.obj")
        );
        assert_eq!(frame_path("out.$F.obj", 12.0), PathBuf::from("out.12.obj"));
        assert_eq!(frame_path("a$FF-$F2", 2.5), PathBuf::from("a2.5-03"));
        assert_eq!(frame_path("plain.obj", 3.0), PathBuf::from("plain.obj"));
    }

    #[test]
    fn frame_ranges() {
        assert_eq!(frames(None, Some("3-5")).unwrap(), vec![3.0, 4.0, 5.0]);
        assert_eq!(frames(Some(2.5), None).unwrap(), vec![2.5]);
        assert_eq!(frames(None, None).unwrap(), vec![1.0]);
        assert_eq!(
            frames(None, Some("5-3")).unwrap_err().to_string(),
            "--frames 5-3: the end is before the start"
        );
        assert!(frames(None, Some("x")).is_err());
        assert_eq!(frames(None, Some("7")).unwrap(), vec![7.0]);
        assert_eq!(
            check_per_frame("out.bgeo", &[1.0, 2.0]).unwrap_err().to_string(),
            "-o out.bgeo: 2 frames would all write this one file; name the frame with $F, $F4 or $FF"
        );
        assert!(check_per_frame("out.bgeo", &[1.0]).is_ok());
        assert!(check_per_frame("out.$F4.bgeo", &[1.0, 2.0]).is_ok());
    }
}
