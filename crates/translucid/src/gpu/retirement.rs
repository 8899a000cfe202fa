//! GPU objects replaced while frames that use them may still be in flight: kept until every
//! frame recorded before the replacement has completed.

#![deny(unsafe_code)]

use std::any::Any;

/// Frames are counted as they are recorded and as they complete, in order; an object retired
/// after `n` recordings is dropped once `n` frames have completed.
#[derive(Default)]
pub struct Retirement {
    recorded: u64,
    completed: u64,
    held: Vec<(u64, Box<dyn Any>)>,
}

impl Retirement {
    /// A frame that may use the current objects was recorded.
    pub fn recorded(&mut self) {
        self.recorded += 1;
    }

    /// The oldest frame in flight completed: what only it and earlier frames used is freed.
    pub fn completed(&mut self) {
        self.completed = (self.completed + 1).min(self.recorded);
        let completed = self.completed;
        self.held.retain(|(last_user, _)| *last_user > completed);
    }

    /// The newest `frames` recorded will never run (the engine abandoned them): what was
    /// retired while they were recorded goes once the frames recorded before them complete.
    pub fn abandoned(&mut self, frames: u64) {
        self.recorded = self.recorded.saturating_sub(frames).max(self.completed);
        let (recorded, completed) = (self.recorded, self.completed);
        for (last_user, _) in &mut self.held {
            *last_user = (*last_user).min(recorded);
        }
        self.held.retain(|(last_user, _)| *last_user > completed);
    }

    /// Keeps `object` (buffers, views, sets, pipelines: anything whose drop frees Vulkan
    /// objects) until the frames recorded so far have completed.
    pub fn retire(&mut self, object: impl Any) {
        if self.recorded > self.completed {
            self.held.push((self.recorded, Box::new(object)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::rc::Rc;

    #[test]
    fn objects_live_until_the_frames_recorded_before_them_complete() {
        let mut r = Retirement::default();
        let object = Rc::new(());
        r.recorded();
        r.recorded();
        r.retire(object.clone());
        r.recorded();
        r.completed();
        assert_eq!(Rc::strong_count(&object), 2, "frame 2 may still use it");
        r.completed();
        assert_eq!(Rc::strong_count(&object), 1, "frames 1 and 2 completed");
        // Nothing in flight: dropped at once.
        r.completed();
        r.retire(object.clone());
        assert_eq!(Rc::strong_count(&object), 1);
    }

    #[test]
    fn abandoned_frames_hold_nothing() {
        let mut r = Retirement::default();
        let object = Rc::new(());
        r.recorded();
        r.recorded();
        r.retire(object.clone());
        r.recorded();
        r.abandoned(2);
        assert_eq!(Rc::strong_count(&object), 2, "frame 1 may still use it");
        r.completed();
        assert_eq!(
            Rc::strong_count(&object),
            1,
            "frame 1 completed, 2 and 3 never run"
        );
        // Counting goes on from the frames that may run.
        r.recorded();
        r.retire(object.clone());
        r.completed();
        assert_eq!(Rc::strong_count(&object), 1);
    }
}
