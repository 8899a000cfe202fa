//! Preparation on worker threads: a declaration's pipelines built beside the frame loop. Each
//! job makes, on its own thread, the renderer a frame would be made with under the new
//! declaration, holds every pipeline it built (they are shared on the device by what they
//! were made from), and drops the renderer. Until a job is taken in (by the context's status
//! query only), frames draw with the declaration before it; once taken in, its content is
//! declared, and the renderers made from then on find their pipelines built.

use crate::gpu::{HeldPipelines, HostImage};
use crate::methods::bins::features::DeclaredContent;
use crate::{Error, Result};
use std::thread::JoinHandle;

use super::renderers::{RendererInputs, SettingsKey};

/// What a job declares once taken in: the engine's content for every renderer, and what
/// its frame drew for the renderers of its settings.
pub struct Declaration {
    pub content: DeclaredContent,
    pub drawn: (SettingsKey, DeclaredContent),
}

/// Where the jobs stand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrepareStatus {
    /// Some job is still building.
    Building,
    /// Every job has been taken in; the pipelines built by those taken in since the last
    /// status.
    Ready { pipelines: u64 },
}

struct Job {
    declaration: Declaration,
    worker: JoinHandle<Result<(HeldPipelines, u64)>>,
}

/// A context's background preparation.
#[derive(Default)]
pub struct Background {
    jobs: Vec<Job>,
    /// The pipelines finished jobs built, held for the renderers made later.
    held: Vec<HeldPipelines>,
    /// Pipelines built by the jobs taken in since the last status.
    built: u64,
    /// The first error of a job taken in since the last status.
    failed: Option<Error>,
}

impl Background {
    /// Starts building, on a new thread, the renderer `inputs` describe (with what its
    /// first frame into `engine_images` builds); `declaration` is declared once it is taken
    /// in.
    pub fn start(
        &mut self,
        inputs: RendererInputs,
        engine_images: Option<(HostImage, HostImage)>,
        declaration: Declaration,
    ) -> Result<()> {
        let worker = std::thread::Builder::new()
            .name("translucid prepare".into())
            .spawn(move || {
                let (built, pipelines) = crate::gpu::in_background(|| {
                    let renderer = inputs.build(engine_images)?;
                    // Held before the renderer goes: pipelines live while someone holds them.
                    let held = inputs.gpu().hold_pipelines();
                    drop(renderer);
                    Ok(held)
                });
                built.map(|held| (held, pipelines))
            })
            .map_err(|e| Error::Internal(format!("no thread to prepare on: {e}")))?;
        self.jobs.push(Job {
            declaration,
            worker,
        });
        Ok(())
    }

    /// Takes in the jobs that finished, oldest first: the declaration of each that
    /// succeeded, to declare.
    pub fn take_finished(&mut self) -> Vec<Declaration> {
        let mut declared = Vec::new();
        let (finished, running): (Vec<Job>, Vec<Job>) = std::mem::take(&mut self.jobs)
            .into_iter()
            .partition(|job| job.worker.is_finished());
        self.jobs = running;
        for job in finished {
            match job.worker.join() {
                Ok(Ok((held, pipelines))) => {
                    self.held.push(held);
                    self.built += pipelines;
                    declared.push(job.declaration);
                }
                Ok(Err(e)) => {
                    self.failed.get_or_insert(e);
                }
                Err(_) => {
                    self.failed.get_or_insert(Error::Internal(
                        "the thread preparing in the background panicked".into(),
                    ));
                }
            }
        }
        declared
    }

    /// Where the jobs stand (after [`Self::take_finished`]); a job's error once.
    pub fn status(&mut self) -> Result<PrepareStatus> {
        if let Some(e) = self.failed.take() {
            return Err(e);
        }
        if !self.jobs.is_empty() {
            return Ok(PrepareStatus::Building);
        }
        Ok(PrepareStatus::Ready {
            pipelines: std::mem::take(&mut self.built),
        })
    }

    /// Waits for every job: nothing they use may go while they run.
    pub fn wait(&mut self) {
        for job in self.jobs.drain(..) {
            let _ = job.worker.join();
        }
    }
}

impl Drop for Background {
    fn drop(&mut self) {
        self.wait();
    }
}
