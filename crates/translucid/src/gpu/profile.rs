//! The device profile: which of the variants that suit a CPU driver or a GPU a device gets.
//! CPU drivers such as lavapipe run a subgroup as masked SIMD, where an `if` runs both its
//! sides and only loop exits save work; GPUs branch for free where a subgroup agrees. Chosen
//! from the device, and forced by `TRANSLUCID_PROFILE=cpu|gpu` (or an option), so that every
//! GPU variant runs, and is tested, on lavapipe too.

use super::vk;
use crate::{Error, Result};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// A CPU driver (lavapipe, SwiftShader): masked, branch-free variants.
    CpuDriver,
    /// A GPU: branching variants.
    Gpu,
}

impl Profile {
    /// The profile a device of `device_type` and `driver` gets unless forced.
    pub fn of_device(device_type: vk::PhysicalDeviceType, driver: vk::DriverId) -> Self {
        if device_type == vk::PhysicalDeviceType::CPU || driver == vk::DriverId::MESA_LLVMPIPE {
            Self::CpuDriver
        } else {
            Self::Gpu
        }
    }

    /// `cpu` or `gpu`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "cpu" => Ok(Self::CpuDriver),
            "gpu" => Ok(Self::Gpu),
            other => Err(Error::InvalidOption(format!(
                "profile {other:?}: it is cpu or gpu"
            ))),
        }
    }

    /// The profile `TRANSLUCID_PROFILE` forces, if it is set (and not empty).
    pub fn from_env() -> Result<Option<Self>> {
        match std::env::var("TRANSLUCID_PROFILE") {
            Ok(name) if !name.is_empty() => Self::parse(&name)
                .map(Some)
                .map_err(|e| Error::InvalidOption(format!("TRANSLUCID_PROFILE: {e}"))),
            _ => Ok(None),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::CpuDriver => "cpu",
            Self::Gpu => "gpu",
        }
    }
}

/// Whether the environment variable `var`, an A/B switch of docs/gpu.md, is set to `forced`
/// rather than to `device` (the device's choice, also when unset or empty); anything else is
/// an error naming both.
pub fn forced_by_env(var: &str, forced: &str, device: &str) -> Result<bool> {
    match std::env::var(var) {
        Ok(value) if value == forced => Ok(true),
        Ok(value) if value == device || value.is_empty() => Ok(false),
        Err(_) => Ok(false),
        Ok(other) => Err(Error::InvalidOption(format!(
            "{var}: {other:?} is neither {forced:?} nor {device:?}"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_follow_the_device_and_parse_by_name() {
        let cpu = Profile::of_device(vk::PhysicalDeviceType::CPU, vk::DriverId::MESA_LLVMPIPE);
        assert_eq!(cpu, Profile::CpuDriver);
        let gpu = Profile::of_device(
            vk::PhysicalDeviceType::DISCRETE_GPU,
            vk::DriverId::NVIDIA_PROPRIETARY,
        );
        assert_eq!(gpu, Profile::Gpu);
        for p in [Profile::CpuDriver, Profile::Gpu] {
            assert_eq!(Profile::parse(p.name()).expect("own name"), p);
        }
        assert!(Profile::parse("GPU").is_err());
    }
}
