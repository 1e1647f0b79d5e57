//! The live session: the opened network document, edits validated by the loader, undo and redo, the dirty marker, atomic save.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use geode_graph::{Document, LoadError, Network};
use geode_op::Registry;
use serde_json::{json, Value as Json};

use crate::edits::{self, Edit, EditError};

/// Undo steps kept (documents are small; this bounds a long session).
const UNDO_DEPTH: usize = 1000;

#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    // The causes are part of the message, not sources: shown once.
    /// The network file could not be read (missing, no regular file,
    /// larger than the memory budget); the refusal names the file.
    #[error("{0}")]
    Read(geode_op::FileRefusal),
    #[error("{path}: {cause}")]
    Syntax {
        path: PathBuf,
        cause: geode_graph::SyntaxError,
    },
    #[error(transparent)]
    Write(#[from] geode_io::IoError),
    #[error("the network has no file yet: give a path to save as")]
    NoPath,
    #[error("save as `{0}`: a network file ends in .json")]
    NotJson(PathBuf),
}

/// One step of the history: the document on the other side of it, and the
/// tab (socket) whose edit it was. Each tab undoes only its own steps.
struct Step {
    doc: Document,
    client: u64,
}

/// Why an undo or redo was not made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HistoryError {
    #[error("nothing to {0}")]
    Nothing(&'static str),
    #[error("another tab made the latest change: {0} it there (each tab undoes its own edits)")]
    OtherTab(&'static str),
}

/// The opened network and its history.
pub struct Session {
    registry: Arc<Registry>,
    path: Option<PathBuf>,
    doc: Document,
    /// The document as last read or saved (dirty = differs).
    saved: Document,
    undo: Vec<Step>,
    redo: Vec<Step>,
    /// The tab and parameter of the last edit, when the tab asked to merge
    /// (a slider drag is one undo step).
    merge_target: Option<(u64, String, String)>,
    network: Result<Network, Vec<LoadError>>,
    /// Bumped by every change of the document.
    version: u64,
}

impl Session {
    /// Opens `path` (a missing file starts an empty network that will be saved there).
    pub fn open(path: Option<&Path>, registry: Arc<Registry>) -> Result<Session, SessionError> {
        let doc = match path {
            Some(p) if p.exists() => {
                let text = geode_op::FileAccess::anywhere()
                    .read_text(p, geode_op::budget_from_env(), &|| false)
                    .map_err(SessionError::Read)?;
                Document::from_json(&text).map_err(|cause| SessionError::Syntax {
                    path: p.to_owned(),
                    cause,
                })?
            }
            _ => Document::new(),
        };
        let network = Network::load_partial(&doc, &registry);
        Ok(Session {
            registry,
            path: path.map(Path::to_owned),
            saved: doc.clone(),
            doc,
            undo: Vec::new(),
            redo: Vec::new(),
            merge_target: None,
            network,
            version: 1,
        })
    }

    pub fn registry(&self) -> &Arc<Registry> {
        &self.registry
    }

    pub fn document(&self) -> &Document {
        &self.doc
    }

    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    pub fn version(&self) -> u64 {
        self.version
    }

    /// The loaded network (each node's problems kept on it, failing only
    /// what reads that node), or why the document is no network at all.
    pub fn network(&self) -> &Result<Network, Vec<LoadError>> {
        &self.network
    }

    pub fn is_dirty(&self) -> bool {
        self.doc != self.saved
    }

    /// Applies an edit of tab 0 (see [`Session::edit_by`]).
    pub fn edit(&mut self, edit: &Edit, merge: bool) -> Result<(), EditError> {
        self.edit_by(edit, merge, 0)
    }

    /// Applies an edit made by tab `client`; `merge` folds it into that
    /// tab's previous step when both set the same parameter (dragging a
    /// slider is one undo step).
    pub fn edit_by(&mut self, edit: &Edit, merge: bool, client: u64) -> Result<(), EditError> {
        let next = edits::apply(&self.doc, edit, &self.registry)?;
        let target = match edit {
            Edit::SetParam { path, param, .. } => Some((client, path.clone(), param.clone())),
            _ => None,
        };
        let merged = merge && target.is_some() && target == self.merge_target;
        if !merged {
            self.undo.push(Step {
                doc: self.doc.clone(),
                client,
            });
            if self.undo.len() > UNDO_DEPTH {
                self.undo.remove(0);
            }
        }
        self.merge_target = target;
        self.redo.clear();
        self.replace(next);
        Ok(())
    }

    /// Undoes tab 0's latest step; false when there is none to undo.
    pub fn undo(&mut self) -> bool {
        self.undo_by(0).is_ok()
    }

    /// Redoes tab 0's latest undone step; false when there is none.
    pub fn redo(&mut self) -> bool {
        self.redo_by(0).is_ok()
    }

    /// Undoes the latest step if tab `client` made it (undoing an older
    /// one would also drop the later edits of another tab).
    pub fn undo_by(&mut self, client: u64) -> Result<(), HistoryError> {
        self.travel(true, client)
    }

    pub fn redo_by(&mut self, client: u64) -> Result<(), HistoryError> {
        self.travel(false, client)
    }

    /// One step back (undo) or forward (redo) through the history.
    fn travel(&mut self, back: bool, client: u64) -> Result<(), HistoryError> {
        let (from, to, verb) = if back {
            (&mut self.undo, &mut self.redo, "undo")
        } else {
            (&mut self.redo, &mut self.undo, "redo")
        };
        match from.last() {
            None => return Err(HistoryError::Nothing(verb)),
            Some(step) if step.client != client => return Err(HistoryError::OtherTab(verb)),
            Some(_) => {}
        }
        let step = from.pop().expect("checked above");
        to.push(Step {
            doc: self.doc.clone(),
            client,
        });
        self.merge_target = None;
        self.replace(step.doc);
        Ok(())
    }

    fn replace(&mut self, doc: Document) {
        self.network = Network::load_partial(&doc, &self.registry);
        self.doc = doc;
        self.version += 1;
    }

    /// Writes the document in canonical form (as `geode fmt`), atomically, to
    /// its file or to `save_as` (which then becomes its file).
    pub fn save(&mut self, save_as: Option<&Path>) -> Result<PathBuf, SessionError> {
        let path = match save_as {
            Some(p) if p.extension().and_then(|e| e.to_str()) != Some("json") => {
                return Err(SessionError::NotJson(p.to_owned()))
            }
            Some(p) => p.to_owned(),
            None => self.path.clone().ok_or(SessionError::NoPath)?,
        };
        let text = self.doc.to_json();
        geode_io::write_atomic(&path, |w| {
            w.write_all(text.as_bytes())
                .map_err(|e| geode_io::IoError::os(&path, e))
        })?;
        self.saved = self.doc.clone();
        self.path = Some(path.clone());
        self.version += 1;
        Ok(path)
    }

    /// Load problems keyed for the studio: node path, parameter, message.
    pub fn problems(&self) -> Vec<Json> {
        let (errors, notes) = match &self.network {
            Ok(n) => (n.problems(), n.notes()),
            Err(e) => (&e[..], &[][..]),
        };
        let item = |e: &LoadError, level: &str| {
            json!({"path": e.path, "param": e.param, "message": e.message, "level": level,
            "line": e.position.map(|p| p.line), "column": e.position.map(|p| p.column)})
        };
        errors
            .iter()
            .map(|e| item(e, "error"))
            .chain(notes.iter().map(|e| item(e, "note")))
            .collect()
    }

    /// The session as the studio shows it.
    pub fn state(&self) -> Json {
        json!({
            "type": "state",
            "version": self.version,
            "path": self.path.as_ref().map(|p| p.display().to_string()),
            "document": self.doc,
            "problems": self.problems(),
            "dirty": self.is_dirty(),
            "canUndo": !self.undo.is_empty(),
            "canRedo": !self.redo.is_empty(),
            // The tab whose step is next to undo or redo (only it may).
            "undoBy": self.undo.last().map(|s| s.client),
            "redoBy": self.redo.last().map(|s| s.client),
            "output": self.network.as_ref().ok().and_then(|n| n.output().map(str::to_owned)),
        })
    }
}
