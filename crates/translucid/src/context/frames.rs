//! A frame as the context keeps it once made: what it cost and, for standalone frames, its
//! pixels; for frames on the engine's device, whether it is still in flight.

use crate::methods::MethodKind;
use crate::renderer::{Frame, HostFrame};
use crate::Image;

/// One view's share of a frame: its GPU time and counts (the frame's are their sums).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViewShare {
    pub gpu_ms: f64,
    pub method_ms: f64,
    pub fragments: u64,
    pub tail_fragments: u64,
    pub unpeeled_pixels: u64,
    pub dispatches: u64,
    pub overflowed: bool,
}

pub struct FrameRecord {
    pub method: MethodKind,
    pub width: u32,
    pub height: u32,
    /// `None` for frames on the engine's device, whose pixels are in the engine's image.
    pub image: Option<Image>,
    /// Recorded on the engine's device and not yet completed: no statistics yet.
    pub in_flight: bool,
    /// The renderer that drew it (`Renderers`).
    pub renderer: u64,
    /// Its views (engine's device): the renderer recorded each as a frame of its own.
    pub views: u32,
    /// Ended without completing, by the abandonment of an earlier frame: no statistics.
    pub abandoned: bool,
    pub frame_index: u64,
    pub stages: Vec<(&'static str, f64)>,
    pub method_ms: f64,
    pub peak_gpu_bytes: u64,
    pub fragments: u64,
    pub tail_fragments: u64,
    pub unpeeled_pixels: u64,
    pub rerenders: u32,
    /// The frame past a documented limit: not all of it is right (engine's device).
    pub overflowed: bool,
    pub dispatches: u64,
    /// Each view's share, in the frame's order (one for a frame of one view).
    pub shares: Vec<ViewShare>,
    /// What the calls that made the frame built (its recording, and on the engine's device
    /// its completion, where the method moves to the variants its counters call for):
    /// pipelines, and bytes of GPU memory.
    pub built: (u64, u64),
}

impl FrameRecord {
    /// A frame recorded on the engine's device, in flight.
    pub fn recorded(method: MethodKind, size: (u32, u32), renderer: u64, index: u64) -> Self {
        Self {
            method,
            width: size.0,
            height: size.1,
            image: None,
            in_flight: true,
            renderer,
            views: 1,
            abandoned: false,
            frame_index: index,
            stages: Vec::new(),
            method_ms: 0.0,
            peak_gpu_bytes: 0,
            fragments: 0,
            tail_fragments: 0,
            unpeeled_pixels: 0,
            rerenders: 0,
            overflowed: false,
            dispatches: 0,
            shares: Vec::new(),
            built: (0, 0),
        }
    }

    /// A standalone frame, rendered.
    pub fn rendered(method: MethodKind, frame: Frame, renderer: u64, index: u64) -> Self {
        let share = ViewShare {
            gpu_ms: frame.stages.iter().map(|(_, ms)| ms).sum(),
            method_ms: frame.method_ms(),
            fragments: frame.fragments,
            tail_fragments: frame.tail_fragments,
            unpeeled_pixels: frame.unpeeled_pixels,
            dispatches: frame.dispatches,
            overflowed: false,
        };
        Self {
            shares: vec![share],
            width: frame.image.width,
            height: frame.image.height,
            method_ms: frame.method_ms(),
            image: Some(frame.image),
            in_flight: false,
            stages: frame.stages,
            peak_gpu_bytes: frame.peak_gpu_bytes,
            fragments: frame.fragments,
            tail_fragments: frame.tail_fragments,
            unpeeled_pixels: frame.unpeeled_pixels,
            rerenders: frame.rerenders,
            dispatches: frame.dispatches,
            ..Self::recorded(method, (0, 0), renderer, index)
        }
    }

    /// Takes what a completed frame on the engine's device reports, for each of its views:
    /// their times and counts added up, stage by stage.
    pub fn completed(&mut self, views: Vec<HostFrame>) {
        self.in_flight = false;
        let mut stages: Vec<(&'static str, f64)> = Vec::new();
        for done in views {
            self.shares.push(ViewShare {
                gpu_ms: done.stages.iter().map(|(_, ms)| ms).sum(),
                method_ms: done.method_ms,
                fragments: done.fragments,
                tail_fragments: done.tail_fragments,
                unpeeled_pixels: done.unpeeled_pixels,
                dispatches: done.dispatches,
                overflowed: done.overflowed,
            });
            for (name, ms) in done.stages {
                match stages.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, total)) => *total += ms,
                    None => stages.push((name, ms)),
                }
            }
            self.method_ms += done.method_ms;
            self.peak_gpu_bytes = self.peak_gpu_bytes.max(done.peak_gpu_bytes);
            self.fragments += done.fragments;
            self.tail_fragments += done.tail_fragments;
            self.unpeeled_pixels += done.unpeeled_pixels;
            self.overflowed |= done.overflowed;
            self.dispatches += done.dispatches;
        }
        self.stages = stages;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(stages: Vec<(&'static str, f64)>, fragments: u64, overflowed: bool) -> HostFrame {
        HostFrame {
            method_ms: stages.iter().map(|(_, ms)| ms).sum(),
            stages,
            peak_gpu_bytes: 100,
            fragments,
            triangles: 0,
            dispatches: 10,
            tail_fragments: 0,
            unpeeled_pixels: 0,
            bands: 1,
            degraded_rows: 0,
            overflowed,
        }
    }

    #[test]
    fn a_frame_of_views_adds_up_their_stages_and_counts() {
        let mut record = FrameRecord::recorded(MethodKind::Exact, (48, 36), 1, 0);
        record.views = 2;
        record.completed(vec![
            view(vec![("setup", 1.0), ("raster", 2.0)], 5, false),
            view(vec![("setup", 0.5), ("raster", 3.0)], 7, true),
        ]);
        assert_eq!(record.stages, [("setup", 1.5), ("raster", 5.0)]);
        assert_eq!(record.method_ms, 6.5);
        assert_eq!((record.fragments, record.dispatches), (12, 20));
        assert_eq!(record.peak_gpu_bytes, 100);
        assert!(record.overflowed && !record.in_flight);
        // Each view's share, in order.
        let shares: Vec<(f64, u64, bool)> = record
            .shares
            .iter()
            .map(|s| (s.gpu_ms, s.fragments, s.overflowed))
            .collect();
        assert_eq!(shares, [(3.0, 5, false), (3.5, 7, true)]);
    }
}
