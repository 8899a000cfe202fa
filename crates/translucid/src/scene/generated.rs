//! Generated scenes (filled in by the scene work).
