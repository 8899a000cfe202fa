//! Image error measures (filled in by the reference work).
