//! # octsolid-fuzz
//!
//! Fuzz targets for every octsolid parser ([`targets`]: `.oct`, OBJ, STL, PLY,
//! `.patches`, scene TOML, MagicaVoxel `.vox`, binvox, OpenVDB `.vdb`, and three that
//! go past parsing), and a mutation fuzzer on stable Rust that drives them
//! ([`driver`]): seeds from the committed corpus ([`corpus`]), mutations
//! ([`mutate`]) from a fixed-seed generator ([`rng`]), each case under
//! `catch_unwind`, a watchdog and a memory ceiling ([`guard`]). See `fuzz/README.md`
//! for why a stable harness and how to run it.
//!
//! The fuzzer has no coverage instrumentation (that needs nightly's sanitizer
//! coverage); its only feedback is the outcome of a case (the target's summary or
//! the library's error text), which keeps a mutant that reached a new outcome. What
//! it finds it finds by volume and by mutations aimed at what parsers get wrong:
//! extreme numbers in text, extreme integers in headers, repeated records, deep
//! nesting. The same target functions serve cargo-fuzz (`fuzz/cargo-fuzz/`) on
//! nightly, coverage-guided.

pub mod corpus;
pub mod driver;
pub mod guard;
pub mod mutate;
pub mod rng;
pub mod scratch;
pub mod targets;
