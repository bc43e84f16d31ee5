//! Rendering octree solids: ray traversal, cameras, shading, images.

pub mod traverse;

pub use traverse::{Hit, Traversal};
