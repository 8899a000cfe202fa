//! Structure types: the `s_type` every extensible struct starts with, so that a zeroed, garbage
//! or wrong struct is caught instead of misread, and so that later versions can chain new
//! structures through `next` without changing any existing layout.

/// Values of the `s_type` field. 0 is never valid, so a zeroed struct is always rejected.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_structure_type {
    ContextCreateInfo = 1,
    MeshCreateInfo = 2,
    TextureCreateInfo = 3,
    MaterialCreateInfo = 4,
    FrameInfo = 5,
    OpaqueLayer = 6,
    FrameStatistics = 7,
    /// `translucid_sampler_info`, chained to the texture create-info.
    SamplerInfo = 8,
    /// `translucid_host_device_create_info`, chained to the context create-info.
    HostDeviceCreateInfo = 100,
    /// `translucid_host_requirements`.
    HostDeviceRequirements = 101,
    /// `translucid_host_frame_targets`.
    HostFrameTargets = 102,
}

impl translucid_structure_type {
    const ALL: [Self; 11] = [
        Self::ContextCreateInfo,
        Self::MeshCreateInfo,
        Self::TextureCreateInfo,
        Self::MaterialCreateInfo,
        Self::FrameInfo,
        Self::OpaqueLayer,
        Self::FrameStatistics,
        Self::SamplerInfo,
        Self::HostDeviceCreateInfo,
        Self::HostDeviceRequirements,
        Self::HostFrameTargets,
    ];

    pub fn from_raw(value: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|t| *t as u32 == value)
    }
}
