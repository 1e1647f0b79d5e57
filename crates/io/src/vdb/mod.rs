//! OpenVDB `.vdb` files: float grids as geode's sparse volumes, out and in.
//! The layout (file version 224, as OpenVDB 8 to 12 write it) is VDB's
//! 5-4-3 tree: a root of upper internal nodes (32^3 slots of 128^3
//! voxels), lower internal nodes (16^3 slots of leaves) and 8^3 leaves.
//! Geode writes values with active-value masks, raw (what OpenVDB itself
//! writes for level sets without Blosc) or zlib-compressed, and reads every encoding
//! OpenVDB writes: raw, zlib, Blosc with LZ4, half floats, mask
//! compression, tiles at every level. Grids of other value types are
//! skipped by their recorded end.

mod blosc;
mod read;
mod tree;
mod write;

pub use read::read_vdb;
pub use write::{write_vdb, VdbCompression};

/// A malformed or unsupported `.vdb` file, and the byte where it was found.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum VdbError {
    #[error("byte {offset}: {message}")]
    Malformed { offset: u64, message: String },
    /// Holding the file's voxels would pass the memory budget.
    #[error("holding its {leaves} leaves of voxels needs {bytes} bytes, over the memory budget of {budget}")]
    TooLarge {
        leaves: u64,
        bytes: u64,
        budget: u64,
    },
    /// The reader was cancelled.
    #[error("cancelled")]
    Cancelled,
}

/// The value type name OpenVDB gives a float tree.
const FLOAT_TREE: &str = "Tree_float_5_4_3";
/// The magic number, written as an i64.
const MAGIC: i64 = 0x5644_4220;
/// The file format version geode writes (OpenVDB's since 8.0).
const FILE_VERSION: u32 = 224;
/// The oldest version whose layout this reader knows (per-grid
/// compression flags).
const OLDEST_VERSION: u32 = 222;
/// Compression flags: zlib, active-value masks, Blosc.
const COMPRESS_ZIP: u32 = 1;
const COMPRESS_ACTIVE_MASK: u32 = 2;
const COMPRESS_BLOSC: u32 = 4;
