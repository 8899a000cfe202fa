//! Rasterization rules (filled in by the reference work).
