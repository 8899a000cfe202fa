//! Frames recorded on the engine's device and not yet completed, oldest first. The engine
//! submits them to one queue in the order they were recorded, so they run, and complete, in
//! that order: completing one completes the older ones first, and abandoning one ends the
//! newer ones too (their commands may depend on its).

use crate::{Error, Result};
use std::collections::VecDeque;

pub struct Flight {
    frames: VecDeque<u64>,
    /// The most frames in flight at once.
    most: u32,
}

impl Flight {
    pub fn new(most: u32) -> Self {
        Self {
            frames: VecDeque::new(),
            most,
        }
    }

    /// Whether another frame may be recorded: not while `most` are in flight.
    pub fn room(&self) -> Result<()> {
        match self.frames.front() {
            Some(&oldest) if self.frames.len() >= self.most as usize => {
                Err(Error::FrameInFlight(format!(
                    "{} frame(s) recorded and not completed, as many as the context was made \
                     for (translucid_context_create_info.frames_in_flight): call \
                     translucid_frame_complete for the oldest, {{{oldest:#x}}}, once its \
                     submission finished",
                    self.most
                )))
            }
            _ => Ok(()),
        }
    }

    /// Notes `frame` recorded, after every frame in flight.
    pub fn recorded(&mut self, frame: u64) {
        self.frames.push_back(frame);
    }

    /// The oldest frame in flight.
    pub fn oldest(&self) -> Option<u64> {
        self.frames.front().copied()
    }

    /// Ends the oldest frame's flight.
    pub fn oldest_completed(&mut self) {
        self.frames.pop_front();
    }

    /// The frames to complete, oldest first, for `frame` to be complete: those recorded
    /// before it, then it.
    pub fn to_complete(&self, frame: u64) -> Result<Vec<u64>> {
        let Some(at) = self.frames.iter().position(|&f| f == frame) else {
            return Err(Error::InvalidArgument(
                "the frame is not in flight: it was completed (completing a newer frame \
                 completes the older ones) or abandoned already"
                    .into(),
            ));
        };
        Ok(self.frames.iter().take(at + 1).copied().collect())
    }

    /// Ends the flight of `frame` and of every frame recorded after it, without completing
    /// them: those frames, `frame` first.
    pub fn abandon(&mut self, frame: u64) -> Result<Vec<u64>> {
        let Some(at) = self.frames.iter().position(|&f| f == frame) else {
            return Err(Error::InvalidArgument(
                "the frame is not in flight: destroy it with translucid_frame_destroy".into(),
            ));
        };
        Ok(self.frames.split_off(at).into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_complete_in_recording_order_up_to_the_most_in_flight() {
        let mut flight = Flight::new(3);
        for frame in [10, 11, 12] {
            flight.room().expect("room");
            flight.recorded(frame);
        }
        assert!(matches!(flight.room(), Err(Error::FrameInFlight(m)) if m.contains("0xa")));
        // Completing the newest completes the older ones first.
        assert_eq!(flight.to_complete(12).expect("in flight"), [10, 11, 12]);
        assert_eq!(flight.to_complete(10).expect("in flight"), [10]);
        assert_eq!(flight.oldest(), Some(10));
        flight.oldest_completed();
        flight.room().expect("room again");
        assert!(matches!(
            flight.to_complete(10),
            Err(Error::InvalidArgument(_))
        ));
    }

    #[test]
    fn abandoning_a_frame_ends_the_newer_ones_too() {
        let mut flight = Flight::new(4);
        for frame in 1..=4 {
            flight.recorded(frame);
        }
        assert_eq!(flight.abandon(2).expect("in flight"), [2, 3, 4]);
        assert_eq!(flight.oldest(), Some(1));
        assert!(matches!(flight.abandon(3), Err(Error::InvalidArgument(_))));
        assert_eq!(flight.to_complete(1).expect("in flight"), [1]);
    }
}
