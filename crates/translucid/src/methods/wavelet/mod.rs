//! `wavelet`: Haar-wavelet transmittance OIT (see DESIGN.md, "Wavelet OIT").

pub mod math;
