//! GPU timestamps around every stage of a frame.

use super::error::vk_err;
use super::Gpu;
use crate::Result;
use ash::vk;

/// A query pool written at stage boundaries: `mark("opaque")` after the opaque pass makes a
/// stage "opaque" lasting from the previous mark.
pub struct Timestamps {
    gpu: Gpu,
    pool: vk::QueryPool,
    capacity: u32,
    names: Vec<&'static str>,
}

impl Timestamps {
    pub fn new(gpu: &Gpu, capacity: u32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(capacity);
        // SAFETY: valid device and create info.
        let pool = unsafe { gpu.device.create_query_pool(&info, gpu.callbacks()) }
            .map_err(vk_err("vkCreateQueryPool"))?;
        Ok(Self {
            gpu: gpu.clone(),
            pool,
            capacity,
            names: Vec::new(),
        })
    }

    /// Resets the pool and writes the starting timestamp.
    pub fn begin(&mut self, cmd: vk::CommandBuffer) {
        self.names.clear();
        // SAFETY: cmd is recording, outside a render pass; the range is within the pool.
        unsafe {
            self.gpu
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, self.capacity)
        };
        self.write(cmd, "");
    }

    /// Ends the stage called `name`.
    pub fn mark(&mut self, cmd: vk::CommandBuffer, name: &'static str) {
        self.write(cmd, name);
    }

    fn write(&mut self, cmd: vk::CommandBuffer, name: &'static str) {
        let index = self.names.len() as u32;
        if index >= self.capacity {
            log::warn!("timestamp pool full; stage {name} not timed");
            return;
        }
        // SAFETY: cmd is recording; the query was reset in begin().
        unsafe {
            self.gpu.device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::ALL_COMMANDS,
                self.pool,
                index,
            )
        };
        self.names.push(name);
    }

    /// Stage names with durations in milliseconds, after the submission completed.
    pub fn read(&self) -> Result<Vec<(&'static str, f64)>> {
        self.results(vk::QueryResultFlags::WAIT)
            .map(|stages| stages.unwrap_or_default())
    }

    /// Like [`Timestamps::read`] without waiting: `None` when some timestamp has not been
    /// written, i.e. the commands have not run (yet). For work someone else submitted.
    pub fn try_read(&self) -> Result<Option<Vec<(&'static str, f64)>>> {
        self.results(vk::QueryResultFlags::empty())
    }

    fn results(&self, wait: vk::QueryResultFlags) -> Result<Option<Vec<(&'static str, f64)>>> {
        let n = self.names.len();
        if n < 2 {
            return Ok(Some(Vec::new()));
        }
        let mut ticks = vec![0u64; n];
        // SAFETY: the queries 0..n were reset and written by recorded commands; without WAIT,
        // unavailable ones give NOT_READY.
        let read = unsafe {
            self.gpu.device.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | wait,
            )
        };
        match read {
            Err(vk::Result::NOT_READY) => return Ok(None),
            other => other.map_err(vk_err("vkGetQueryPoolResults"))?,
        }
        let ms_per_tick = self.gpu.info().timestamp_period_ns as f64 * 1e-6;
        Ok(Some(
            (1..n)
                .map(|i| {
                    (
                        self.names[i],
                        ticks[i].saturating_sub(ticks[i - 1]) as f64 * ms_per_tick,
                    )
                })
                .collect(),
        ))
    }
}

impl Drop for Timestamps {
    fn drop(&mut self) {
        // SAFETY: no pending submission uses the pool once its owner is dropped.
        unsafe {
            self.gpu
                .device
                .destroy_query_pool(self.pool, self.gpu.callbacks())
        };
    }
}
