//! Reading and writing solids.
