//! Transparency methods.
