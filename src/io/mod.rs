//! Reading and writing solids and images: the native `.oct` format (see
//! `docs/FORMAT.md`), PNG output, and the atomic write both use.

pub mod atomic;
pub mod oct;
pub mod png;
