//! What the library's unit tests share: the tests' one seeded generator, the same
//! file as `tests/common`'s, so a test moved beside the code keeps its cases.

#[path = "../tests/common/rng.rs"]
mod rng;

pub(crate) use rng::Rng;
