//! ARCHITECTURE.md stays true: every path it names exists. Paths with a
//! `/` are taken from the repository root or from the `src` of the crate
//! whose section names them; bare file names must exist in that crate (or,
//! outside a crate's section, anywhere in the repository).

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// Every file and folder under `dir`, skipping build output and installs.
fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if ["target", ".git", "node_modules", ".venv"].contains(&name.as_str()) {
            continue;
        }
        if p.is_dir() {
            walk(&p, out);
        }
        out.push(p);
    }
}

fn looks_like_path(token: &str) -> bool {
    const EXTENSIONS: [&str; 10] = [
        ".rs", ".md", ".json", ".sh", ".py", ".mjs", ".cpp", ".toml", ".hs", ".ts",
    ];
    let chars_ok = token
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || "._/-".contains(c));
    let start_ok = !token.starts_with('.') || token.starts_with("../") || token.starts_with(".ci/");
    chars_ok && start_ok && (token.contains('/') || EXTENSIONS.iter().any(|e| token.ends_with(e)))
}

#[test]
fn every_path_architecture_names_exists() {
    let root = root();
    let text = std::fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
    let mut files = Vec::new();
    walk(&root, &mut files);
    let mut crate_dir: Option<PathBuf> = None;
    let mut missing = Vec::new();
    let mut checked = 0;
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("### ") {
            crate_dir = h
                .split('`')
                .nth(1)
                .filter(|c| c.starts_with("crates/") || c.starts_with("studio/"))
                .map(|c| root.join(c));
            continue;
        }
        if line.starts_with("## ") {
            crate_dir = None;
        }
        for (k, token) in line.split('`').enumerate() {
            if k.is_multiple_of(2) || !looks_like_path(token) {
                continue;
            }
            checked += 1;
            let rel = token.trim_end_matches('/');
            let found = if token.contains('/') {
                root.join(rel).exists()
                    || crate_dir
                        .as_ref()
                        .is_some_and(|c| c.join("src").join(rel).exists() || c.join(rel).exists())
            } else {
                let within = crate_dir.clone().unwrap_or_else(|| root.clone());
                files
                    .iter()
                    .any(|f| f.starts_with(&within) && f.file_name().is_some_and(|n| n == token))
            };
            if !found {
                missing.push(token.to_owned());
            }
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md names paths that do not exist: {missing:?}"
    );
    assert!(checked > 60, "only {checked} paths checked");
}
