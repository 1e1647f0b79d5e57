//! Shared by the UV kernel's integration tests.

pub mod meshes;
