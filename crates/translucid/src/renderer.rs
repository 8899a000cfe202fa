//! Frame rendering.
