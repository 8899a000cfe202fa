//! CPU exact renderer (filled in by the reference work).
