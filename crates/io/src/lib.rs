//! geode's file formats. Reads OBJ (with OpenSubdiv tags), STL, PLY,
//! glTF/GLB and Houdini's .geo/.bgeo; writes OBJ, binary STL, binary PLY,
//! GLB, USDA and .geo/.bgeo. Every write is atomic. The only crate besides the CLI that touches the file system.

mod atomic;
mod attrib_codec;
mod error;
mod gltf_attribs;
mod gltf_instancing;
mod gltf_read;
mod gltf_write;
mod houdini;
pub mod obj;
mod ply;
mod ply_build;
mod ply_write;
mod progress;
mod stl;
mod text;
mod usda;
mod usda_primvars;
pub mod vdb;
mod weld;

use std::path::Path;

use geode_geo::{ops, Geometry};

pub use atomic::{abandoned_temporary, process_alive, write_atomic, write_atomic_shared};
pub use error::{IoError, ParseError, Position};
pub use progress::{NoProgress, Progress};

/// A file format geode reads or writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Obj,
    Stl,
    Ply,
    Gltf,
    Glb,
    Usda,
    /// Houdini's JSON geometry.
    Geo,
    /// Houdini's binary JSON geometry.
    Bgeo,
}

impl Format {
    pub const ALL: [Format; 8] = [
        Format::Obj,
        Format::Stl,
        Format::Ply,
        Format::Gltf,
        Format::Glb,
        Format::Usda,
        Format::Geo,
        Format::Bgeo,
    ];

    /// The format named by a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "obj" => Format::Obj,
            "stl" => Format::Stl,
            "ply" => Format::Ply,
            "gltf" => Format::Gltf,
            "glb" => Format::Glb,
            "usda" => Format::Usda,
            "geo" => Format::Geo,
            "bgeo" => Format::Bgeo,
            _ => return None,
        })
    }

    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Stl => "stl",
            Format::Ply => "ply",
            Format::Gltf => "gltf",
            Format::Glb => "glb",
            Format::Usda => "usda",
            Format::Geo => "geo",
            Format::Bgeo => "bgeo",
        }
    }

    pub fn can_read(self) -> bool {
        self != Format::Usda
    }

    pub fn can_write(self) -> bool {
        self != Format::Gltf
    }

    /// Whether the format keeps packed instances as instances.
    pub fn keeps_instances(self) -> bool {
        matches!(
            self,
            Format::Glb | Format::Usda | Format::Geo | Format::Bgeo
        )
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.extension())
    }
}

fn list(f: impl Fn(Format) -> bool) -> String {
    Format::ALL
        .iter()
        .filter(|x| f(**x))
        .map(|x| format!(".{}", x.extension()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parses bytes in a format; `path` names the source in errors and gives the
/// folder external glTF buffers are read from.
pub fn read_bytes(
    bytes: &[u8],
    format: Format,
    path: &Path,
    progress: &dyn Progress,
) -> Result<Geometry, IoError> {
    if bytes.is_empty() {
        return Err(ParseError::byte(
            0,
            format!(
                "empty file: expected {} data",
                format.extension().to_uppercase()
            ),
        )
        .in_file(path));
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        parse_unguarded(bytes, format, path.parent(), progress)
    }));
    match result {
        Ok(r) => r.map_err(|e| e.in_file(path)),
        // Defence in depth for third-party parsers: a panic is a parse error, not a crash.
        Err(_) => Err(ParseError::whole("malformed file (the parser rejected it)").in_file(path)),
    }
}

/// The parsers without the panic guard of [`read_bytes`]: for fuzz targets,
/// which must see a panic to report it.
#[doc(hidden)]
pub fn parse_unguarded(
    bytes: &[u8],
    format: Format,
    base: Option<&Path>,
    progress: &dyn Progress,
) -> Result<Geometry, ParseError> {
    match format {
        Format::Obj => obj::read_obj(bytes, progress),
        Format::Stl => stl::read_stl(bytes, progress),
        Format::Ply => ply::read_ply(bytes, progress),
        Format::Gltf | Format::Glb => gltf_read::read_gltf(bytes, base, progress),
        Format::Geo | Format::Bgeo => houdini::read_houdini(bytes, progress.memory_budget()),
        Format::Usda => Err(ParseError::whole(
            "reading USDA is not supported (geode writes it)",
        )),
    }
}

/// Reads a geometry file, the format chosen by its extension. Only a
/// regular file is read (a device or a pipe may never end); callers with a
/// memory budget read the bytes themselves and call [`read_bytes`].
pub fn read(path: &Path, progress: &dyn Progress) -> Result<Geometry, IoError> {
    let format = read_format(path)?;
    let bytes = read_regular(path).map_err(|e| IoError::os(path, e))?;
    read_bytes(&bytes, format, path, progress)
}

/// A whole regular file's bytes; anything else is refused unread. The kind
/// is asked before opening (opening a FIFO waits for a writer forever) and
/// again of the open file (it may have been swapped in between).
pub(crate) fn read_regular(path: &Path) -> std::io::Result<Vec<u8>> {
    let not_regular = || {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file; only regular files are read",
        )
    };
    if !std::fs::metadata(path)?.file_type().is_file() {
        return Err(not_regular());
    }
    let mut file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if !meta.file_type().is_file() {
        return Err(not_regular());
    }
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(meta.len() as usize)?;
    std::io::Read::read_to_end(&mut file, &mut bytes)?;
    Ok(bytes)
}

/// The format a file is read as, from its extension.
pub fn read_format(path: &Path) -> Result<Format, IoError> {
    Format::from_path(path)
        .filter(|f| f.can_read())
        .ok_or_else(|| IoError::UnknownFormat {
            path: path.to_owned(),
            expected: list(Format::can_read),
        })
}

/// Encodes a geometry into bytes of a format. Formats without instancing get
/// the packed primitives unpacked.
pub fn write_bytes(
    g: &Geometry,
    format: Format,
    path: &Path,
    progress: &dyn Progress,
) -> Result<Vec<u8>, IoError> {
    let mut out = Vec::new();
    encode(g, format, path, &mut out, progress, u64::MAX)?;
    Ok(out)
}

/// Refuses, before unpacking, packed geometry whose unpacked form would not
/// fit `memory_budget` bytes.
fn check_unpack_budget(g: &Geometry, path: &Path, memory_budget: u64) -> Result<(), IoError> {
    let bytes = ops::unpacked_bytes(g);
    if bytes <= memory_budget as f64 {
        return Ok(());
    }
    let instances = g.packed_instances().len();
    Err(IoError::TooLarge {
        path: path.to_owned(),
        message: format!(
            "unpacking {instances} packed instances for this format would need about {:.1} GB, more than the memory budget of {:.1} GB (GEODE_MEMORY_MB); write .glb or .usda, which keep instances",
            bytes / 1e9,
            memory_budget as f64 / 1e9
        ),
    })
}

fn encode(
    g: &Geometry,
    format: Format,
    path: &Path,
    w: &mut dyn std::io::Write,
    progress: &dyn Progress,
    memory_budget: u64,
) -> Result<(), IoError> {
    let unpacked;
    let g = if !format.keeps_instances() && g.has_packed() {
        check_unpack_budget(g, path, memory_budget)?;
        unpacked = ops::unpack_with(g, &|| progress.cancelled()).map_err(|e| match e {
            geode_geo::GeoError::Cancelled => IoError::Cancelled {
                path: path.to_owned(),
            },
            e => IoError::Unsupported {
                path: path.to_owned(),
                message: e.to_string(),
            },
        })?;
        &unpacked
    } else {
        g
    };
    if format != Format::Usda && has_patches(g) {
        return Err(IoError::Unsupported {
            path: path.to_owned(),
            message: format!(
                "{format} cannot hold spline patches: convert them to polygons first (node `convert`; `geode cook` does it for you), or write .usda, which keeps them"
            ),
        });
    }
    match format {
        Format::Obj => obj::write_obj(g, w, path, progress),
        Format::Stl => stl::write_stl(g, w, path, progress),
        Format::Ply => ply_write::write_ply(g, w, path, progress),
        Format::Glb => gltf_write::write_glb(g, w, path, progress),
        Format::Usda => usda::write_usda(g, w, path, progress),
        Format::Geo | Format::Bgeo => {
            let binary = format == Format::Bgeo;
            let bytes = houdini::encode_houdini(g, binary, &|| progress.cancelled()).map_err(
                |e| match e {
                    houdini::EncodeError::Unsupported(message) => IoError::Unsupported {
                        path: path.to_owned(),
                        message,
                    },
                    houdini::EncodeError::Cancelled => IoError::Cancelled {
                        path: path.to_owned(),
                    },
                },
            )?;
            w.write_all(&bytes).map_err(|e| IoError::os(path, e))
        }
        Format::Gltf => Err(IoError::UnknownFormat {
            path: path.to_owned(),
            expected: list(Format::can_write),
        }),
    }
}

/// Whether `g` or any geometry it instances has a spline patch.
pub fn has_patches(g: &Geometry) -> bool {
    g.has_patches() || g.packed_instances().iter().any(|i| has_patches(&i.source))
}

/// Writes a geometry file atomically, the format chosen by the extension
/// (no memory budget: see [`write_limited`]).
pub fn write(g: &Geometry, path: &Path, progress: &dyn Progress) -> Result<(), IoError> {
    write_limited(g, path, progress, u64::MAX)
}

/// Writes a geometry file atomically, refusing to unpack instances beyond
/// `memory_budget` bytes. `progress.cancelled()` is polled while encoding
/// and between every megabyte written; a cancelled write leaves nothing.
pub fn write_limited(
    g: &Geometry,
    path: &Path,
    progress: &dyn Progress,
    memory_budget: u64,
) -> Result<(), IoError> {
    let format = Format::from_path(path)
        .filter(|f| f.can_write())
        .ok_or_else(|| IoError::UnknownFormat {
            path: path.to_owned(),
            expected: list(Format::can_write),
        })?;
    let r = write_atomic(path, |w| {
        let mut w = atomic::Cancelling {
            inner: w,
            cancelled: &|| progress.cancelled(),
        };
        encode(g, format, path, &mut w, progress, memory_budget)
    });
    match r {
        Err(_) if progress.cancelled() => Err(IoError::Cancelled {
            path: path.to_owned(),
        }),
        r => r,
    }
}

/// The texture coordinates of class `class` (`uv`), as pairs: a `uv` of
/// two floats, or Houdini's three (z dropped). None for anything else.
pub(crate) fn texcoords(
    g: &Geometry,
    class: geode_geo::AttribClass,
) -> Option<std::borrow::Cow<'_, [geode_geo::glam::Vec2]>> {
    use geode_geo::AttribData;
    match g.attrib(class, "uv").map(|a| a.data()) {
        Some(AttribData::Vec2(v)) => Some(std::borrow::Cow::Borrowed(v.as_slice())),
        Some(AttribData::Vec3(v)) => Some(std::borrow::Cow::Owned(
            v.iter().map(|t| t.truncate()).collect(),
        )),
        _ => None,
    }
}
